"""``mission warmup`` and the first-run notice: a cold numba cache is detected, announced on a
terminal only, and filled by the warmup so that the next run finds it warm."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

_SCRIPT = """
import io, sys
from executive.commands.warmup_cmd import announce_compiling, kernels_cold

class Tty(io.StringIO):
    def isatty(self):
        return True

tty = Tty()
said = announce_compiling(tty)
print(said, repr(tty.getvalue()), kernels_cold())
"""


def _probe(cache: Path) -> str:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    env.pop("NUMBA_DISABLE_JIT", None)
    out = subprocess.run([sys.executable, "-c", _SCRIPT], cwd=ROOT, env=env, capture_output=True,
                         text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.strip()


def test_cold_cache_is_announced_once_on_a_terminal(tmp_path: Path) -> None:
    first = _probe(tmp_path)
    assert first.startswith("True 'compiling kernels (first run only")
    assert first.endswith("False")  # the probe is cached now
    assert _probe(tmp_path) == "False '' False"


def test_no_notice_when_the_output_is_not_a_terminal() -> None:
    from executive.commands.warmup_cmd import announce_compiling

    stream = io.StringIO()
    assert announce_compiling(stream) is False
    assert stream.getvalue() == ""


def test_warmup_runs_the_demo_scenario_and_reports(capsys) -> None:
    from executive.cli import main

    assert main(["warmup"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("kernels ") and " compiled (" in out and out.rstrip().endswith(" s)")
