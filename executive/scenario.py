"""Scripted stuck-robot scenarios: a YAML file describing a situation and what must happen.

The format is documented in ``docs/scenarios.md``. ``load_scenario`` parses and validates a file
(errors name the file and the field); ``run_scenario`` runs it against one tree in the simulator
and returns a ``ScenarioResult`` saying whether each expectation held.
"""

from __future__ import annotations

import copy
import math
import os
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import Any, Mapping

import numpy as np

from navcore.maps import MapError, OccupancyGrid, load_map
from navcore.safe_read import load_yaml
from navcore.params import suggest
from navcore.types import Pose2D

from executive.world import MovingObstacle, Shape, World


class ScenarioError(ValueError):
    """A scenario file is unreadable or malformed; the message names file and field."""


OUTCOMES = ("succeeded", "failed", "timeout")
TOP_KEYS = ("name", "description", "map", "robot", "params", "start", "goals", "objects",
            "moving", "phantoms", "faults", "time_limit", "expect", "expect_by_tree", "seed",
            "known_issue")
EXPECT_KEYS = ("outcome", "recoveries_fired", "recoveries_not_fired", "no_collision",
               "max_time", "solved")

# ASCII art: '#' wall, '.'/' ' free, '?' unknown, 'S' start, 'G' goal, 'o' an object that is in
# the world but not in the map (the robot only sees it with its laser), 'P' a phantom obstacle:
# in the costmap but not in the world (it stays until a recovery clears the costmap).
_ASCII_FREE = ". SGoP"


@dataclass
class Expectation:
    outcome: str | None = "succeeded"
    recoveries_fired: list[str] = field(default_factory=list)
    recoveries_not_fired: list[str] = field(default_factory=list)
    no_collision: bool = True
    max_time: float | None = None


@dataclass
class Scenario:
    name: str
    source: str
    grid: OccupancyGrid
    start: Pose2D
    goals: list[Pose2D]
    description: str = ""
    map_source: str = "inline"
    robot: dict[str, Any] = field(default_factory=dict)
    params: dict[str, dict[str, Any]] = field(default_factory=dict)
    objects: list[Shape] = field(default_factory=list)
    moving: list[MovingObstacle] = field(default_factory=list)
    phantoms: list[tuple[Shape, str]] = field(default_factory=list)
    faults: list[dict[str, Any]] = field(default_factory=list)
    time_limit: float = 120.0
    expect: Expectation = field(default_factory=Expectation)
    expect_by_tree: dict[str, Expectation] = field(default_factory=dict)
    seed: int = 0
    known_issue: str = ""  # why the stack does not meet the expectation yet (tests: xfail)

    def expectation_for(self, tree_name: str) -> Expectation:
        """The expectation for a tree (by file stem, e.g. ``move_base``), else the default one."""
        return self.expect_by_tree.get(tree_name, self.expect)


def _num(v: Any, where: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
        raise ScenarioError(f"{where}: expected a number, got {v!r}")
    return float(v)


def _pose(v: Any, where: str) -> Pose2D:
    if not isinstance(v, (list, tuple)) or len(v) not in (2, 3):
        raise ScenarioError(f"{where}: expected [x, y] or [x, y, yaw], got {v!r}")
    vals = [_num(x, where) for x in v]
    return Pose2D(vals[0], vals[1], vals[2] if len(vals) == 3 else 0.0)


def _shape(v: Any, where: str) -> Shape:
    if not isinstance(v, Mapping) or len([k for k in v if k in ("box", "circle")]) != 1:
        raise ScenarioError(f"{where}: expected {{box: [x0, y0, x1, y1]}} or "
                            f"{{circle: [x, y, r]}}, got {v!r}")
    kind = "box" if "box" in v else "circle"
    vals = v[kind]
    n = 4 if kind == "box" else 3
    if not isinstance(vals, (list, tuple)) or len(vals) != n:
        raise ScenarioError(f"{where}: {kind} needs {n} numbers, got {vals!r}")
    nums = tuple(_num(x, f"{where}: {kind}") for x in vals)
    if kind == "box":
        x0, y0, x1, y1 = nums
        nums = (min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1))
    elif nums[2] <= 0:
        raise ScenarioError(f"{where}: circle radius must be > 0, got {nums[2]}")
    return Shape(kind, nums)


