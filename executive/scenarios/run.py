"""Running scenarios: one run (scenario x tree x seed), many runs (serial or a process pool),
multi-seed verdicts and JUnit XML.

``run_scenario`` never raises for a problem of the run itself: a broken scenario, a tree that does
not load or an exception while running gives a result with outcome ``error`` (and the message),
so a batch never loses the results it already has. Each run drives its mission through the
public API (executive/api.py: ``open_mission``, ``Navigator.follow_waypoints``, ``run(on_tick=)``);
the ``on_tick`` hook applies the events at their time (a goal through ``update_goal`` /
``add_waypoint``; the world, faults, phantoms and parameters through the executive it is handed)
and notes what the record needs: the body's true motion, the recoveries, and the error code that
caused the end.
"""

from __future__ import annotations

import math
import os
import traceback
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import Any, Callable, Iterable

import numpy as np

from navcore.types import Pose2D

from executive.scenarios.check import RunRecord, check
from executive.scenarios.model import Event, Scenario, Shape
from executive.scenarios.source import ScenarioError

DEFAULT_WALL_LIMIT = 300.0   # s of wall time per run before it is stopped as an error


@dataclass
class ScenarioResult:
    """One scenario run against one tree with one seed, and whether it met its expectation."""

    scenario: str
    tree: str
    outcome: str            # succeeded | failed | timeout | error | skipped
    sim_time: float
    wall_time: float
    recoveries: list[dict[str, Any]]
    collisions: int
    solved: bool
    passed: bool
    failures: list[str]
    reason: str = ""        # Nav2 error-code name of what ended it (TIME_LIMIT for timeouts)
    detail: str = ""        # the words behind it (the executive's reason, the error message)
    run_dir: str | None = None
    known_issue: str = ""
    seed: int = 0
    source: str = ""
    final_pose: list[float] = field(default_factory=list)
    distance_to_goal: float | None = None
    goals_reached: int = 0
    goals_total: int = 0
    distance: float = 0.0          # path driven (m)
    events: dict[str, float] = field(default_factory=dict)   # event name -> time it fired (s)

    @property
    def recovery_types(self) -> list[str]:
        return [r["type"] for r in self.recoveries]

    def as_dict(self) -> dict[str, Any]:
        return {"scenario": self.scenario, "tree": self.tree, "seed": self.seed,
                "outcome": self.outcome, "reason": self.reason, "detail": self.detail,
                "solved": self.solved, "passed": self.passed, "failures": self.failures,
                "known_issue": self.known_issue,
                "final_pose": self.final_pose,
                "distance_to_goal_m": (None if self.distance_to_goal is None
                                       else round(self.distance_to_goal, 3)),
                "goals_reached": self.goals_reached, "goals_total": self.goals_total,
                "distance_m": round(self.distance, 3),
                "events": {k: round(v, 3) for k, v in self.events.items()}, "recoveries": self.recoveries, "contacts": self.collisions,
                "sim_time_s": round(self.sim_time, 3), "wall_time_s": round(self.wall_time, 3),
                "run_dir": self.run_dir, "source": self.source}


def reason_name(code: int) -> str:
    """The Nav2 name of an error code (the planner, controller and behaviour ranges differ)."""
    from executive.scenarios.parse import CODE_ENUMS
    for enum in CODE_ENUMS:
        try:
            return enum(int(code)).name
        except ValueError:
            continue
    return f"CODE_{int(code)}"


