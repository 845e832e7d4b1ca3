"""Scenario files -> ``Scenario``: every field checked, every problem reported as file:line.

The format is documented in ``docs/scenarios.md``. ``scenario_from_source`` collects all the
problems of a file before raising (``ScenarioError.errors``); ``scenario_files`` expands folders
to their scenario files, leaving out map descriptors and robot profiles kept beside them.
"""

from __future__ import annotations

import copy
import os
from pathlib import Path as FsPath
from typing import Any, Mapping

import numpy as np

from navcore.error_codes import (BackUpError, ControllerError, DriveOnHeadingError,
                                 PlannerError, RecoveryError, SpinError, WaitError)
from navcore.maps import MapError, OccupancyGrid, load_map
from navcore.params import suggest
from navcore.types import Pose2D

from executive.scenarios.model import (EVENT_ACTIONS, OUTCOMES, Event, Expectation, Generate,
                                       MovingObstacle, Scenario, Shape, TimeRef, Window)
from executive.scenarios.fields import _Bad, _int, _mapping, _num, _shape
from executive.scenarios.generate import check_spec
from executive.scenarios.source import (Path_, Problems, ScenarioError, Source, read_source)

TOP_KEYS = ("name", "description", "map", "robot", "profile", "params", "start", "goals",
            "objects", "moving", "phantoms", "faults", "events", "time_limit", "wall_limit",
            "expect", "expect_by_tree", "seed", "seeds", "pass_at_least", "generate",
            "known_issue")
EXPECT_KEYS = ("outcome", "reason", "recoveries_fired", "recoveries_not_fired", "recoveries",
               "no_collision", "max_time", "solved", "final_pose", "goals_reached", "stopped",
               "slow_in", "reverse", "via", "avoid", "preempt_within")
RECOVERY_KEYS = ("all_of", "any_of", "none_of", "at_least", "at_most", "order")
MAP_KEYS = ("file", "data", "ascii", "resolution", "unknown")
EVENT_KEYS = ("at", "name") + EVENT_ACTIONS + ("to",)
# Nav2 error-code names an end reason may take, plus the executive's own ends.
CODE_ENUMS = (PlannerError, ControllerError, SpinError, BackUpError, DriveOnHeadingError,
              WaitError, RecoveryError)    # their value ranges do not overlap
REASON_NAMES = tuple(dict.fromkeys(
    [e.name for enum in CODE_ENUMS for e in enum if e.value]
    + ["TIME_LIMIT", "INTERNAL_ERROR", "TREE_FAILURE"]))

# ASCII art: '#' wall, '.'/' ' free, '?' unknown, 'S' start, 'G' goal, 'o' an object in the
# world but not in the map, 'P' a phantom obstacle (in the costmaps, not in the world).
_ASCII_FREE = ". SGoP"


# --------------------------------------------------------------------------- small checkers
def _list(pb: Problems, path: Path_, v: Any, nonempty: bool = False) -> list:
    if not isinstance(v, list):
        pb.add(path, f"expected a list, got {v!r}")
        raise _Bad
    if nonempty and not v:
        pb.add(path, "must not be empty")
        raise _Bad
    return v


def _names(pb: Problems, path: Path_, v: Any) -> list[str]:
    if isinstance(v, str):
        v = [v]
    if not isinstance(v, list) or not all(isinstance(x, str) and x for x in v):
        pb.add(path, f"expected a node type or name, or a list of them, got {v!r}")
        raise _Bad
    return list(v)


def _pose(pb: Problems, path: Path_, v: Any) -> Pose2D:
    if not isinstance(v, (list, tuple)) or len(v) not in (2, 3):
        pb.add(path, f"expected [x, y] or [x, y, yaw], got {v!r}")
        raise _Bad
    vals = [_num(pb, path + (i,), x) for i, x in enumerate(v)]
    return Pose2D(vals[0], vals[1], vals[2] if len(vals) == 3 else 0.0)