def _ascii(text: str, resolution: float, where: str
           ) -> tuple[OccupancyGrid, dict[str, list[tuple[float, float]]], list[Shape]]:
    """Parse ASCII art; returns the map, marker cell centres by letter, and phantom-free objects
    ('o' cells become 1-cell boxes; adjacent cells are merged row-wise)."""
    lines = text.strip("\n").splitlines()
    if not lines:
        raise ScenarioError(f"{where}: empty drawing")
    h, w = len(lines), max(len(ln) for ln in lines)
    data = np.zeros((h, w), np.int16)
    markers: dict[str, list[tuple[float, float]]] = {"S": [], "G": [], "o": [], "P": []}
    boxes: dict[str, list[Shape]] = {"o": [], "P": []}
    for r, ln in enumerate(lines):
        row = h - 1 - r  # first line = top = max y
        run_start: dict[str, int | None] = {"o": None, "P": None}
        for c, ch in enumerate(ln.ljust(w) + " "):
            for k in ("o", "P"):
                if ch == k and run_start[k] is None:
                    run_start[k] = c
                elif ch != k and run_start[k] is not None:
                    c0 = run_start[k]
                    boxes[k].append(Shape("box", (c0 * resolution, row * resolution,
                                                  c * resolution, (row + 1) * resolution)))
                    run_start[k] = None
            if c >= w:
                break
            if ch == "#":
                data[row, c] = 100
            elif ch == "?":
                data[row, c] = -1
            elif ch not in _ASCII_FREE:
                raise ScenarioError(f"{where}: line {r + 1} column {c + 1}: unknown character "
                                    f"{ch!r} (use # . ? S G o P)")
            if ch in markers:
                markers[ch].append(((c + 0.5) * resolution, (row + 0.5) * resolution))
    return OccupancyGrid(data, resolution), markers, boxes["o"] + [
        Shape("phantom", b.values) for b in boxes["P"]]


def _expectation(v: Any, where: str) -> Expectation:
    if v is None:
        return Expectation()
    if not isinstance(v, Mapping):
        raise ScenarioError(f"{where}: expected a mapping, got {v!r}")
    for k in v:
        if k not in EXPECT_KEYS:
            raise ScenarioError(f"{where}: unknown key '{k}'{suggest(str(k), EXPECT_KEYS)}")
    e = Expectation()
    if "outcome" in v:
        if v["outcome"] not in OUTCOMES and v["outcome"] is not None:
            raise ScenarioError(f"{where}: outcome must be one of {', '.join(OUTCOMES)}, "
                                f"got {v['outcome']!r}")
        e.outcome = v["outcome"]
    for k in ("recoveries_fired", "recoveries_not_fired"):
        if k in v:
            if not isinstance(v[k], list) or not all(isinstance(x, str) for x in v[k]):
                raise ScenarioError(f"{where}: {k} must be a list of node types, got {v[k]!r}")
            setattr(e, k, list(v[k]))
    if "no_collision" in v:
        if not isinstance(v["no_collision"], bool):
            raise ScenarioError(f"{where}: no_collision must be true or false")
        e.no_collision = v["no_collision"]
    if "max_time" in v:
        e.max_time = _num(v["max_time"], f"{where}: max_time")
    return e


