"""``mission warmup`` and the first-run notice: a cold numba cache is detected, announced on a
terminal only, and filled by the warmup so that the next run finds it warm."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

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


_COVERAGE = """
import sys
from numba.core.registry import CPUDispatcher
from executive.api import shipped_tree
from executive.commands.warmup_cmd import warm_navigation
from executive.scenario import load_scenario, run_scenario

def signatures():
    out = {}
    for name, mod in list(sys.modules.items()):
        if name.startswith(("navcore.", "hw.", "behaviors.", "executive.")):
            for attr, obj in list(vars(mod).items()):
                if isinstance(obj, CPUDispatcher) and obj.signatures:
                    out[f"{name}.{attr}"] = sorted(map(str, obj.signatures))
    return out

demo = sys.argv[1]
warm_navigation(demo)
before = signatures()
r = run_scenario(load_scenario(demo), shipped_tree("smach_recovery"))
after = signatures()
print(r.outcome)
print(sorted(before))
print(sorted(k for k in before if after[k] != before[k]))
"""


def test_navigation_warmup_compiles_the_planner_kernels_the_demo_calls() -> None:
    """The demo's second process (``warm_navigation``) must compile the local and global
    planners' kernels with exactly the argument types the demo calls them with; any other
    variant would be compiled by both processes on a cold cache."""
    if os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"):
        pytest.skip("compiled signatures exist only with numba's JIT on")
    demo = str(ROOT / "executive" / "data" / "demo.yaml")
    out = subprocess.run([sys.executable, "-c", _COVERAGE, demo], cwd=ROOT, capture_output=True,
                         text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    outcome, warmed, changed = out.stdout.strip().splitlines()[-3:]
    assert outcome == "succeeded"
    for kernel in ("navcore.controllers.critics.score_dwa", "navcore.controllers.rollout.simulate",
                   "navcore.controllers.map_grid.distance_grid",
                   "navcore.planners.traceback.gradient_path",
                   "navcore.planners.wavefront.refresh_records"):
        assert f"'{kernel}'" in warmed
    assert changed == "[]"  # the demo called no other variant of a kernel the warm-up compiled


def test_navigation_part_of_the_warmup(capsys) -> None:
    from executive.cli import main

    assert main(["warmup", "--part", "navigation"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("kernels ") and out.rstrip().endswith(" s)")


def test_a_failed_run_stops_the_second_process_a_good_one_lets_it_finish() -> None:
    from executive.commands.warmup_cmd import end_navigation_warmup

    slow = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    end_navigation_warmup(slow, keep=False)
    assert slow.returncode is not None and slow.returncode != 0  # killed, not waited out
    quick = subprocess.Popen([sys.executable, "-c", "import sys; sys.exit(3)"])
    end_navigation_warmup(quick, keep=True)
    assert quick.returncode == 3  # ran to its end
    end_navigation_warmup(None, keep=True)  # no second process (warm cache): nothing to do