class _Tracker:
    """Per tick: the body's true motion, recoveries' start/end, error-code changes."""

    def __init__(self, ex: Any, sim: Any) -> None:
        import py_trees
        from py_trees.common import Status

        from behaviors.base import Recovery
        self.ex, self.sim = ex, sim
        self.running_status = Status.RUNNING
        self.storage = py_trees.blackboard.Blackboard.storage
        self.prefix = ex.namespace + "/"
        self.nodes: dict[tuple[str, str], list[Any]] = {}
        for n in ex.tree.root.iterate():
            if isinstance(n, Recovery):
                self.nodes.setdefault((n.name, type(n).__name__), []).append(n)
        self.records: list[dict[str, Any]] = []
        self.t: list[float] = []
        self.x: list[float] = []
        self.y: list[float] = []
        self.v: list[float] = []
        self.w: list[float] = []
        self.last_code: tuple[float, int] | None = None
        self.now = 0.0
        # blackboard key of each node's error_code_id port: the code a failing node wrote
        self.code_keys: dict[int, str] = {}
        for n in ex.tree.root.iterate():
            ports = getattr(n, "output_ports", None)
            if ports is not None and "error_code_id" in ports():
                try:
                    self.code_keys[id(n)] = n.port_key("error_code_id")
                except Exception:  # noqa: BLE001 - a port left unwired writes nowhere
                    pass
        self.failure_status = Status.FAILURE
        ex.tree.visitors.append(self)   # py_trees calls run(node) for every node ticked
        self.full = False

    def initialise(self) -> None:
        """py_trees visitor API (called before each tick)."""

    def finalise(self) -> None:
        """py_trees visitor API (called after each tick)."""

    def run(self, node: Any) -> None:
        """The latest node that failed with a non-zero error code is the cause of a failure."""
        if node.status == self.failure_status:
            key = self.code_keys.get(id(node))
            if key is not None:
                code = self.storage.get(key)
                if isinstance(code, (int, np.integer)) and not isinstance(code, bool) and code:
                    self.last_code = (self.now, int(code))

    def tick(self, now: float) -> None:
        ex = self.ex
        p = ex.io.true_pose() or ex.robot.pose()
        if self.sim is not None:
            tw = self.sim.true_velocity()
            v, w = tw.vx, tw.wz
        else:
            tw = ex.robot.velocity()
            v, w = tw.vx, tw.wz
        self.t.append(now)
        self.x.append(p.x)
        self.y.append(p.y)
        self.v.append(v)
        self.w.append(w)
        trace = ex.trace.recoveries
        while len(self.records) < len(trace):
            r = trace[len(self.records)]
            self.records.append({"name": r["recovery"], "type": r["type"], "t": r["t"],
                                 "end": None})
        for r in self.records:
            if r["end"] is None and not self.running(r):
                r["end"] = round(now, 3)

    def running(self, r: dict[str, Any]) -> bool:
        return any(n.status == self.running_status
                   for n in self.nodes.get((r["name"], r["type"]), ()))

    def open_recoveries(self) -> list[dict[str, Any]]:
        return [r for r in self.records if r["end"] is None]


class _Events:
    """Applies a scenario's events to a running mission at their time."""

    def __init__(self, scenario: Scenario, nav: Any) -> None:
        self.pending = list(scenario.events)
        self.t0 = 0.0           # the clock at the start: event times are relative to it
        self.nav = nav          # executive.api.Navigator
        self.fired: dict[str, float] = {}
        self.goal_changes: list[float] = []
        self.added: dict[str, Any] = {}
        # the simulator names scenario objects object0, object1, ... (executive.mission)
        self.by_name: dict[str, str] = {s.name: f"object{i}"
                                        for i, s in enumerate(scenario.objects) if s.name}
        self.phantoms: dict[str, tuple[Shape, str]] = {s.name: (s, w)
                                                       for s, w in scenario.phantoms if s.name}

    def due(self, ev: Event, now: float, recoveries: list[dict[str, Any]]) -> bool:
        if ev.at is not None:
            return now >= ev.at - 1e-9
        if ev.while_recovery:   # a matching recovery still running, for ``delay`` s so far
            return any(r["end"] is None and ev.while_recovery in ("any", r["type"], r["name"])
                       and now + self.t0 >= r["t"] + ev.delay - 1e-9 for r in recoveries)
        first = next((r for r in recoveries if ev.after_recovery in ("any", r["type"], r["name"])),
                     None)
        return first is not None and now + self.t0 >= first["t"] + ev.delay - 1e-9

    def apply_due(self, ex: Any, now: float, recoveries: list[dict[str, Any]]) -> None:
        if not self.pending:
            return
        still = []
        for ev in self.pending:
            if self.due(ev, now, recoveries):
                self.apply(ex, ev, now)
                self.fired[ev.name] = now
            else:
                still.append(ev)
        self.pending = still

    @staticmethod
    def _costmaps(ex: Any, which: str) -> list[Any]:
        c = ex.components
        return {"global": [c["global_costmap"]], "local": [c["local_costmap"]],
                "both": [c["global_costmap"], c["local_costmap"]]}[which]

    def apply(self, ex: Any, ev: Event, now: float) -> None:
        """Apply one event to the running mission; ``ex``: the executive ``on_tick`` was given."""
        from executive.perception import paint_phantom
        sim = self.nav.sim
        a = ev.action
        if a == "goal":
            # Nav2's pre-emption: the new goal goes on the blackboard and the tree
            # (GoalUpdated) decides what to do with a running recovery
            self.nav.update_goal(ev.arg)
            self.goal_changes.append(now)
        elif a == "add_goal":
            self.nav.add_waypoint(ev.arg)
        elif a == "add":
            from hw.sim import Box, Circle
            s = ev.arg
            obj = (Box(*s.values, name=s.name) if s.kind == "box" else Circle(*s.values,
                                                                           name=s.name))
            sim.world.add(obj)
            if s.name:
                self.added[s.name] = obj
        elif a == "remove":
            obj = self.added.pop(ev.arg, None)
            if obj is None:
                target = self.by_name.get(ev.arg)
                obj = next((o for o in sim.world.objects if o.name == target), None)
            if obj is not None:
                sim.world.remove(obj)
        elif a == "fault":
            sim.add_fault(dict(ev.arg, start=now))
        elif a == "end_fault":
            sim.end_faults(ev.arg, now)
        elif a == "phantom":
            shape, which = ev.arg
            for cm in self._costmaps(ex, which):
                paint_phantom(cm, shape)
            if shape.name:
                self.phantoms[shape.name] = (shape, which)
        elif a in ("move_phantom", "remove_phantom"):
            shape, which = self.phantoms[ev.arg]
            for cm in self._costmaps(ex, which):
                clear_shape(cm, shape)
                if a == "move_phantom":
                    paint_phantom(cm, ev.to)
            if a == "move_phantom":
                self.phantoms[ev.arg] = (ev.to, which)
        elif a == "set":
            params = ex.components["parameters"]
            for ns, values in ev.arg.items():
                if ns not in params:
                    raise ScenarioError(f"event {ev.name}: set: no namespace {ns!r}")
                params[ns].set(values)