def scenario_from_mapping(doc: Any, source: str) -> Scenario:
    """Validate a parsed scenario document (see docs/scenarios.md)."""
    if not isinstance(doc, Mapping):
        raise ScenarioError(f"{source}: a scenario must be a mapping, got {type(doc).__name__}")
    for k in doc:
        if k not in TOP_KEYS:
            raise ScenarioError(f"{source}: unknown key '{k}'{suggest(str(k), TOP_KEYS)}")
    name = str(doc.get("name") or FsPath(source).stem)
    m = doc.get("map")
    if not isinstance(m, Mapping) or ("file" in m) == ("ascii" in m):
        raise ScenarioError(f"{source}: map: give either {{file: MAP.yaml}} or "
                            f"{{ascii: |, resolution: R}}")
    markers: dict[str, list[tuple[float, float]]] = {"S": [], "G": []}
    extra: list[Shape] = []
    if "file" in m:
        path = m["file"]
        if not os.path.isabs(path):
            path = os.path.join(os.path.dirname(os.path.abspath(source)), path)
        try:
            grid = load_map(path)
        except MapError as e:
            raise ScenarioError(f"{source}: map: {e}") from None
        map_source = path
    else:
        res = _num(m.get("resolution", 0.1), f"{source}: map: resolution")
        if res <= 0:
            raise ScenarioError(f"{source}: map: resolution must be > 0")
        if not isinstance(m["ascii"], str):
            raise ScenarioError(f"{source}: map: ascii must be a block of text")
        grid, markers, extra = _ascii(m["ascii"], res, f"{source}: map: ascii")
        map_source = "inline"

    def marker_pose(letter: str, key: str) -> Pose2D:
        pts = markers.get(letter, [])
        if len(pts) != 1:
            raise ScenarioError(f"{source}: {key}: not given, and the map has "
                                f"{len(pts)} '{letter}' markers (need exactly one)")
        return Pose2D(*pts[0], 0.0)

    if "start" in doc:
        start = _pose(doc["start"], f"{source}: start")
    else:
        start = marker_pose("S", "start")
    if "goals" in doc:
        g = doc["goals"]
        if not isinstance(g, list) or not g:
            raise ScenarioError(f"{source}: goals: expected a non-empty list of [x, y, yaw]")
        goals = [_pose(p, f"{source}: goals[{i}]") for i, p in enumerate(g)]
    else:
        goals = [marker_pose("G", "goals")]

    objects = [s for s in extra if s.kind != "phantom"]
    phantoms = [(Shape("box", s.values), "both") for s in extra if s.kind == "phantom"]
    for i, o in enumerate(doc.get("objects") or []):
        objects.append(_shape(o, f"{source}: objects[{i}]"))
    for i, p in enumerate(doc.get("phantoms") or []):
        where = f"{source}: phantoms[{i}]"
        which = p.get("costmap", "both") if isinstance(p, Mapping) else "both"
        if which not in ("local", "global", "both"):
            raise ScenarioError(f"{where}: costmap must be local, global or both, got {which!r}")
        q = {k: v for k, v in p.items() if k != "costmap"} if isinstance(p, Mapping) else p
        phantoms.append((_shape(q, where), which))
    moving = []
    for i, mv in enumerate(doc.get("moving") or []):
        where = f"{source}: moving[{i}]"
        if not isinstance(mv, Mapping):
            raise ScenarioError(f"{where}: expected a mapping")
        for k in mv:
            if k not in ("radius", "waypoints", "speed", "start_time", "loop"):
                raise ScenarioError(f"{where}: unknown key '{k}'"
                                    f"{suggest(str(k), ('radius', 'waypoints', 'speed', 'start_time', 'loop'))}")
        wps = mv.get("waypoints")
        if not isinstance(wps, list) or not wps:
            raise ScenarioError(f"{where}: waypoints: expected a list of [x, y]")
        pts = [(p.x, p.y) for p in (_pose(w, f"{where}: waypoints") for w in wps)]
        moving.append(MovingObstacle(_num(mv.get("radius", 0.25), f"{where}: radius"), pts,
                                     _num(mv.get("speed", 0.5), f"{where}: speed"),
                                     _num(mv.get("start_time", 0.0), f"{where}: start_time"),
                                     bool(mv.get("loop", False))))
    faults = doc.get("faults") or []
    if not isinstance(faults, list) or not all(isinstance(f, Mapping) for f in faults):
        raise ScenarioError(f"{source}: faults: expected a list of mappings")
    try:
        from hw.sim.faults import FaultError, fault_from_mapping
    except ImportError:
        fault_from_mapping = None
    if fault_from_mapping is not None:
        for i, f in enumerate(faults):
            try:
                fault_from_mapping(f, where=f"faults[{i}]")
            except FaultError as e:
                raise ScenarioError(f"{source}: {e}") from None
    robot = doc.get("robot") or {}
    params = doc.get("params") or {}
    if not isinstance(robot, Mapping) or not isinstance(params, Mapping):
        raise ScenarioError(f"{source}: robot and params must be mappings")
    time_limit = _num(doc.get("time_limit", 120.0), f"{source}: time_limit")
    if time_limit <= 0:
        raise ScenarioError(f"{source}: time_limit must be > 0")
    expect = _expectation(doc.get("expect"), f"{source}: expect")
    by_tree = {}
    ebt = doc.get("expect_by_tree") or {}
    if not isinstance(ebt, Mapping):
        raise ScenarioError(f"{source}: expect_by_tree: expected tree name -> expectation")
    for tree_name, e in ebt.items():
        merged = dict(doc.get("expect") or {})
        merged.update(e or {})
        by_tree[str(tree_name)] = _expectation(merged, f"{source}: expect_by_tree: {tree_name}")
    for key, pose in [("start", start)] + [(f"goals[{i}]", g) for i, g in enumerate(goals)]:
        cell = grid.world_to_map(pose.x, pose.y)
        if cell is None:
            raise ScenarioError(f"{source}: {key} ({pose.x:g}, {pose.y:g}) is outside the map")
    seed = doc.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int):
        raise ScenarioError(f"{source}: seed must be an integer")
    return Scenario(name=name, source=source, grid=grid, start=start, goals=goals,
                    description=str(doc.get("description", "")).strip(), map_source=map_source,
                    robot=dict(robot), params=copy.deepcopy(dict(params)), objects=objects,
                    moving=moving, phantoms=phantoms, faults=[dict(f) for f in faults],
                    time_limit=time_limit, expect=expect, expect_by_tree=by_tree, seed=seed,
                    known_issue=str(doc.get("known_issue") or "").strip())