def _seeds(pb: Problems, path: Path_, v: Any) -> list[int]:
    """``1..10`` (inclusive), a list of integers, or one integer."""
    if isinstance(v, str) and ".." in v:
        a, _, b = v.partition("..")
        try:
            lo, hi = int(a.strip()), int(b.strip())
        except ValueError:
            pb.add(path, f"expected FIRST..LAST (e.g. 1..10), got {v!r}")
            raise _Bad from None
        if hi < lo or hi - lo >= 1000:
            pb.add(path, f"range {v!r} must go up and hold at most 1000 seeds")
            raise _Bad
        return list(range(lo, hi + 1))
    if isinstance(v, list) and v:
        out = [_int(pb, path + (i,), s, 0) for i, s in enumerate(v)]
        if len(set(out)) != len(out):
            pb.add(path, "a seed is listed twice")
            raise _Bad
        return out
    if isinstance(v, int) and not isinstance(v, bool):
        return [_int(pb, path, v, 0)]
    pb.add(path, f"expected FIRST..LAST, a list of seeds or one seed, got {v!r}")
    raise _Bad


def parse_seeds(text: str) -> list[int]:
    """Seeds from the command line (``1..10``, ``3`` or ``1,4,9``); ValueError if malformed."""
    pb = Problems(Source("--seeds", None))
    try:
        if "," in text:
            return _seeds(pb, (), [int(s) for s in text.split(",")])
        return _seeds(pb, (), text if ".." in text else int(text))
    except _Bad:
        raise ValueError(pb.errors[0].split(": ", 1)[-1]) from None


# --------------------------------------------------------------------------- maps
def _ascii(pb: Problems, path: Path_, text: str, resolution: float
           ) -> tuple[OccupancyGrid, dict[str, list[tuple[float, float]]], list[Shape]]:
    """Parse ASCII art: the map, marker cell centres by letter, and 'o'/'P' boxes (merged row
    by row; phantoms get kind 'phantom')."""
    lines = text.strip("\n").splitlines()
    if not lines:
        pb.add(path, "empty drawing")
        raise _Bad
    h, w = len(lines), max(len(ln) for ln in lines)
    if h * w > 4_000_000:
        pb.add(path, f"drawing of {w}x{h} characters is too large")
        raise _Bad
    data = np.zeros((h, w), np.int16)
    markers: dict[str, list[tuple[float, float]]] = {"S": [], "G": [], "o": [], "P": []}
    boxes: dict[str, list[Shape]] = {"o": [], "P": []}
    first = pb.src.line(path) or 0
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
                what = f"line {r + 1} column {c + 1}: unknown character {ch!r} (use # . ? S G o P)"
                if first:
                    pb.errors.append(f"{pb.src.name}:{first + 1 + r}: map.ascii: {what}")
                else:
                    pb.add(path, what)
                raise _Bad
            if ch in markers:
                markers[ch].append(((c + 0.5) * resolution, (row + 0.5) * resolution))
    return OccupancyGrid(data, resolution), markers, boxes["o"] + [
        Shape("phantom", b.values) for b in boxes["P"]]


def data_root(near: str) -> str | None:
    """The real-data folder: ``$NAVBT_DATA``, else a ``shared/data`` folder beside one of the
    folders above ``near`` (``../shared/data`` from a checkout); None when absent."""
    env = os.environ.get("NAVBT_DATA")
    if env:
        return env if os.path.isdir(env) else None
    d = os.path.dirname(os.path.abspath(near))
    while True:
        cand = os.path.join(d, "shared", "data")
        if os.path.isdir(os.path.join(cand, "maps")):
            return cand
        parent = os.path.dirname(d)
        if parent == d:
            return None
        d = parent