class _TickHook:
    """What a scenario run does after each cycle (``Navigator.run``'s ``on_tick``): track the
    body and the recoveries, apply the events now due, note the recoveries a goal change
    pre-empts, stop at the wall-clock limit, then call the caller's ``on_tick``. ``t0``: the
    clock when the task began."""

    def __init__(self, source: str, tracker: _Tracker, events: _Events, t0: float, wall: Any,
                 limit_wall: float, on_tick: Callable[[Any], Any] | None) -> None:
        self.source, self.tracker, self.events = source, tracker, events
        self.wall, self.limit_wall, self.on_tick = wall, limit_wall, on_tick
        self.t0 = t0
        self.ticks = 0
        # (recovery name, goal-change time, end of that recovery): end filled in after the run
        self.preempts: list[tuple[str, float, float]] = []

    def __call__(self, ex: Any) -> bool | None:
        tracker, events, t0 = self.tracker, self.events, self.t0
        now = ex.clock.now() - ex.period    # the time of the tick just run
        tracker.tick(now)
        tracker.now = ex.clock.now()       # the visitor's time for the next tick
        self.ticks += 1
        n = len(events.goal_changes)
        events.apply_due(ex, now - t0, tracker.records)
        if len(events.goal_changes) > n:
            for r in tracker.open_recoveries():
                self.preempts.append((r["name"], now - t0, -1.0))
        if self.ticks % 25 == 0 and self.wall.now() > self.limit_wall:
            raise ScenarioError(f"{self.source}: wall-clock limit {self.limit_wall:g} s "
                                f"reached at t={now - t0:.1f} s simulated")
        return self.on_tick(ex) if self.on_tick is not None else None


def clear_shape(cm: Any, shape: Shape) -> None:
    """Free a shape's cells in every clearable layer of a costmap (a phantom moved away)."""
    from navcore.costmap.cost_values import FREE_SPACE
    x0, y0, x1, y1 = shape.bbox()
    for layer in [l for l in cm.layers if getattr(l, "clearable", False)]:
        g = layer.grid
        c0 = max(0, int((x0 - g.origin_x) / g.resolution))
        c1 = min(g.size_x, int(math.ceil((x1 - g.origin_x) / g.resolution)))
        r0 = max(0, int((y0 - g.origin_y) / g.resolution))
        r1 = min(g.size_y, int(math.ceil((y1 - g.origin_y) / g.resolution)))
        for my in range(r0, r1):
            for mx in range(c0, c1):
                wx, wy = g.map_to_world(mx, my)
                if shape.contains(wx, wy) or shape.kind != "circle":
                    g.costs[my, mx] = FREE_SPACE
        layer.add_extra_bounds(x0, y0, x1, y1)


