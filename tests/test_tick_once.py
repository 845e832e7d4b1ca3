"""``tick_once`` (the executive's tick, without generators) does exactly what draining
``tick()`` (py_trees' generator protocol) does: random trees of the nodes that define both,
mixed with nodes that define ``tick`` only and stock py_trees behaviours, ticked both ways from
the same script, give the same statuses, the same lifecycle calls in the same order and the
same feedback, tick by tick, through halts and parameter changes."""

from __future__ import annotations

import itertools

import numpy as np
import py_trees
import pytest
from py_trees.common import Status

from behaviors.base import Leaf, Recovery, make
from executive.tree_loader import LeanBehaviourTree
from navcore.clock import SimClock
from navcore.params import Param, Parameters
from navcore.types import Pose2D

S, F, R, I = Status.SUCCESS, Status.FAILURE, Status.RUNNING, Status.INVALID
_ns = itertools.count()

# the control nodes and decorators with a tick_once of their own, and some without
CONTROLS = ["Sequence", "SequenceWithMemory", "Fallback", "ReactiveSequence", "ReactiveFallback",
            "PipelineSequence", "IfThenElse", "RecoveryNode", "RoundRobin"]
DECORATORS = ["Inverter", "ForceSuccess", "ForceFailure", "RateController", "SetParameters",
              "GoalUpdatedController", "Timeout"]
_STORAGE = py_trees.blackboard.Blackboard.storage


class Scripted(Leaf, register=False):
    """A navbt leaf whose n-th update returns ``script[n % len(script)]``."""

    INPUT_PORTS: dict = {}
    OUTPUT_PORTS: dict = {}

    def __init__(self, name: str, script: list[Status], log: list) -> None:
        super().__init__(name=name)
        self.script, self.log, self.n = script, log, 0

    def initialise(self) -> None:
        self.log.append((self.name, "initialise"))

    def update(self) -> Status:
        status = self.script[self.n % len(self.script)]
        self.n += 1
        self.say("update {}", self.n)
        return status


class ScriptedRecovery(Recovery, Scripted, register=False):
    """A Scripted leaf marked as a recovery (its class changes ``tick`` only)."""


def _params() -> dict[str, Parameters]:
    return {"DWAPlannerROS": Parameters((Param("path_distance_bias", 32.0, float, min=0.0),),
                                        where="DWAPlannerROS")}


def build(seed: int, log: list, params: dict, clock: SimClock, root_kind: str | None = None,
          max_depth: int = 4, ns: str = "") -> py_trees.behaviour.Behaviour:
    """The random tree of ``seed`` (the same nodes, names and scripts for the same seed), its
    root a ``root_kind`` when given, its keys under ``ns``."""
    rng = np.random.default_rng(seed)
    ns = ns or f"/once{next(_ns)}"
    names = itertools.count()

    def leaf(depth: int) -> py_trees.behaviour.Behaviour:
        # runs of one status (a child RUNNING for a while, failing twice...) as well as mixes
        script = [(S, F, R)[k] for k in rng.integers(0, 3, size=int(rng.integers(1, 6)))
                  for _ in range(int(rng.integers(1, 7)))]
        name = f"leaf{next(names)}"
        kind = rng.integers(0, 3)
        if kind == 0:   # a stock py_trees behaviour: py_trees' own tick and tick_once
            return py_trees.behaviours.StatusQueue(name=name, queue=script, eventually=script[-1])
        cls = ScriptedRecovery if kind == 1 else Scripted
        return cls(name, script, log)

    def node(depth: int, kind: str | None = None) -> py_trees.behaviour.Behaviour:
        if kind is None and (depth >= max_depth or rng.random() < 0.3):
            return leaf(depth)
        if kind in DECORATORS or (kind is None and rng.random() < 0.35):
            kind = kind or DECORATORS[int(rng.integers(0, len(DECORATORS)))]
            ports: dict = {}
            if kind == "RateController":
                ports["hz"] = float(rng.choice([0.0, 4.0, 20.0]))
            elif kind == "SetParameters":   # (its port 'namespace' clashes with make's)
                ports["port_values"] = {"namespace": str(rng.choice(["DWAPlannerROS",
                                                                     "Unknown"]))}
                ports["values"] = {"path_distance_bias": float(rng.choice([8.0, -1.0]))}
                ports["required"] = bool(rng.integers(0, 2))
            elif kind == "Timeout":
                ports["msec"] = int(rng.choice([100, 400]))
            return make(kind, name=f"{kind}{next(names)}", namespace=ns, child=node(depth + 1),
                        **ports)
        kind = kind or CONTROLS[int(rng.integers(0, len(CONTROLS)))]
        n = {"IfThenElse": int(rng.integers(2, 4)), "RecoveryNode": 2}.get(
            kind, int(rng.integers(1, 5)))
        ports = {}
        if kind == "RecoveryNode":
            ports = {"number_of_retries": int(rng.integers(0, 3)),
                     "reset_after": float(rng.choice([0.0, 0.2]))}
        elif kind == "RoundRobin":
            ports = {"wrap_around": bool(rng.integers(0, 2))}
        return make(kind, name=f"{kind}{next(names)}", namespace=ns,
                    children=[node(depth + 1) for _ in range(n)], **ports)

    root = node(0, root_kind)
    for n in root.iterate():
        n.setup(clock=clock, parameters=params)
        _log_calls(n, log)
    return root