def _map(pb: Problems, m: Any, source: str
         ) -> tuple[OccupancyGrid | None, str, dict[str, list], list[Shape], bool, str]:
    """(grid or None when skipped, map source, markers, ascii objects, unknown solid, skip)."""
    path: Path_ = ("map",)
    m = _mapping(pb, path, m, MAP_KEYS)
    given = [k for k in ("file", "data", "ascii") if k in m]
    if len(given) != 1:
        pb.add(path, "give one of {file: MAP.yaml}, {data: maps/NAME.yaml} (the real-data "
                     "folder) or {ascii: |, resolution: R}")
        raise _Bad
    unknown = m.get("unknown", "free")
    if unknown not in ("free", "solid"):
        pb.add(path + ("unknown",), f"must be free or solid, got {unknown!r}")
        unknown = "free"
    solid = unknown == "solid"
    if "ascii" in m:
        res = _num(pb, path + ("resolution",), m.get("resolution", 0.1), 0.0, strict_lo=True)
        if not isinstance(m["ascii"], str):
            pb.add(path + ("ascii",), "must be a block of text")
            raise _Bad
        grid, markers, extra = _ascii(pb, path + ("ascii",), m["ascii"], res)
        return grid, "inline", markers, extra, solid, ""
    if "resolution" in m:
        pb.add(path + ("resolution",), "only for ascii maps (a map file gives its own)")
    key = "file" if "file" in m else "data"
    rel = m[key]
    if not isinstance(rel, str) or not rel:
        pb.add(path + (key,), f"expected a file name, got {rel!r}")
        raise _Bad
    if key == "data":
        root = data_root(source)
        if root is None:
            return None, rel, {}, [], solid, (f"real data not found for map {rel} (set "
                                              "NAVBT_DATA or place shared/data beside the "
                                              "checkout)")
        full = os.path.join(root, rel)
    else:
        full = rel if os.path.isabs(rel) else os.path.join(
            os.path.dirname(os.path.abspath(source)), rel)
    try:
        grid = load_map(full)
    except (MapError, OSError, ValueError) as e:
        pb.add(path + (key,), str(e))
        raise _Bad from None
    return grid, full, {}, [], solid, ""


# --------------------------------------------------------------------------- expectations
def _outcomes(pb: Problems, path: Path_, v: Any) -> tuple[str, ...] | None:
    if v is None:
        return None
    vals = v if isinstance(v, list) else [v]
    for x in vals:
        if x not in OUTCOMES:
            pb.add(path, f"outcome must be one of {', '.join(OUTCOMES)} (or a list of them), "
                         f"got {x!r}")
            raise _Bad
    return tuple(vals)


def _reasons(pb: Problems, path: Path_, v: Any) -> tuple[str, ...] | None:
    if v is None:
        return None
    vals = v if isinstance(v, list) else [v]
    for x in vals:
        if x not in REASON_NAMES:
            pb.add(path, f"unknown reason {x!r}{suggest(str(x), REASON_NAMES)}; one of "
                         f"{', '.join(REASON_NAMES)}")
            raise _Bad
    return tuple(vals)


def _counts(pb: Problems, path: Path_, v: Any) -> dict[str, int]:
    if isinstance(v, int) and not isinstance(v, bool):
        return {"": _int(pb, path, v, 0)}
    d = _mapping(pb, path, v)
    out = {}
    for k, n in d.items():
        if not isinstance(k, str) or not k:
            pb.add(path, f"expected node type or name -> count, got key {k!r}")
            raise _Bad
        out["" if k == "total" else k] = _int(pb, path + (k,), n, 0)
    return out


def _timeref(pb: Problems, path: Path_, v: Any, events: set[str]) -> TimeRef:
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return TimeRef(at=_num(pb, path, v, 0.0))
    if v == "end":
        return TimeRef(event="end")
    if isinstance(v, str) and v in events:
        return TimeRef(event=v)
    if isinstance(v, Mapping):
        d = _mapping(pb, path, v, ("event", "delay"))
        ev = d.get("event")
        if ev != "end" and ev not in events:
            pb.add(path + ("event",), f"no event named {ev!r}"
                                      f"{suggest(str(ev), sorted(events))}")
            raise _Bad
        return TimeRef(event=ev, delay=_num(pb, path + ("delay",), d.get("delay", 0.0)))
    pb.add(path, f"expected seconds, an event name, 'end' or {{event: NAME, delay: S}}, "
                 f"got {v!r}")
    raise _Bad


