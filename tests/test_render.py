"""Tree pictures: a shape per node kind, subtrees, ports, and a run's per-node statistics."""

from __future__ import annotations

import io
import json
import re

import py_trees
from py_trees.common import Status

from navcore.clock import SimClock
from navcore.types import Pose2D
from executive.executive import Executive
from executive.recorder import Recorder, walk
from executive.render import (KIND_STYLE, NodeStats, render_tree, stats_from_footer,
                              subtree_name, tree_dot)
from executive.tree_loader import load_tree_file, shipped_tree
from tests.test_executive import wall_ahead_robot


def _node_lines(dot: str) -> dict[int, str]:
    return {int(m.group(1)): m.group(0) for m in re.finditer(r"^\s*n(\d+) \[.*$", dot, re.M)}


def test_groot_like_picture_of_a_shipped_tree():
    root = load_tree_file(shipped_tree("smach_recovery"), namespace="/t").root
    nodes = [n for n, _ in walk(root)]
    dot = tree_dot(root, title="SmachRecovery")
    lines = _node_lines(dot)
    assert len(lines) == len(nodes)
    for i, n in enumerate(nodes):
        t = type(n).__name__
        expect = {"RecoveryNode": "control", "RateController": "decorator",
                  "IsGoalNearby": "condition", "FollowPath": "action"}.get(t)
        if expect:
            st = KIND_STYLE[expect]
            assert f"shape={st.shape} " in lines[i] and st.fill in lines[i], (t, lines[i])
        assert "<b>" in lines[i] and t in lines[i]
        if n.name != t:  # a custom name keeps the type visible
            assert n.name in lines[i]
    # every SubTree instance is a framed cluster with its name
    subtrees = ("FreeTheStart", "NavigateWithEscalation", "NavigateByGoalSpace",
                "LineUpAndEnter", "Navigate", "Escalation")
    assert dot.count("subgraph cluster_") == len(subtrees)
    for name in subtrees:
        assert f"<b>SubTree</b> {name}<" in dot, name
    assert "SmachRecovery" in dot and ">condition<" in dot  # title and legend
    assert len(re.findall(r"^\s*n\d+ -> n\d+;", dot, re.M)) == len(nodes) - 1
    # ports on request: non-default constants and blackboard keys
    ported = tree_dot(root, ports=True)
    rate = _node_lines(ported)[[type(n).__name__ for n in nodes].index("RateController")]
    assert "hz: 1<" in rate
    plan = _node_lines(ported)[[n.name for n in nodes].index("ComputePathToPrePose")]
    assert "goal: {pre_pose}" in plan and "path \u2192 {path}" in plan
    assert "use_start" not in plan  # left at its default
    # collapsing a subtree: one folder node counting its nodes, none of its nodes drawn
    collapsed = tree_dot(root, collapse=["Escalation"])
    escalation = next(c for n in nodes for c in getattr(n, "children", [])
                      if subtree_name(c, n) == "Escalation")
    inside = len([n for n, _ in walk(escalation)])     # the subtree's nodes, counted from the tree
    assert inside >= 10
    assert "shape=folder" in collapsed and f"{inside} nodes" in collapsed
    assert "RotateFullTurn" not in collapsed and "subgraph cluster_" in collapsed
    assert render_tree(root, "svg").lstrip().startswith(b"<?xml")


def _status_leaf(name: str, statuses: list[Status]) -> py_trees.behaviour.Behaviour:
    return py_trees.behaviours.StatusQueue(name, queue=statuses, eventually=statuses[-1])


def test_run_statistics_and_last_failure_chain():
    # tick 0: 'bad' fails -> 'attempt' fails -> fallback tries 'backup' (SUCCESS)
    # tick 1: 'bad' runs; tick 2.. 'bad' succeeds, the attempt succeeds.
    bad = _status_leaf("bad", [Status.FAILURE, Status.RUNNING, Status.SUCCESS])
    guard = _status_leaf("guard", [Status.FAILURE])  # fails every tick, caught by inverter
    attempt = py_trees.composites.Sequence("attempt", memory=False, children=[
        py_trees.decorators.Inverter("not_guard", guard), bad])
    backup = _status_leaf("backup", [Status.SUCCESS])
    root = py_trees.composites.Selector("root", memory=False, children=[attempt, backup])
    stream = io.StringIO()
    ex = Executive(py_trees.trees.BehaviourTree(root), wall_ahead_robot(Pose2D()), SimClock(),
                   0.1, recorder=Recorder(stream))
    for _ in range(4):
        ex.step()
    ex.recorder.footer({"outcome": "test"})
    footer = json.loads(stream.getvalue().splitlines()[-1])["footer"]
    names = [n.name for n, _ in walk(root)]
    stats = dict(zip(names, footer["node_stats"]))
    assert stats["root"] == [4, 3, 0, 0.1]          # SUCCESS (by backup), RUNNING, SUCCESS x2
    assert stats["attempt"] == [4, 2, 1, 0.1]      # FAILURE, RUNNING, SUCCESS, SUCCESS
    assert stats["bad"] == [4, 2, 1, 0.1]
    assert stats["guard"] == [4, 0, 4, 0.0] and stats["not_guard"] == [4, 4, 0, 0.0]
    assert stats["backup"] == [1, 1, 0, 0.0]       # only when the attempt failed
    # the guard's failures were caught by the inverter: the last propagated failure is 'bad'
    assert [names[i] for i in footer["last_failure"]] == ["attempt", "bad"]
    assert footer["last_failure_tick"] == 0
    parsed, chain = stats_from_footer(footer)
    assert parsed[names.index("backup")] == NodeStats(1, 1, 0, 0.0)
    dot = tree_dot(root, stats=parsed, last_failure=chain)
    lines = _node_lines(dot)
    assert "4 ticks, 2 ok, 1 failed, 0.1 s running" in lines[names.index("bad")]
    assert 'color="#d62728" penwidth=3' in lines[names.index("bad")]
    assert 'color="#d62728"' not in lines[names.index("guard")]
    red_edges = re.findall(r"n(\d+) -> n(\d+) \[color=\"#d62728\"", dot)
    assert red_edges == [(str(names.index("attempt")), str(names.index("bad")))]


def test_unrecorded_run_adds_no_visitor():
    root = _status_leaf("x", [Status.SUCCESS])
    tree = py_trees.trees.BehaviourTree(root)
    ex = Executive(tree, wall_ahead_robot(Pose2D()), SimClock(), 0.1)
    assert tree.visitors == [] and ex.recorder.node_stats is None


def test_a_failing_sink_is_dropped_and_the_run_goes_on():
    class Broken:
        def __init__(self):
            self.ticks = 0

        def start(self, header, executive):
            pass

        def tick(self, line, executive):
            self.ticks += 1
            if self.ticks == 3:
                raise OSError("No space left on device")

        def finish(self, footer):
            pass

    class Counting(Broken):
        def tick(self, line, executive):
            self.ticks += 1

    broken, counting = Broken(), Counting()
    root = _status_leaf("x", [Status.RUNNING])
    rec = Recorder(None, sinks=[broken, counting])
    ex = Executive(py_trees.trees.BehaviourTree(root), wall_ahead_robot(Pose2D()), SimClock(),
                   0.1, recorder=rec)
    for _ in range(6):
        ex.step()
    assert broken.ticks == 3 and counting.ticks == 6 and rec.sinks == [counting]
    assert rec.sink_errors == ["Broken.tick: OSError: No space left on device"]