def _error_result(scenario: Scenario | None, name: str, tree: str, seed: int, message: str,
                  wall: float = 0.0, outcome: str = "error", source: str = "") -> ScenarioResult:
    known = scenario.known_issue_for(tree) if scenario is not None else ""
    return ScenarioResult(name, tree, outcome, 0.0, wall, [], 0, False,
                          outcome == "skipped", [] if outcome == "skipped" else [message],
                          "INTERNAL_ERROR" if outcome == "error" else "", message, None, known,
                          seed, source or (scenario.source if scenario else ""))


def run_scenario(scenario: Scenario, tree_path: str, record_dir: str | None = None,
                 config_path: str | None = None, on_tick: Callable[[Any], Any] | None = None,
                 hardware: bool | str = False, seed: int | None = None,
                 wall_limit: float | None = None) -> ScenarioResult:
    """Run one scenario against one tree with one seed (default: the scenario's ``seed``).

    Never raises for the run's own problems: those give outcome ``error`` (or ``skipped`` when
    a real map is absent here)."""
    from navcore.clock import WallClock
    wall = WallClock()
    seed = scenario.seed if seed is None else seed
    tree_name = FsPath(tree_path).stem
    if scenario.skip:
        return _error_result(scenario, scenario.name, tree_name, seed, scenario.skip,
                             outcome="skipped")
    try:
        return _run(scenario, tree_path, tree_name, record_dir, config_path, on_tick, hardware,
                    seed, wall, wall_limit)
    except Exception as e:  # noqa: BLE001 - one broken run must not lose the others
        msg = str(e) if isinstance(e, ScenarioError) else \
            f"{type(e).__name__}: {e}\n{traceback.format_exc(limit=6)}"
        return _error_result(scenario, scenario.name, tree_name, seed, msg, wall.now())


def _run(scenario: Scenario, tree_path: str, tree_name: str, record_dir: str | None,
         config_path: Any, on_tick: Callable[[Any], Any] | None, hardware: bool | str,
         seed: int, wall: Any, wall_limit: float | None) -> ScenarioResult:
    from executive.api import open_mission
    from executive.config import ConfigError
    from executive.recorder import Recorder
    from executive.scenarios.generate import materialize
    from executive.scenarios.profiles import scenario_config
    from executive.world import World
    sc = materialize(scenario, seed)
    try:
        config = scenario_config(sc, config_path)
    except ConfigError as e:
        raise ScenarioError(str(e)) from None
    world = World(sc.objects, sc.moving, sc.phantoms, sc.faults, sc.unknown_solid)
    limit_wall = wall_limit or sc.wall_limit or DEFAULT_WALL_LIMIT
    recorder = Recorder(None)
    if record_dir is not None:
        from executive.run_folder import open_recorder
        recorder = open_recorder(record_dir, grid=sc.grid)
    try:
        nav = open_mission(tree_path, config, sc.grid, sc.start, world=world, seed=seed,
                           recorder=recorder, meta={"scenario": sc.name, "seed": seed},
                           hardware=hardware)
        try:
            # the tracker watches every node tick (a py_trees visitor), so it goes on the tree
            # before the first cycle: the executive of the API (``nav.executive``)
            ex = nav.executive
            tracker = _Tracker(ex, nav.sim)
            nav.follow_waypoints(sc.goals, sc.time_limit)
            t0 = nav.clock.now()     # the task's start: event and record times count from it
            events = _Events(sc, nav)
            events.t0 = t0
            tracker.now = t0
            hook = _TickHook(sc.source, tracker, events, t0, wall, limit_wall, on_tick)
            result = nav.run(on_tick=hook)
            outcome = result.outcome
            reason, detail = "", ""
            if outcome == "failed":
                if ex.internal_error is not None or (
                        ex.trace.errors and ex.trace.errors[-1]["t"] >= ex.clock.now()
                        - 2 * ex.period):
                    reason, detail = "INTERNAL_ERROR", result.reason
                elif tracker.last_code is not None:
                    reason = reason_name(tracker.last_code[1])
                    detail = (f"error code {tracker.last_code[1]} at "
                              f"t={tracker.last_code[0] - t0:.1f} s")
                else:
                    reason, detail = "TREE_FAILURE", result.reason
            elif outcome == "timeout":
                reason, detail = "TIME_LIMIT", result.reason
            elif outcome != "succeeded":
                detail = result.reason
            sim_time = result.sim_time
            tracker.tick(ex.clock.now())     # close the recoveries the end interrupted
            for r in tracker.records:
                r["t"] = round(r["t"] - t0, 3)
                r["end"] = round((r["end"] if r["end"] is not None else sim_time + t0) - t0, 3)
            ends = {}
            preempts = hook.preempts
            for name, tg, _ in preempts:
                rec = next((r for r in tracker.records if r["name"] == name and r["t"] <= tg
                            and r["end"] >= tg), None)
                ends[(name, tg)] = rec["end"] if rec else tg
            preempts = [(n, tg, ends[(n, tg)]) for n, tg, _ in preempts]
            collisions = result.collisions
            if record_dir is not None:
                from executive.run_folder import finish
                finish(record_dir, ex, result, sc.grid, config.footprint(),
                       extra={"name": sc.name, "tree": tree_path, "seed": seed,
                              "reason": reason},
                       obstacles=[s.polygon() for s in sc.objects],
                       phantoms=[shape.polygon() for shape, _ in sc.phantoms])
            truth = nav.sim.true_pose() if nav.sim is not None else nav.pose()
            goal = nav.get_feedback().goal      # the goal being driven to at the end
        finally:
            nav.close()       # drivers and emulators of hardware="emulated" too
    finally:
        recorder.close()
    reached, total = result.goals_reached, result.goals_total
    t = np.asarray(tracker.t) - t0
    rec = RunRecord(outcome, reason, sim_time, reached, total, truth, goal,
                    collisions, tracker.records, t, np.asarray(tracker.x),
                    np.asarray(tracker.y), np.asarray(tracker.v), np.asarray(tracker.w),
                    events.fired, preempts)
    failures = check(scenario.expectation_for(tree_name), rec)
    return ScenarioResult(
        sc.name, tree_name, outcome, sim_time, wall.now(), tracker.records, collisions,
        outcome == "succeeded" and collisions == 0, not failures, failures, reason, detail,
        record_dir, scenario.known_issue_for(tree_name), seed, sc.source,
        [round(truth.x, 3), round(truth.y, 3), round(truth.theta, 3)],
        math.hypot(truth.x - goal.x, truth.y - goal.y), reached, total, result.distance,
        dict(events.fired))