def _expectation(pb: Problems, path: Path_, v: Any, events: set[str]) -> Expectation:
    e = Expectation()
    if v is None:
        return e
    d = _mapping(pb, path, v, EXPECT_KEYS)

    def field(key: str, build: Any) -> None:
        if key in d:
            try:
                build(d[key], path + (key,))
            except _Bad:
                pass
    field("outcome", lambda x, p: setattr(e, "outcome", _outcomes(pb, p, x)))
    field("reason", lambda x, p: setattr(e, "reason", _reasons(pb, p, x)))
    field("recoveries_fired", lambda x, p: setattr(e, "recoveries_fired", _names(pb, p, x)))
    field("recoveries_not_fired",
          lambda x, p: setattr(e, "recoveries_not_fired", _names(pb, p, x)))

    def recoveries(x: Any, p: Path_) -> None:
        r = _mapping(pb, p, x, RECOVERY_KEYS)
        for k, attr in (("all_of", "recoveries_fired"), ("none_of", "recoveries_not_fired"),
                        ("any_of", "recoveries_any_of"), ("order", "recoveries_order")):
            if k in r:
                try:
                    getattr(e, attr).extend(_names(pb, p + (k,), r[k]))
                except _Bad:
                    pass
        for k in ("at_least", "at_most"):
            if k in r:
                try:
                    setattr(e, f"recoveries_{k}", _counts(pb, p + (k,), r[k]))
                except _Bad:
                    pass
    field("recoveries", recoveries)

    def boolean(x: Any, p: Path_) -> None:
        if not isinstance(x, bool):
            pb.add(p, f"must be true or false, got {x!r}")
            raise _Bad
        e.no_collision = x
    field("no_collision", boolean)
    field("solved", lambda x, p: None)  # accepted for old files: 'solved' is measured
    field("max_time", lambda x, p: setattr(e, "max_time", _num(pb, p, x, 0.0, strict_lo=True)))
    field("preempt_within",
          lambda x, p: setattr(e, "preempt_within", _num(pb, p, x, 0.0)))

    def final_pose(x: Any, p: Path_) -> None:
        f = _mapping(pb, p, x, ("of", "within", "yaw"))
        of = f.get("of", "goal")
        target = None if of == "goal" else _pose(pb, p + ("of",), of)
        within = _num(pb, p + ("within",), f.get("within", 0.25), 0.0)
        yaw = _num(pb, p + ("yaw",), f["yaw"], 0.0) if "yaw" in f else None
        e.final_pose = (target, within, yaw)
    field("final_pose", final_pose)

    def goals_reached(x: Any, p: Path_) -> None:
        if isinstance(x, int) and not isinstance(x, bool):
            n = _int(pb, p, x, 0)
            e.goals_reached = (n, n)
            return
        g = _mapping(pb, p, x, ("at_least", "at_most"))
        lo = _int(pb, p + ("at_least",), g.get("at_least", 0), 0)
        hi = _int(pb, p + ("at_most",), g["at_most"], 0) if "at_most" in g else None
        e.goals_reached = (lo, hi)
    field("goals_reached", goals_reached)

    def stopped(x: Any, p: Path_) -> None:
        for i, w in enumerate(x if isinstance(x, list) else [x]):
            q = p + (i,) if isinstance(x, list) else p
            try:
                wd = _mapping(pb, q, w, ("from", "until", "v", "w"))
                if "from" not in wd:
                    pb.add(q, "needs 'from' (and 'until', default: end)")
                    continue
                e.stopped.append(Window(_timeref(pb, q + ("from",), wd["from"], events),
                                        _timeref(pb, q + ("until",), wd.get("until", "end"),
                                                 events),
                                        _num(pb, q + ("v",), wd.get("v", 0.02), 0.0),
                                        _num(pb, q + ("w",), wd.get("w", 0.05), 0.0)))
            except _Bad:
                pass
    field("stopped", stopped)

    def slow_in(x: Any, p: Path_) -> None:
        for i, s in enumerate(_list(pb, p, x)):
            try:
                sd = _mapping(pb, p + (i,), s)
                if "max_speed" not in sd:
                    pb.add(p + (i,), "needs max_speed (m/s)")
                    continue
                e.slow_in.append((_shape(pb, p + (i,), {k: v for k, v in sd.items()
                                                         if k != "max_speed"}),
                                  _num(pb, p + (i, "max_speed"), sd["max_speed"], 0.0)))
            except _Bad:
                pass
    field("slow_in", slow_in)

    def reverse(x: Any, p: Path_) -> None:
        r = _mapping(pb, p, x, ("max_speed", "max_duration"))
        if "max_speed" in r:
            e.max_reverse_speed = _num(pb, p + ("max_speed",), r["max_speed"], 0.0)
        if "max_duration" in r:
            e.max_reverse_time = _num(pb, p + ("max_duration",), r["max_duration"], 0.0)
    field("reverse", reverse)

    def regions(attr: str) -> Any:
        def build(x: Any, p: Path_) -> None:
            for i, s in enumerate(_list(pb, p, x)):
                try:
                    getattr(e, attr).append(_shape(pb, p + (i,), s))
                except _Bad:
                    pass
        return build
    field("via", regions("via"))
    field("avoid", regions("avoid"))
    return e


