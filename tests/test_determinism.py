"""Same seed, same run: the tick log is byte-identical (wall-clock figures live elsewhere)."""

from __future__ import annotations

import io
import re
import subprocess
import sys
from pathlib import Path

from behaviors.base import NavNode
from executive.cli import main
from executive.mission import build_mission, run_mission
from executive.recorder import Recorder
from executive.scenario import load_scenario, scenario_config
from executive.tree_loader import load_tree_text, shipped_tree
from executive.world import World

SCENARIOS = Path(__file__).resolve().parent / "scenarios"


def _ticks(name: str, tree: str) -> tuple[str, str]:
    sc = load_scenario(SCENARIOS / f"{name}.yaml")
    config = scenario_config(sc, None)
    stream, timing = io.StringIO(), io.StringIO()
    mission = build_mission(shipped_tree(tree), config, sc.grid, sc.start,
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


# --------------------------------------------------------------------------------------------
# Run folders: records depend on the scenario, tree, config and seed only, not on the process
# that ran them (its earlier missions, a worker of a pool) nor on the wall clock.
ROOT = Path(__file__).resolve().parent.parent
RECORDS = ("ticks.jsonl", "summary.json")
UUID4 = re.compile(r"[0-9a-f]{8}-[0-9a-f]{4}-4[0-9a-f]{3}-[89ab][0-9a-f]{3}-[0-9a-f]{12}")
# recoveries, private keys of unwired outputs (IsGoalInNarrowSpace's free_width, error_msg)
COMPARED = ("dead_end_backoff", "corridor_blocked")
BEFORE = ("goal_walled_in", "goal_in_obstacle")   # short missions of the same tree run first


def _cli(*argv: str) -> None:
    """``mission`` in a new process (1: a scenario missed its expectation; the files count)."""
    done = subprocess.run([sys.executable, "-m", "executive.cli", *argv], cwd=ROOT,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode in (0, 1), done.stderr


def _records(record: Path) -> dict[str, bytes]:
    out = {}
    for name in COMPARED:
        for f in RECORDS:
            out[f"{name}/{f}"] = (record / f"{name}__smach_recovery__seed0" / f).read_bytes()
    return out


def test_a_run_folder_is_the_same_in_a_fresh_process_after_other_missions_and_in_a_pool(
        tmp_path, capsys) -> None:
    files = [str(SCENARIOS / f"{n}.yaml") for n in COMPARED]
    before = [str(SCENARIOS / f"{n}.yaml") for n in BEFORE]
    for f in files:   # each scenario alone in a fresh process
        _cli("scenario", "run", f, "--record", str(tmp_path / "fresh"))
    # in this process, after missions of the same tree (the mission counter moved on)
    main(["scenario", "run", *before, "--record", str(tmp_path / "first")])
    main(["scenario", "run", *files, "--record", str(tmp_path / "here")])
    capsys.readouterr()
    # in a pool of two: the third and fourth task go to a worker that already ran one
    _cli("scenario", "run", *before, *files, "--jobs", "2", "--record", str(tmp_path / "pool"))
    fresh = _records(tmp_path / "fresh")
    for other in ("here", "pool"):
        got = _records(tmp_path / other)
        for name in fresh:   # byte for byte
            assert got[name] == fresh[name], f"{other}/{name} differs from the fresh run's"
    ticks = fresh["dead_end_backoff/ticks.jsonl"].decode()
    assert "IsGoalInNarrowSpace_" in ticks and '"recovery":' in ticks   # private keys recorded
    for text in map(bytes.decode, fresh.values()):
        # no uuid4 (differs every run), no /mission_N (this process's history), no wall clock
        assert not UUID4.search(text) and "/mission_" not in text and "overrun" not in text


def test_private_keys_are_named_by_place_in_the_tree_and_kept_apart_by_the_namespace() -> None:
    text = """
        main_tree: T
        trees:
          T:
            Sequence:
              children:
                - IsGoalInNarrowSpace: {name: narrow}
                - IsGoalInNarrowSpace: {name: narrow}
                - NavigateToPose: {name: go}
                - NavigateToPose: {name: go}
        """

    def private(tree) -> list[str]:
        keys = []
        for node in tree.nodes():
            if isinstance(node, NavNode):
                base = node._scoped_node_name() + "/"
                keys += [k for k in node._keys.values() if k.startswith(base)]
        return keys

    a, b = load_tree_text(text, namespace="/det_a"), load_tree_text(text, namespace="/det_b")
    ka, kb = private(a), private(b)
    # both narrow nodes' free_width and the go nodes' inner nodes' private inputs
    assert sum(k.endswith("/free_width") for k in ka) == 2 and len(ka) > 2
    assert len(set(ka)) == len(ka)                       # unique within the tree
    assert not any(UUID4.search(k) for k in ka)
    assert [k.removeprefix("/det_a/") for k in ka] == [k.removeprefix("/det_b/") for k in kb]
    assert all(k.startswith("/det_a/") for k in ka) and not set(ka) & set(kb)
    again = load_tree_text(text, namespace="/det_a")          # the same tree built again: same keys
    assert private(again) == ka