# --------------------------------------------------------------------------- batches
@dataclass
class Task:
    """One run to do: a scenario file (or an already loaded scenario), a tree, a seed."""

    source: str
    tree: str
    seed: int | None = None
    scenario: Scenario | None = None
    record_dir: str | None = None
    config_path: Any = None             # a robot YAML path or executive.config.ConfigSources
    hardware: bool | str = False
    wall_limit: float | None = None


def run_task(task: Task) -> ScenarioResult:
    """Run one task; a scenario that does not load gives an ``error`` result naming why."""
    from executive.scenarios.parse import load_scenario
    tree_name = FsPath(task.tree).stem
    sc = task.scenario
    if sc is None:
        try:
            sc = load_scenario(task.source)
        except ScenarioError as e:
            return _error_result(None, FsPath(task.source).stem, tree_name, task.seed or 0,
                                 str(e), source=task.source)
    return run_scenario(sc, task.tree, record_dir=task.record_dir,
                        config_path=task.config_path, hardware=task.hardware, seed=task.seed,
                        wall_limit=task.wall_limit)


def run_tasks(tasks: list[Task], jobs: int = 1,
              on_result: Callable[[ScenarioResult], None] | None = None
              ) -> list[ScenarioResult]:
    """Run tasks serially or on ``jobs`` worker processes; results in task order either way
    (each run is deterministic, so the pool gives the serial results)."""
    results: list[ScenarioResult | None] = [None] * len(tasks)
    if jobs <= 1 or len(tasks) <= 1:
        for i, t in enumerate(tasks):
            results[i] = run_task(t)
            if on_result is not None:
                on_result(results[i])
        return [r for r in results if r is not None]
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool
    ctx = multiprocessing.get_context("fork" if os.name == "posix" else "spawn")
    with ProcessPoolExecutor(max_workers=jobs, mp_context=ctx) as pool:
        futures = {pool.submit(run_task, t): i for i, t in enumerate(tasks)}
        for fut in as_completed(futures):
            i = futures[fut]
            t = tasks[i]
            try:
                results[i] = fut.result()
            except (BrokenProcessPool, Exception) as e:  # noqa: BLE001 - a worker died
                results[i] = _error_result(t.scenario, FsPath(t.source).stem,
                                           FsPath(t.tree).stem, t.seed or 0,
                                           f"worker failed: {type(e).__name__}: {e}",
                                           source=t.source)
            if on_result is not None:
                on_result(results[i])
    return [r for r in results if r is not None]