# --------------------------------------------------------------------------- events
def _events(pb: Problems, v: Any, objects: dict[str, Shape], phantoms: set[str]) -> list[Event]:
    from hw.sim.faults import FAULT_KINDS, FaultError, fault_from_mapping
    out: list[Event] = []
    names: set[str] = set()
    for i, ev in enumerate(_list(pb, ("events",), v)):
        p: Path_ = ("events", i)
        try:
            d = _mapping(pb, p, ev, EVENT_KEYS)
            actions = [k for k in d if k in EVENT_ACTIONS]
            if len(actions) != 1:
                pb.add(p, f"give exactly one of {', '.join(EVENT_ACTIONS)}")
                continue
            action = actions[0]
            name = d.get("name", f"event{i}")
            if not isinstance(name, str) or not name or name == "end":
                pb.add(p + ("name",), f"expected a name, got {name!r}")
                continue
            if name in names:
                pb.add(p + ("name",), f"two events are named {name!r}")
            names.add(name)
            e = Event(name, action, None)
            if "at" not in d:
                pb.add(p, "needs 'at': seconds, or {after_recovery: TYPE|NAME|any, delay: S}"
                          " or {while_recovery: TYPE|NAME|any, delay: S}")
                continue
            at = d["at"]
            if isinstance(at, Mapping):
                a = _mapping(pb, p + ("at",), at, ("after_recovery", "while_recovery", "delay"))
                which = [k for k in ("after_recovery", "while_recovery") if k in a]
                if len(which) != 1:
                    pb.add(p + ("at",), "give one of after_recovery or while_recovery")
                    continue
                rec = a[which[0]]
                if not isinstance(rec, str) or not rec:
                    pb.add(p + ("at", which[0]), f"expected a recovery type, name or 'any', "
                                                 f"got {rec!r}")
                    continue
                setattr(e, which[0], rec)
                e.delay = _num(pb, p + ("at", "delay"), a.get("delay", 0.0), 0.0)
            else:
                e.at = _num(pb, p + ("at",), at, 0.0)
            arg = d[action]
            q = p + (action,)
            if action in ("goal", "add_goal"):
                e.arg = _pose(pb, q, arg)
            elif action == "add":
                e.arg = _shape(pb, q, arg)
                if e.arg.name:
                    objects[e.arg.name] = e.arg
            elif action == "remove":
                if arg not in objects:
                    pb.add(q, f"no object named {arg!r}{suggest(str(arg), sorted(objects))}")
                    continue
                e.arg = arg
            elif action == "fault":
                f = dict(_mapping(pb, q, arg))
                f.setdefault("start", 0.0)
                try:
                    fault_from_mapping(f, where="fault")
                except FaultError as err:
                    pb.add(q, str(err).removeprefix("fault: "))
                    continue
                e.arg = f
            elif action == "end_fault":
                if arg not in FAULT_KINDS:
                    pb.add(q, f"unknown fault kind {arg!r}{suggest(str(arg), FAULT_KINDS)}")
                    continue
                e.arg = arg
            elif action == "phantom":
                which = arg.get("costmap", "both") if isinstance(arg, Mapping) else "both"
                if which not in ("local", "global", "both"):
                    pb.add(q + ("costmap",), f"must be local, global or both, got {which!r}")
                    continue
                e.arg = (_shape(pb, q, arg, ("costmap",)), which)
                if e.arg[0].name:
                    phantoms.add(e.arg[0].name)
            elif action in ("move_phantom", "remove_phantom"):
                if arg not in phantoms:
                    pb.add(q, f"no phantom named {arg!r}{suggest(str(arg), sorted(phantoms))}")
                    continue
                e.arg = arg
                if action == "move_phantom":
                    if "to" not in d:
                        pb.add(p, "move_phantom needs 'to: {box: ...}'")
                        continue
                    e.to = _shape(pb, p + ("to",), d["to"])
            elif action == "set":
                s = _mapping(pb, q, arg)
                for ns, values in s.items():
                    _mapping(pb, q + (ns,), values)
                e.arg = s
            if "to" in d and action != "move_phantom":
                pb.add(p + ("to",), "only for move_phantom")
            out.append(e)
        except _Bad:
            pass
    return out


