"""Same seed, same run: the tick log is byte-identical (wall-clock figures live elsewhere)."""

from __future__ import annotations

import io
import subprocess
import sys
from pathlib import Path

from executive.mission import build_mission, run_mission
from executive.recorder import Recorder
from executive.scenario import load_scenario, scenario_config
from executive.tree_loader import shipped_tree
from executive.world import World

SCENARIOS = Path(__file__).resolve().parent / "scenarios"


def _ticks(name: str, tree: str) -> tuple[str, str]:
    sc = load_scenario(SCENARIOS / f"{name}.yaml")
    config = scenario_config(sc, None)
    stream, timing = io.StringIO(), io.StringIO()
    mission = build_mission(str(shipped_tree(tree)), config, sc.grid, sc.start,
                            world=World(sc.objects, sc.moving, sc.phantoms, sc.faults),
                            seed=sc.seed, recorder=Recorder(stream, timing=timing),
                            meta={"scenario": sc.name})
    run_mission(mission, sc.goals, min(sc.time_limit, 20.0))
    mission.executive.shutdown()
    return stream.getvalue(), timing.getvalue()


def _run_in_new_process() -> str:
    code = ("import sys; sys.path.insert(0, 'tests'); from test_determinism import _ticks; "
            "sys.stdout.write(_ticks('laser_dropout', 'move_base')[0])")
    root = Path(__file__).resolve().parent.parent
    return subprocess.run([sys.executable, "-c", code], cwd=root, check=True,
                          capture_output=True, text=True, timeout=300).stdout


def test_two_runs_with_the_same_seed_write_identical_tick_logs() -> None:
    a, b = _run_in_new_process(), _run_in_new_process()
    assert a.count("\n") > 100 and '"fault":"stale_laser"' in a  # the drop-out was seen
    assert a == b
    assert "overrun_ms" not in a