def load_scenario(path: str | os.PathLike) -> Scenario:
    """Read and validate one scenario file."""
    path = str(path)
    doc = load_yaml(path, what="scenario", error=ScenarioError)
    return scenario_from_mapping(doc, path)


def scenario_files(paths: list[str]) -> list[str]:
    """Expand directories to their ``*.yaml`` files (sorted); keep files as given."""
    out: list[str] = []
    for p in paths:
        if os.path.isdir(p):
            out += sorted(str(q) for q in FsPath(p).glob("*.yaml"))
        else:
            out.append(p)
    return out


# --------------------------------------------------------------------------- running
@dataclass
class ScenarioResult:
    """One scenario run against one tree, and whether it met its expectation."""

    scenario: str
    tree: str
    outcome: str
    sim_time: float
    wall_time: float
    recoveries: list[str]
    collisions: int
    solved: bool
    passed: bool
    failures: list[str]
    reason: str = ""
    run_dir: str | None = None
    known_issue: str = ""
    distance: float = 0.0        # path driven (m)
    goals_reached: int = 0

    def as_dict(self) -> dict[str, Any]:
        return {"scenario": self.scenario, "tree": self.tree, "outcome": self.outcome,
                "sim_time_s": round(self.sim_time, 3), "wall_time_s": round(self.wall_time, 3),
                "recoveries": self.recoveries, "collisions": self.collisions,
                "solved": self.solved, "passed": self.passed, "failures": self.failures,
                "reason": self.reason, "run_dir": self.run_dir, "known_issue": self.known_issue}