def tasks_for(sources: Iterable[tuple[str, Scenario | None]], trees: list[str],
              seeds: list[int] | None = None, **options: Any) -> list[Task]:
    """A task per scenario x tree x seed (the scenario's own seeds unless ``seeds`` is given)."""
    out = []
    for source, sc in sources:
        run_seeds = seeds if seeds is not None else (sc.run_seeds() if sc else [None])
        for tree in trees:
            for s in run_seeds:
                out.append(Task(source, tree, s, sc, **options))
    return out


@dataclass
class Verdict:
    """A scenario against a tree over its seeds: passes when at least ``needed`` met it."""

    scenario: str
    tree: str
    runs: list[ScenarioResult]
    needed: int

    @property
    def met(self) -> int:
        return sum(1 for r in self.runs if r.passed)

    @property
    def solved(self) -> int:
        return sum(1 for r in self.runs if r.solved)

    @property
    def skipped(self) -> bool:
        return all(r.outcome == "skipped" for r in self.runs)

    @property
    def passed(self) -> bool:
        return self.met >= self.needed

    @property
    def known_issue(self) -> str:
        return next((r.known_issue for r in self.runs if r.known_issue), "")

    def as_dict(self) -> dict[str, Any]:
        return {"scenario": self.scenario, "tree": self.tree, "seeds": [r.seed for r in self.runs],
                "met": self.met, "needed": self.needed, "runs": len(self.runs),
                "solved": self.solved, "passed": self.passed, "skipped": self.skipped,
                "known_issue": self.known_issue}


def verdicts(results: list[ScenarioResult], needed: dict[str, int]) -> list[Verdict]:
    """Group results by scenario and tree; ``needed``: scenario name -> seeds that must pass
    (all of them when absent)."""
    groups: dict[tuple[str, str], list[ScenarioResult]] = {}
    for r in results:
        groups.setdefault((r.scenario, r.tree), []).append(r)
    out = []
    for (name, tree), runs in groups.items():
        k = needed.get(name)
        out.append(Verdict(name, tree, runs, len(runs) if k is None else min(k, len(runs))))
    return out


def junit_xml(results: list[ScenarioResult], verdict_list: list[Verdict]) -> str:
    """JUnit XML: a test suite per tree, a test case per run (``scenario[seed]``)."""
    import xml.etree.ElementTree as ET
    root = ET.Element("testsuites", name="navbt scenarios")
    for tree in dict.fromkeys(r.tree for r in results):
        rs = [r for r in results if r.tree == tree]
        suite = ET.SubElement(root, "testsuite", name=tree, tests=str(len(rs)))
        fails = errors = skipped = 0
        for r in rs:
            case = ET.SubElement(suite, "testcase", classname=f"scenarios.{tree}",
                                 name=f"{r.scenario}[seed={r.seed}]",
                                 time=f"{r.wall_time:.3f}", file=r.source)
            if r.outcome == "skipped":
                skipped += 1
                ET.SubElement(case, "skipped", message=r.detail)
            elif r.outcome == "error":
                errors += 1
                ET.SubElement(case, "error", message=r.detail.splitlines()[0] if r.detail
                              else "error").text = r.detail
            elif not r.passed and r.known_issue:
                skipped += 1
                ET.SubElement(case, "skipped", message=f"known issue: {r.known_issue}")
            elif not r.passed:
                v = next((v for v in verdict_list if v.scenario == r.scenario and v.tree == tree),
                         None)
                if v is not None and v.passed:
                    ET.SubElement(case, "system-out").text = (
                        f"missed ({'; '.join(r.failures)}) but the scenario passes: "
                        f"{v.met} of {len(v.runs)} seeds met it (needs {v.needed})")
                else:
                    fails += 1
                    ET.SubElement(case, "failure", message="; ".join(r.failures)).text = \
                        f"{'; '.join(r.failures)} ({r.reason}: {r.detail})"
            ET.SubElement(case, "properties")
            props = case.find("properties")
            for k, v in (("outcome", r.outcome), ("reason", r.reason),
                         ("sim_time_s", f"{r.sim_time:.3f}"), ("contacts", str(r.collisions))):
                ET.SubElement(props, "property", name=k, value=v)
        suite.set("failures", str(fails))
        suite.set("errors", str(errors))
        suite.set("skipped", str(skipped))
    return ET.tostring(root, encoding="unicode")