def _generate(pb: Problems, v: Any) -> Generate | None:
    d = _mapping(pb, ("generate",), v, ("seed", "clutter", "patrol", "start_goal"))
    g = Generate()
    if "seed" in d:
        g.seed = _int(pb, ("generate", "seed"), d["seed"], 0)
    for key in ("clutter", "patrol", "start_goal"):
        if key in d:
            try:
                spec = check_spec(pb, ("generate", key), key, d[key])
            except _Bad:
                continue
            if key == "clutter":
                g.clutter = spec
            else:
                setattr(g, key, spec)
    return g


# --------------------------------------------------------------------------- the scenario
def scenario_from_source(src: Source, check_config: bool = False) -> Scenario:
    """Validate a parsed scenario; raise ScenarioError listing every problem (file:line)."""
    pb = Problems(src)
    doc = src.doc
    source = src.name
    if not isinstance(doc, Mapping):
        pb.add((), f"a scenario must be a mapping, got {type(doc).__name__}")
        pb.raise_if_any()
    for k in doc:
        if k not in TOP_KEYS:
            pb.add((k,), f"unknown key '{k}'{suggest(str(k), TOP_KEYS)}")
    name = doc.get("name") or FsPath(source).stem
    if not isinstance(name, str):
        pb.add(("name",), f"expected a name, got {name!r}")
        name = FsPath(source).stem
    grid = None
    markers: dict[str, list] = {}
    extra: list[Shape] = []
    map_source, solid, skip = "inline", False, ""
    try:
        grid, map_source, markers, extra, solid, skip = _map(pb, doc.get("map"), source)
    except _Bad:
        pass

    def marker_pose(letter: str, key: str) -> Pose2D | None:
        pts = markers.get(letter, [])
        if len(pts) != 1:
            if grid is not None and not (doc.get("generate") or {}):
                pb.add((key,), f"not given, and the map has {len(pts)} '{letter}' markers "
                               "(need exactly one)")
            return None
        return Pose2D(*pts[0], 0.0)

    def attempt(build: Any, default: Any = None) -> Any:
        try:
            return build()
        except _Bad:
            return default
    start = attempt(lambda: _pose(pb, ("start",), doc["start"])) if "start" in doc \
        else marker_pose("S", "start")
    goals: list[Pose2D] = []
    if "goals" in doc:
        g = attempt(lambda: _list(pb, ("goals",), doc["goals"], nonempty=True), [])
        goals = [p for p in (attempt(lambda i=i, q=q: _pose(pb, ("goals", i), q))
                             for i, q in enumerate(g)) if p is not None]
    else:
        mp = marker_pose("G", "goals")
        goals = [mp] if mp is not None else []
    objects = [s for s in extra if s.kind != "phantom"]
    phantoms = [(Shape("box", s.values), "both") for s in extra if s.kind == "phantom"]
    for i, o in enumerate(attempt(lambda: _list(pb, ("objects",), doc.get("objects") or []), [])):
        s = attempt(lambda: _shape(pb, ("objects", i), o))
        if s is not None:
            objects.append(s)
    for i, p in enumerate(attempt(lambda: _list(pb, ("phantoms",), doc.get("phantoms") or []),
                                  [])):
        which = p.get("costmap", "both") if isinstance(p, Mapping) else "both"
        if which not in ("local", "global", "both"):
            pb.add(("phantoms", i, "costmap"), f"must be local, global or both, got {which!r}")
            continue
        s = attempt(lambda: _shape(pb, ("phantoms", i), p, ("costmap",)))
        if s is not None:
            phantoms.append((s, which))
    moving = []
    mkeys = ("radius", "waypoints", "speed", "start_time", "loop")
    for i, mv in enumerate(attempt(lambda: _list(pb, ("moving",), doc.get("moving") or []), [])):
        p = ("moving", i)
        try:
            d = _mapping(pb, p, mv, mkeys)
            wps = _list(pb, p + ("waypoints",), d.get("waypoints"), nonempty=True)
            pts = [(q.x, q.y) for q in (_pose(pb, p + ("waypoints", j), w)
                                        for j, w in enumerate(wps))]
            moving.append(MovingObstacle(
                _num(pb, p + ("radius",), d.get("radius", 0.25), 0.0, strict_lo=True), pts,
                _num(pb, p + ("speed",), d.get("speed", 0.5), 0.0, strict_lo=True),
                _num(pb, p + ("start_time",), d.get("start_time", 0.0)),
                bool(d.get("loop", False))))
        except _Bad:
            pass
    faults = []
    from hw.sim.faults import FaultError, fault_from_mapping
    for i, f in enumerate(attempt(lambda: _list(pb, ("faults",), doc.get("faults") or []), [])):
        try:
            fault_from_mapping(f, where="fault")
            faults.append(dict(f))
        except FaultError as e:
            pb.add(("faults", i), str(e).removeprefix("fault: "))
    named_objects = {s.name: s for s in objects if s.name}
    named_phantoms = {s.name for s, _ in phantoms if s.name}
    events = attempt(lambda: _events(pb, doc.get("events") or [], named_objects,
                                     named_phantoms), [])
    event_names = {e.name for e in events}
    robot = doc.get("robot") or {}
    params = doc.get("params") or {}
    if not isinstance(robot, Mapping):
        pb.add(("robot",), f"expected a mapping of robot parameters, got {robot!r}")
        robot = {}
    if not isinstance(params, Mapping) or not all(isinstance(v, Mapping) or v is None
                                                   for v in params.values()):
        pb.add(("params",), "expected namespace -> mapping of parameters")
        params = {}
    profile = ""
    if "profile" in doc:
        from executive.scenarios.profiles import find_profile
        try:
            profile = find_profile(doc["profile"], source)
        except ScenarioError as e:
            pb.add(("profile",), str(e))
    time_limit = attempt(lambda: _num(pb, ("time_limit",), doc.get("time_limit", 120.0), 0.0,
                                      strict_lo=True), 120.0)
    wall_limit = attempt(lambda: _num(pb, ("wall_limit",), doc["wall_limit"], 0.0,
                                      strict_lo=True)) if "wall_limit" in doc else None
    expect = attempt(lambda: _expectation(pb, ("expect",), doc.get("expect"), event_names),
                     Expectation())
    by_tree = {}
    ebt = doc.get("expect_by_tree") or {}
    if not isinstance(ebt, Mapping):
        pb.add(("expect_by_tree",), "expected tree name -> expectation")
        ebt = {}
    for tree_name, e in ebt.items():
        if e is not None and not isinstance(e, Mapping):
            pb.add(("expect_by_tree", tree_name), f"expected a mapping, got {e!r}")
            continue
        merged = dict(doc.get("expect") or {}) if isinstance(doc.get("expect"), Mapping) else {}
        merged.update(e or {})
        # lines: the tree's own keys where given, else the shared expect's
        x = attempt(lambda: _expectation(pb, ("expect_by_tree", tree_name), merged,
                                         event_names))
        if x is not None:
            by_tree[str(tree_name)] = x
    seed = attempt(lambda: _int(pb, ("seed",), doc.get("seed", 0), 0), 0)
    seeds = attempt(lambda: _seeds(pb, ("seeds",), doc["seeds"])) if "seeds" in doc else None
    pass_at_least = None
    if "pass_at_least" in doc:
        pass_at_least = attempt(lambda: _int(pb, ("pass_at_least",), doc["pass_at_least"], 1))
        if pass_at_least is not None and seeds is not None and pass_at_least > len(seeds):
            pb.add(("pass_at_least",), f"{pass_at_least} is more than the {len(seeds)} seeds")
    generate = attempt(lambda: _generate(pb, doc["generate"])) if "generate" in doc else None
    known, known_by = "", {}
    ki = doc.get("known_issue")
    if isinstance(ki, Mapping):
        for t, why in ki.items():
            if not isinstance(why, str) or not why.strip():
                pb.add(("known_issue", t), "expected the measured reason (text)")
            else:
                known_by[str(t)] = why.strip()
    elif ki is not None and not isinstance(ki, str):
        pb.add(("known_issue",), "expected the measured reason, or tree name -> reason")
    elif ki:
        known = ki.strip()
    if grid is not None:
        poses = ([("start", start)] if start is not None else []) + [
            (f"goals[{i}]", g) for i, g in enumerate(goals)]
        for key, pose in poses:
            if grid.world_to_map(pose.x, pose.y) is None:
                pb.add((key.split("[")[0],) + ((int(key[6:-1]),) if "[" in key else ()),
                       f"({pose.x:g}, {pose.y:g}) is outside the map")
        gen_goals = generate is not None and (generate.patrol or generate.start_goal)
        if not goals and not gen_goals and "goals" not in doc and not pb.errors:
            pb.add(("goals",), "no goals")
    pb.raise_if_any()
    if grid is None:   # a real map that is absent here: a stand-in so the scenario can report
        grid = OccupancyGrid(np.zeros((2, 2), np.int16), 1.0)
    sc = Scenario(name=name, source=source, grid=grid, start=start or Pose2D(),
                  goals=goals, description=str(doc.get("description", "")).strip(),
                  map_source=map_source, unknown_solid=solid, profile=profile,
                  robot=copy.deepcopy(dict(robot)),
                  params={k: dict(v or {}) for k, v in copy.deepcopy(dict(params)).items()},
                  objects=objects, moving=moving, phantoms=phantoms, faults=faults,
                  events=events, time_limit=time_limit, wall_limit=wall_limit, expect=expect,
                  expect_by_tree=by_tree, seed=seed, seeds=seeds, pass_at_least=pass_at_least,
                  generate=generate, known_issue=known, known_issues=known_by, skip=skip,
                  lines={k: v for k, v in src.lines.items()
                         if k and k[0] in ("params", "robot")})
    if check_config:
        from executive.scenarios.profiles import config_problems
        errs = config_problems(sc, src)
        if errs:
            raise ScenarioError("\n".join(errs), errs)
    return sc