def _log_calls(node: py_trees.behaviour.Behaviour, log: list) -> None:
    """Record every stop and terminate of ``node`` (instance attributes: what the tick calls)."""
    stop, terminate = node.stop, node.terminate

    def logged_stop(new_status: Status = I) -> None:
        log.append((node.name, "stop", new_status, node.status))
        stop(new_status)

    def logged_terminate(new_status: Status) -> None:
        log.append((node.name, "terminate", new_status, node.status))
        terminate(new_status)

    node.stop, node.terminate = logged_stop, logged_terminate


def state(root: py_trees.behaviour.Behaviour, ns: str) -> list:
    """Every node's status, feedback, recovery starts and current child; the tree's keys."""
    current = [getattr(getattr(n, "current_child", None), "name", None) for n in root.iterate()]
    keys = sorted((k[len(ns):], repr(v)) for k, v in _STORAGE.items() if k.startswith(ns + "/"))
    return [(n.name, n.status, n.feedback_message, getattr(n, "recovery_starts", 0))
            for n in root.iterate()] + [current, keys]


def both_ways(seed: int, root_kind: str | None = None, max_depth: int = 4) -> list:
    """The trace (states, lifecycle calls, parameter) of 40 ticks with ``tick_once`` and with
    the drained ``tick()``."""
    runs = []
    for once in (True, False):
        log: list = []
        params, clock, ns = _params(), SimClock(), f"/once{next(_ns)}"
        root = build(seed, log, params, clock, root_kind, max_depth, ns)
        trace = []
        for t in range(40):
            if t % 7 == 3:   # a new goal now and then (GoalUpdatedController)
                _STORAGE[ns + "/goal"] = Pose2D(float(t), 0.0)
            if t in (17, 31):
                root.stop(I)             # a halt (a new goal) in the middle of runs
            if once:
                root.tick_once()
            else:
                for _ in root.tick():
                    pass
            trace.append((state(root, ns), list(log),
                          params["DWAPlannerROS"].path_distance_bias))
            log.clear()
            clock.advance(0.05)
        runs.append(trace)
    return runs


@pytest.mark.parametrize("seed", range(80))
def test_tick_once_is_the_drained_generator_tick_by_tick(seed):
    runs = both_ways(seed)
    assert runs[0] == runs[1]


@pytest.mark.parametrize("kind", CONTROLS + DECORATORS)
def test_each_node_kind_at_the_root_ticks_the_same_both_ways(kind):
    """Small trees under each kind hit its branches (retries, resets, throttling) often."""
    for seed in range(25):
        runs = both_ways(seed, kind, max_depth=2)
        assert runs[0] == runs[1], f"{kind}, seed {seed}"


def test_random_trees_exercise_every_tick_once():
    """The seeds above build every node kind and see all three statuses at the root."""
    kinds, roots = set(), set()
    for seed in range(60):
        root = build(seed, [], _params(), SimClock())
        kinds |= {type(n).__name__ for n in root.iterate()}
        for _ in range(40):
            root.tick_once()
            roots.add(root.status)
    assert set(CONTROLS + DECORATORS) <= kinds
    assert {"Scripted", "ScriptedRecovery", "StatusQueue"} <= kinds
    assert roots == {S, F, R}


def test_the_executive_tree_ticks_through_tick_once_and_visitors_see_the_generator():
    """LeanBehaviourTree ticks the root with tick_once when nothing watches; a visitor gets
    every node as it finishes (py_trees' protocol), the root last, with the same outcome."""
    for seed in range(5):
        results, seen = [], []

        class Visitor(py_trees.visitors.VisitorBase):
            def run(self, behaviour):
                seen.append(behaviour.name)

        for visit in (False, True):
            log: list = []
            ns = f"/once{next(_ns)}"
            root = build(seed, log, _params(), SimClock(), ns=ns)
            tree = LeanBehaviourTree(root)
            if visit:
                tree.visitors.append(Visitor())
            for _ in range(10):
                tree.tick()
            results.append((state(root, ns), log))
        assert results[0] == results[1]
        assert seen.count(root.name) == 10 and seen[-1] == root.name


def test_a_class_that_changes_tick_once_alone_is_refused():
    with pytest.raises(TypeError, match="defines tick_once but not tick"):
        class Bad(Scripted, register=False):
            def tick_once(self) -> None:
                pass


def test_a_class_that_changes_tick_alone_ticks_through_it():
    calls = []

    class Wrapped(Scripted, register=False):
        def tick(self):
            calls.append(self.name)
            yield from super().tick()

    node = Wrapped("w", [S], [])
    node.tick_once()
    assert calls == ["w"] and node.status is S and node.n == 1
