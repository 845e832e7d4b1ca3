"""The stuck-robot scenario catalogue (tests/scenarios/*.yaml), run against its expectations.

Every scenario runs with the SMACH-style tree (trees/smach_recovery.yaml), multi-seed ones over
all their seeds and judged by their k-of-n rule. A scenario states what a good tree must do; where
a tree misses it today the file carries a ``known_issue`` for that tree with the measured reason,
and the test reports it as xfail with that reason. The other shipped trees run a cheap subset
here; the full table of every tree against the whole catalogue is bench/bench_scenarios.py.
"""

from __future__ import annotations

import functools
from pathlib import Path

import pytest

from executive.scenario import (Expectation, ScenarioError, load_scenario, scenario_files,
                                scenario_from_mapping)
from executive.scenarios import run_tasks, tasks_for, verdicts

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CATALOGUE = sorted(scenario_files([str(HERE / "scenarios")]))
SMACH = str(ROOT / "trees" / "smach_recovery.yaml")
MOVE_BASE = str(ROOT / "trees" / "move_base.yaml")
TREES = {t: str(ROOT / "trees" / f"{t}.yaml")
         for t in ("smach_recovery", "nav2", "move_base", "near_goal_reconfigure")}


def test_catalogue_is_complete_and_valid():
    scenarios = [load_scenario(p, check_config=True) for p in CATALOGUE]
    assert len(scenarios) >= 40
    names = [s.name for s in scenarios]
    assert len(set(names)) == len(names)
    for s in scenarios:
        assert s.description, s.source
        assert (s.goals or s.generate) and s.time_limit <= 200
        if s.map_source == "inline":      # small drawn maps keep the catalogue fast
            assert s.grid.width * s.grid.height <= 100 * 60, s.name
        for tree in s.known_issues:
            assert tree in TREES, f"{s.name}: known_issue for unknown tree {tree}"
    assert sum(1 for s in scenarios if s.seeds and len(s.seeds) > 1) >= 4
    assert sum(1 for s in scenarios if s.map_source not in ("inline",)
               and "shared" in s.map_source or s.skip) >= 3
    assert sum(1 for s in scenarios if s.events) >= 8


@functools.lru_cache(maxsize=None)
def _verdict(path: str, tree: str):
    """All seeds of a scenario against a tree (shared by the tests below: each run costs)."""
    s = load_scenario(path)
    results = run_tasks(tasks_for([(path, s)], [tree]))
    (v,) = verdicts(results, {s.name: s.needed()})
    return s, v


def _judge(path: str, tree_stem: str) -> None:
    s, v = _verdict(path, TREES[tree_stem])
    if v.skipped:
        pytest.skip(f"{s.name}: {v.runs[0].detail}")
    errors = [r.detail for r in v.runs if r.outcome == "error"]
    assert not errors, errors
    for r in v.runs:
        assert r.sim_time <= s.time_limit + 0.2
    known = s.known_issue_for(tree_stem)
    misses = [(r.seed, r.outcome, r.reason, r.failures) for r in v.runs if not r.passed]
    if not v.passed and known:
        pytest.xfail(f"{s.name} / {tree_stem}: {known} ({misses})")
    assert v.passed, f"{s.name}: {v.met}/{len(v.runs)} seeds met it (need {v.needed}): {misses}"
    for r in v.runs:
        if r.outcome == "succeeded" and r.passed:
            assert r.solved and r.collisions == 0


@pytest.mark.parametrize("path", CATALOGUE, ids=[Path(p).stem for p in CATALOGUE])
def test_scenario_meets_expectation(path):
    _judge(path, "smach_recovery")


# the other shipped trees on a cheap subset (short runs covering events, faults, a blocked
# route and a stale obstacle); bench/bench_scenarios.py runs them on everything
SUBSET = ["goal_replaced_mid_route", "laser_dropout_stops_robot", "corridor_blocked",
          "phantom_obstacle", "speed_limit_zone"]


@pytest.mark.parametrize("tree", ["nav2", "move_base", "near_goal_reconfigure"])
@pytest.mark.parametrize("name", SUBSET)
def test_other_trees_on_a_subset(name, tree):
    _judge(str(HERE / "scenarios" / f"{name}.yaml"), tree)


# stuck-robot situations where move_base gives up or runs out of time and the SMACH-style
# recoveries get the robot unstuck
BEYOND_MOVE_BASE = ["dead_end_backoff", "rotate_blocked_near_wall"]


@pytest.mark.parametrize("name", BEYOND_MOVE_BASE)
def test_recovery_tree_solves_more_than_move_base(name):
    path = str(HERE / "scenarios" / f"{name}.yaml")
    _, mb = _verdict(path, MOVE_BASE)
    _, sm = _verdict(path, SMACH)
    (m,), (r,) = mb.runs, sm.runs
    assert not m.solved and m.collisions == 0, f"{name}: move_base {m.outcome}"
    assert m.known_issue, f"{name}: move_base misses it: its known_issue must say why"
    assert r.solved and r.collisions == 0, f"{name}: smach_recovery {r.outcome} ({r.reason})"


def test_same_seed_same_run():
    from executive.scenario import run_scenario
    s = load_scenario(HERE / "scenarios" / "goal_minus_x.yaml")
    a = run_scenario(s, SMACH)
    b = run_scenario(s, SMACH)
    assert (a.outcome, a.sim_time, a.recoveries, a.final_pose) == \
        (b.outcome, b.sim_time, b.recoveries, b.final_pose)