def scenario_from_mapping(doc: Any, source: str) -> Scenario:
    """Validate a parsed scenario document given without line numbers (see docs/scenarios.md)."""
    return scenario_from_source(Source(source, doc))


def load_scenario(path: str | os.PathLike, check_config: bool = False) -> Scenario:
    """Read and validate one scenario file (``check_config``: also build its merged robot
    config, so that parameter errors are reported now)."""
    return scenario_from_source(read_source(path), check_config=check_config)


def file_kind(path: str) -> str:
    """'scenario', 'map' (a map_server YAML: has ``image``) or 'profile' (``robot_profile``),
    judged from the top-level keys; 'scenario' when unreadable (the check reports why)."""
    try:
        src = read_source(path)
    except ScenarioError:
        return "scenario"
    if isinstance(src.doc, Mapping):
        if "image" in src.doc and "map" not in src.doc:
            return "map"
        if "robot_profile" in src.doc:
            return "profile"
    return "scenario"


def scenario_files(paths: list[str]) -> list[str]:
    """Expand folders to their scenario ``*.yaml`` files (sorted; map YAMLs and robot profiles
    beside them left out); files given one by one are kept as given."""
    out: list[str] = []
    for p in paths:
        if os.path.isdir(p):
            out += [q for q in sorted(str(q) for q in FsPath(p).glob("*.yaml"))
                    if file_kind(q) == "scenario"]
        else:
            out.append(p)
    return out