def check_expectation(e: Expectation, outcome: str, sim_time: float, fired_types: list[str],
                      collisions: int) -> list[str]:
    """Every way the run missed its expectation (empty when it met it)."""
    failures = []
    if e.outcome is not None and outcome != e.outcome:
        failures.append(f"outcome: expected {e.outcome}, got {outcome}")
    for r in e.recoveries_fired:
        if r not in fired_types:
            failures.append(f"recovery {r} must fire but did not")
    for r in e.recoveries_not_fired:
        if r in fired_types:
            failures.append(f"recovery {r} fired but must not")
    if e.no_collision and collisions:
        failures.append(f"{collisions} collision(s)")
    if e.max_time is not None and sim_time > e.max_time:
        failures.append(f"took {sim_time:.1f} s, more than max_time {e.max_time:g} s")
    return failures


def scenario_config(scenario: Scenario, base: Any = None) -> Any:
    """The robot config for a scenario: the base config (a robot YAML path, or the
    ``ConfigSources`` of ROS files) with its robot/params overrides."""
    from executive.config import ConfigSources, config_from_mapping, merged_doc
    sources = base if isinstance(base, ConfigSources) else ConfigSources(config=base)
    doc, origins, notes = merged_doc(sources)
    base_name = os.path.basename(sources.config) if sources.config else (
        sources.describe() if sources.has_ros() else "robot.yaml")
    source = f"{scenario.source} (over {base_name})"
    doc.setdefault("robot", {})
    doc["robot"] = dict(doc["robot"] or {}, **scenario.robot)
    for key in scenario.robot:
        origins[("robot", key)] = source          # the scenario's values: named as such
    for ns, values in scenario.params.items():
        if not isinstance(values, Mapping):
            raise ScenarioError(f"{scenario.source}: params: {ns}: expected a mapping")
        doc[ns] = dict(doc.get(ns) or {}, **values)
        for key in values:
            origins[(ns, key)] = source
    return config_from_mapping(doc, source, origins, notes)


def run_scenario(scenario: Scenario, tree_path: str, record_dir: str | None = None,
                 config_path: str | None = None,
                 on_tick: Any = None, hardware: bool | str = False) -> ScenarioResult:
    """Run one scenario against one tree in the simulator (simulated clock); ``hardware=
    "emulated"`` runs it through the real drivers and device emulators (see build_mission)."""
    from navcore.clock import WallClock

    from executive.api import open_mission
    from executive.config import ConfigError
    from executive.recorder import Recorder
    wall = WallClock()
    tree_name = FsPath(tree_path).stem
    try:
        config = scenario_config(scenario, config_path)
    except ConfigError as e:
        raise ScenarioError(str(e)) from None
    world = World(scenario.objects, scenario.moving, scenario.phantoms, scenario.faults)
    recorder = Recorder(None)
    if record_dir is not None:
        from executive.run_folder import open_recorder
        recorder = open_recorder(record_dir, grid=scenario.grid)
    try:
        nav = open_mission(tree_path, config, scenario.grid, scenario.start, world=world,
                           seed=scenario.seed, recorder=recorder,
                           meta={"scenario": scenario.name}, hardware=hardware)
        nav.follow_waypoints(scenario.goals)
        result = nav.run(scenario.time_limit, on_tick=on_tick)
        if record_dir is not None:
            from executive.run_folder import finish
            finish(record_dir, nav.executive, result, scenario.grid, config.footprint(),
                   extra={"name": scenario.name, "tree": tree_path},
                   obstacles=[s.polygon() for s in scenario.objects],
                   phantoms=[shape.polygon() for shape, _ in scenario.phantoms])
        fired_types = [r["type"] for r in nav.executive.trace.recoveries]
        nav.close()      # drivers and emulators of hardware="emulated" too
    finally:
        recorder.close()
    e = scenario.expectation_for(tree_name)
    failures = check_expectation(e, result.outcome, result.sim_time, fired_types,
                                 result.collisions)
    return ScenarioResult(scenario.name, tree_name, result.outcome, result.sim_time, wall.now(),
                          fired_types, result.collisions,
                          result.outcome == "succeeded" and result.collisions == 0,
                          not failures, failures, result.reason, record_dir,
                          scenario.known_issue, result.distance, result.goals_reached)
