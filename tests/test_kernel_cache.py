"""Cached kernels and changed callees: numba checks a cached kernel against its own source file
only, so a caller whose callee (another file) changed would run the callee's old code;
navcore.kernel_cache drops the cache when any kernel source changed."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from navcore.kernel_cache import cache_dirs, refresh, source_dirs, sources_stamp

ROOT = Path(__file__).resolve().parents[1]

CALLER = """from numba import njit
from kpkg.callee import f


@njit(cache=True)
def g():
    return f() + 10
"""

# import the two-module package from argv[1]; refresh its cache first when argv[2] is "1"
SCRIPT = """import os, sys
base, do_refresh = sys.argv[1], sys.argv[2] == "1"
sys.path.insert(0, base)
from navcore.kernel_cache import refresh
if do_refresh:
    refresh([os.path.join(base, "kpkg")], os.environ.get("NUMBA_CACHE_DIR") or None,
            os.path.join(base, "stamp"))
from kpkg.caller import g
print(g(), sum(g.stats.cache_hits.values()))
"""


def _callee(pkg: Path, value: int, mtime: float) -> None:
    path = pkg / "callee.py"
    path.write_text(f"from numba import njit\n\n\n@njit(cache=True)\ndef f():\n    return {value}\n")
    os.utime(path, (mtime, mtime))


def _package(base: Path) -> Path:
    pkg = base / "kpkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "caller.py").write_text(CALLER)
    _callee(pkg, 1, 1_700_000_000)
    return pkg


def _run(base: Path, do_refresh: bool, cache: str | None = None) -> tuple[int, int]:
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_DISABLE_JIT", "NUMBA_CACHE_DIR")}
    if cache:
        env["NUMBA_CACHE_DIR"] = cache
    out = subprocess.run([sys.executable, "-c", SCRIPT, str(base), "1" if do_refresh else "0"],
                         cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    value, hits = out.stdout.split()
    return int(value), int(hits)  # hits: calls served from the cache


def test_a_caller_sees_its_changed_callee_after_a_refresh(tmp_path):
    pkg = _package(tmp_path)
    assert _run(tmp_path, True) == (11, 0)          # compiled, cached
    assert _run(tmp_path, True) == (11, 1)          # loaded from the cache: nothing changed
    _callee(pkg, 2, 1_700_000_100)                  # the callee's file changes, the caller's not
    assert _run(tmp_path, True) == (12, 0)          # the cache was dropped: compiled afresh
    assert _run(tmp_path, True) == (12, 1)


def test_with_numba_cache_dir_the_files_are_where_refresh_looks(tmp_path):
    pkg = _package(tmp_path)
    cache = str(tmp_path / "cache")
    assert _run(tmp_path, True, cache) == (11, 0)
    (where,) = cache_dirs([str(pkg)], cache)
    assert any(n.endswith(".nbi") for n in os.listdir(where))
    _callee(pkg, 3, 1_700_000_200)
    assert _run(tmp_path, True, cache) == (13, 0)


def test_refresh_removes_only_numba_files_and_only_when_the_sources_changed(tmp_path):
    pkg = _package(tmp_path)
    pyc = pkg / "__pycache__"
    pyc.mkdir()
    for name in ("caller.g-5.py311.nbi", "caller.g-5.py311.1.nbc", "caller.cpython-311.pyc"):
        (pyc / name).write_bytes(b"x")
    stamp = str(tmp_path / "stamp")
    assert refresh([str(pkg)], None, stamp) is True
    assert sorted(os.listdir(pyc)) == ["caller.cpython-311.pyc"]
    (pyc / "caller.g-5.py311.nbi").write_bytes(b"x")
    assert refresh([str(pkg)], None, stamp) is False      # same sources: the cache stays
    assert (pyc / "caller.g-5.py311.nbi").exists()
    before = sources_stamp([str(pkg)])
    _callee(pkg, 4, 1_700_000_300)
    assert sources_stamp([str(pkg)]) != before
    assert refresh([str(pkg)], None, stamp) is True
    assert not (pyc / "caller.g-5.py311.nbi").exists()


def test_navbt_kernel_sources_are_every_folder_of_navcore_and_hw():
    dirs = {os.path.relpath(d, ROOT) for d in source_dirs(str(ROOT))}
    assert {"navcore", "navcore/costmap", "navcore/planners", "navcore/controllers", "hw",
            "hw/sim", "hw/drivers"} <= dirs
    assert not any("__pycache__" in d for d in dirs)