# ------------------------------------------------------------------ format and checks (fast)
ASCII = "#######\n#S...G#\n#######\n"


def test_ascii_markers_objects_and_phantoms():
    s = scenario_from_mapping({"map": {"resolution": 0.5, "ascii":
                                       "#########\n#S.oo.PG#\n#########\n"}}, "x.yaml")
    assert (s.start.x, s.start.y) == (0.75, 0.75)
    assert (s.goals[0].x, s.goals[0].y) == (3.75, 0.75)
    assert [o.values for o in s.objects] == [(1.5, 0.5, 2.5, 1.0)]
    assert [(p.values, w) for p, w in s.phantoms] == [((3.0, 0.5, 3.5, 1.0), "both")]
    assert s.grid.data[0, 0] == 100 and s.grid.data[1, 1] == 0


@pytest.mark.parametrize("doc,message", [
    ({"map": {"resolution": 0.1, "ascii": "#x#\n"}}, r"line 1 column 2: unknown character 'x'"),
    ({"map": {"resolution": 0.1, "ascii": ASCII}, "objects": [{"box": [1, 2, 3]}]},
     r"objects\[0\]\.box: box needs 4 numbers"),
    ({"map": {"resolution": 0.1, "ascii": ASCII}, "faults": [{"kind": "laser_dropuot",
                                                              "start": 1}]},
     r"unknown kind 'laser_dropuot' \(did you mean 'laser_dropout'\?\)"),
    ({"map": {"resolution": 0.1, "ascii": ASCII}, "start": [50, 0, 0]}, r"start: \(50, 0\) is outside"),
    ({"map": {"resolution": 0.1, "ascii": ASCII}, "time_limt": 5},
     r"unknown key 'time_limt' \(did you mean 'time_limit'\?\)"),
    ({"map": {"resolution": 0.1, "ascii": ASCII}, "expect": {"outcome": "won"}},
     r"outcome must be one of"),
    ({"map": {"file": "nope.yaml"}}, r"map\.file: .*nope.yaml"),
    ({"map": {}}, r"map: give one of"),
    ({"map": {"resolution": 0.1, "ascii": ASCII},
      "moving": [{"radius": 0.2, "waypoints": [[1, 1]], "sped": 1}]},
     r"moving\[0\]\.sped: unknown key 'sped' \(did you mean 'speed'\?\)"),
])
def test_format_errors_name_file_and_field(doc, message):
    with pytest.raises(ScenarioError, match=r"^x\.yaml: .*" + message):
        scenario_from_mapping(doc, "x.yaml")


def test_check_expectation():
    import numpy as np

    from executive.scenarios import RunRecord, check
    from navcore.types import Pose2D
    e = Expectation(outcome=("succeeded",), recoveries_fired=["Spin"],
                    recoveries_not_fired=["BackUp"], no_collision=True, max_time=10.0)

    def rec(outcome, t, fired, contacts):
        return RunRecord(outcome, "", t, 1, 1, Pose2D(), Pose2D(), contacts,
                         [{"name": f, "type": f, "t": 1.0, "end": 2.0} for f in fired])
    assert check(e, rec("succeeded", 9.0, ["Spin"], 0)) == []
    f = check(e, rec("failed", 12.0, ["BackUp"], 2))
    assert f == ["outcome: expected succeeded, got failed", "recovery Spin must fire but did not",
                 "recovery BackUp fired but must not", "2 collision(s)",
                 "took 12.0 s, more than max_time 10 s"]


def test_scenario_config_overrides_and_errors():
    from executive.scenario import scenario_config
    s = scenario_from_mapping({"map": {"resolution": 0.1, "ascii": ASCII},
                               "params": {"move_base": {"controller_frequency": 5.0}}},
                              "x.yaml")
    assert scenario_config(s).move_base.controller_frequency == 5.0
    s.params = {"move_base": {"controller_frequenzy": 5.0}}
    from executive.config import ConfigError
    # the scenario's own value is reported at the scenario, not at the base file
    with pytest.raises(ConfigError, match=r"^x\.yaml: move_base: unknown parameter "
                                          r"'controller_frequenzy'"):
        scenario_config(s)


def test_moving_obstacle_timing():
    from executive.scenario import MovingObstacle
    m = MovingObstacle(0.25, [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0)], 1.0, start_time=10.0)
    assert m.position(5.0) == (0.0, 0.0)
    assert m.position(11.0) == pytest.approx((1.0, 0.0))
    assert m.position(13.0) == pytest.approx((2.0, 1.0))
    assert m.position(100.0) == (2.0, 2.0)


def test_scenario_over_an_unreadable_or_broken_base_config_names_the_file(tmp_path):
    from executive.config import ConfigError
    from executive.scenario import scenario_config
    s = load_scenario(HERE / "scenarios" / "unknown_box.yaml")
    with pytest.raises(ConfigError, match="missing.yaml: cannot read robot config"):
        scenario_config(s, str(tmp_path / "missing.yaml"))
    bad = tmp_path / "bad.yaml"
    bad.write_text("robot:\n  footprint: [[0, 0]\n")
    with pytest.raises(ConfigError, match=r"bad.yaml:\d+: not valid YAML"):
        scenario_config(s, str(bad))
