"""Sweep files: which scenarios, seeds and trees to run over which parameter points.

A sweep file (docs/sweeps.md) names scenarios (paths and globs, relative to the file), seeds
(``0..9`` or a list), trees, an optional base robot config, and the points: ``grid:`` axes are
crossed, ``zip:`` axes advance together (one axis, crossed with the grid), ``points:`` lists
whole points. A key with a ``/`` is a tree port (``Subtree/Node.port``, node by name or type);
any other key is a robot-config parameter (``DWAPlannerROS.sim_time``,
``global_costmap.inflation_layer.inflation_radius``). Every run is one (scenario, seed, tree,
point). Every error names the file and line, and every error is found before anything runs.
"""

from __future__ import annotations

import glob
import hashlib
import itertools
import json
import math
import os
from dataclasses import dataclass, field
from typing import Any, Mapping

from navcore.params import suggest

from executive.errors import ExecutiveError
from executive.param_files import parse_yaml_lines

TOP_KEYS = ("name", "description", "scenarios", "seeds", "trees", "config", "launch", "args",
            "params", "nav2_params", "grid", "zip", "points", "time_limit", "search", "trials",
            "sampler_seed")
SEARCH_KEYS = ("low", "high", "log", "step", "choices")
MAX_RUNS = 1_000_000


class SweepError(ExecutiveError, ValueError):
    """A sweep file is unreadable or malformed; the message says ``file:line: what``."""


@dataclass(frozen=True)
class RunTask:
    """One run of a sweep: everything a worker needs, as plain values (it crosses processes)."""

    scenario: str            # path as resolved from the sweep file
    seed: int
    tree: str                # path
    point: tuple[tuple[str, Any], ...]   # sorted (key, value) pairs
    config: Any = None       # the base robot config: None (bundled), a path or ConfigSources
    time_limit: float | None = None

    @property
    def run_id(self) -> str:
        """Stable identity of the run: the same run has the same id in every sweep and resume."""
        body = json.dumps([os.path.basename(self.scenario), _rel(self.scenario), self.seed,
                           os.path.basename(self.tree), list(map(list, self.point)),
                           self.time_limit, _config_id(self.config)], sort_keys=True,
                          default=repr)
        return hashlib.sha256(body.encode()).hexdigest()[:20]


def _config_id(config: Any) -> Any:
    """What names a base config in a run id: file names and launch args, not folders."""
    if config is None:
        return None
    if isinstance(config, str):
        return os.path.basename(config)
    return [os.path.basename(config.config or ""), os.path.basename(config.launch or ""),
            sorted(config.args.items()), [os.path.basename(p) for p in config.params],
            [os.path.basename(p) for p in config.nav2_params]]


def _rel(path: str) -> str:
    """The last two path parts: enough to tell files apart, independent of the checkout's place."""
    parts = os.path.normpath(path).split(os.sep)
    return "/".join(parts[-2:])


@dataclass(frozen=True)
class SearchDim:
    """One dimension of an Optuna search (``mission tune``)."""

    key: str
    low: float | None = None
    high: float | None = None
    log: bool = False
    step: float | None = None
    choices: tuple[Any, ...] = ()
    integer: bool = False


@dataclass
class SweepSpec:
    name: str
    source: str
    scenarios: list[str]
    seeds: list[int] | None
    trees: list[str]
    config: Any          # None, a robot YAML path, or ConfigSources (launch / rosparam / Nav2)
    points: list[dict[str, Any]]
    time_limit: float | None = None
    search: list[SearchDim] = field(default_factory=list)
    trials: int = 20
    sampler_seed: int = 0
    description: str = ""

    def tasks(self, points: list[dict[str, Any]] | None = None) -> list[RunTask]:
        """Every run of the sweep, in a fixed order (scenario, seed, tree, point)."""
        from executive.scenario import load_scenario
        out = []
        for path in self.scenarios:
            seeds = self.seeds if self.seeds is not None else [load_scenario(path).seed]
            for seed in seeds:
                for tree in self.trees:
                    for p in (self.points if points is None else points):
                        out.append(RunTask(path, int(seed), tree, tuple(sorted(p.items())),
                                           self.config, self.time_limit))
        return out


class _Where:
    """Error messages with ``file:line`` from a path of keys."""

    def __init__(self, source: str, lines: dict[tuple, int]) -> None:
        self.source, self.lines = source, lines

    def __call__(self, path: tuple, what: str) -> SweepError:
        p = path
        while p and p not in self.lines:
            p = p[:-1]
        return SweepError(f"{self.source}:{self.lines.get(p, 1)}: {what}")


# --------------------------------------------------------------------------- parsing
def parse_seeds(v: Any, err: Any = None, path: tuple = ("seeds",)) -> list[int]:
    """``3``, ``[1, 2, 5]`` or ``"0..9"`` (inclusive) -> a list of seeds."""
    def bad(what: str) -> SweepError:
        return err(path, what) if err else SweepError(what)
    if isinstance(v, bool):
        raise bad(f"seeds: expected an integer, a list or 'A..B', got {v!r}")
    if isinstance(v, int):
        return [v]
    if isinstance(v, str) and ".." in v:
        a, _, b = v.partition("..")
        try:
            lo, hi = int(a), int(b)
        except ValueError:
            raise bad(f"seeds: {v!r} is not 'A..B' with integers") from None
        if hi < lo or hi - lo >= 100_000:
            raise bad(f"seeds: {v!r} must be A..B with A <= B and fewer than 100000 seeds")
        return list(range(lo, hi + 1))
    if isinstance(v, list) and v and all(isinstance(s, int) and not isinstance(s, bool)
                                         for s in v):
        return list(v)
    raise bad(f"seeds: expected an integer, a non-empty list of integers or 'A..B', got {v!r}")


def _paths(v: Any, base: str, key: str, err: _Where, globbing: bool) -> list[str]:
    items = v if isinstance(v, list) else [v]
    if not items or not all(isinstance(x, str) and x for x in items):
        raise err((key,), f"{key}: expected a path or a list of paths, got {v!r}")
    out: list[str] = []
    for i, item in enumerate(items):
        path = item if os.path.isabs(item) else os.path.join(base, item)
        if globbing and any(c in item for c in "*?["):
            found = sorted(glob.glob(path))
            if not found:
                raise err((key, i) if isinstance(v, list) else (key,),
                          f"{key}: '{item}' matches no file")
            out += found
        elif os.path.isdir(path) and globbing:
            out += sorted(str(p) for p in glob.glob(os.path.join(path, "*.yaml")))
        elif not os.path.isfile(path):
            raise err((key, i) if isinstance(v, list) else (key,), f"{key}: no such file '{item}'")
        else:
            out.append(path)
    return list(dict.fromkeys(os.path.normpath(p) for p in out))


def _axis_values(v: Any, key: str, path: tuple, err: _Where) -> list[Any]:
    if not isinstance(v, list) or not v:
        raise err(path, f"{key}: expected a non-empty list of values, got {v!r}")
    for i, x in enumerate(v):
        if isinstance(x, float) and not math.isfinite(x):
            raise err(path + (i,), f"{key}: value {x!r} is not finite")
        if not isinstance(x, (int, float, str, bool, list)):
            raise err(path + (i,), f"{key}: value {x!r} must be a number, string, bool or list")
    return list(v)


def _check_key(key: Any, path: tuple, err: _Where) -> str:
    if not isinstance(key, str) or not key:
        raise err(path, f"parameter key must be a string, got {key!r}")
    if "/" in key:
        tree_part, _, port = key.rpartition(".")
        if not port or "/" not in tree_part or not all(tree_part.split("/")):
            raise err(path, f"'{key}': a tree port is 'Subtree/Node.port'")
    elif "." not in key:
        raise err(path, f"'{key}': a parameter is 'namespace.name' (e.g. DWAPlannerROS.sim_time)")
    return key


def expand_points(doc: Mapping[str, Any], err: _Where,
                  origins: list[dict[str, tuple]] | None = None) -> list[dict[str, Any]]:
    """The points of a sweep: ``points`` x product(grid axes) x zip (advancing together).
    ``origins``, when given, gets for each point the key path where each of its values is
    written (``("grid", key, i)``, ``("zip", key, i)``, ``("points", i, key)``)."""
    axes: list[list[tuple[dict[str, Any], dict[str, tuple]]]] = []
    grid = doc.get("grid") or {}
    if not isinstance(grid, Mapping):
        raise err(("grid",), "grid: expected a mapping of parameter -> list of values")
    for k, v in grid.items():
        key = _check_key(k, ("grid", k), err)
        axes.append([({key: x}, {key: ("grid", k, i)})
                     for i, x in enumerate(_axis_values(v, key, ("grid", k), err))])
    z = doc.get("zip")
    if z is not None:
        if not isinstance(z, Mapping) or not z:
            raise err(("zip",), "zip: expected a mapping of parameter -> list of values")
        lists = {_check_key(k, ("zip", k), err): _axis_values(v, k, ("zip", k), err)
                 for k, v in z.items()}
        lengths = {len(v) for v in lists.values()}
        if len(lengths) != 1:
            raise err(("zip",), f"zip: every list must have the same length, got "
                                f"{', '.join(f'{k}: {len(v)}' for k, v in lists.items())}")
        n = lengths.pop()
        axes.append([({k: v[i] for k, v in lists.items()}, {k: ("zip", k, i) for k in lists})
                     for i in range(n)])
    base_points: list[tuple[dict[str, Any], dict[str, tuple]]] = [({}, {})]
    if "points" in doc:
        pts = doc["points"]
        if not isinstance(pts, list) or not pts:
            raise err(("points",), "points: expected a non-empty list of mappings")
        base_points = []
        for i, p in enumerate(pts):
            if not isinstance(p, Mapping):
                raise err(("points", i), f"points[{i}]: expected a mapping, got {p!r}")
            base_points.append(({_check_key(k, ("points", i, k), err): v for k, v in p.items()},
                                {k: ("points", i, k) for k in p}))
    out: list[dict[str, Any]] = []
    n_total = len(base_points)
    for a in axes:
        n_total *= len(a)
    if n_total > MAX_RUNS:
        raise err(("grid",), f"the sweep has {n_total} points, more than {MAX_RUNS}")
    for bp, bwhere in base_points:
        for combo in itertools.product(*axes):
            p, where = dict(bp), dict(bwhere)
            for part, part_where in combo:
                for k in part:
                    if k in p:
                        raise err(part_where[k], f"'{k}' is set by more than one axis")
                p.update(part)
                where.update(part_where)
            out.append(p)
            if origins is not None:
                origins.append(where)
    return out


def _search(doc: Mapping[str, Any], err: _Where) -> list[SearchDim]:
    s = doc.get("search")
    if s is None:
        return []
    if not isinstance(s, Mapping) or not s:
        raise err(("search",), "search: expected a mapping of parameter -> {low, high} or "
                               "{choices: [...]}")
    dims = []
    for k, v in s.items():
        key = _check_key(k, ("search", k), err)
        where = ("search", k)
        if not isinstance(v, Mapping):
            raise err(where, f"search: {key}: expected {{low: A, high: B}} or {{choices: [...]}}")
        for kk in v:
            if kk not in SEARCH_KEYS:
                raise err(where + (kk,), f"search: {key}: unknown key '{kk}'"
                                         f"{suggest(str(kk), SEARCH_KEYS)}")
        if "choices" in v:
            ch = _axis_values(v["choices"], key, where + ("choices",), err)
            dims.append(SearchDim(key, choices=tuple(ch)))
            continue
        lo, hi = v.get("low"), v.get("high")
        for name, x in (("low", lo), ("high", hi)):
            if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
                raise err(where + (name,), f"search: {key}: {name} must be a finite number")
        if hi <= lo:
            raise err(where, f"search: {key}: high ({hi}) must be above low ({lo})")
        log = v.get("log", False)
        if not isinstance(log, bool) or (log and lo <= 0):
            raise err(where, f"search: {key}: log must be true/false, and needs low > 0")
        step = v.get("step")
        if step is not None and (isinstance(step, bool) or not isinstance(step, (int, float))
                                 or not step > 0):
            raise err(where, f"search: {key}: step must be a number > 0")
        integer = all(isinstance(x, int) for x in (lo, hi)) and (step is None
                                                                  or isinstance(step, int))
        dims.append(SearchDim(key, float(lo), float(hi), log, step, (), integer))
    return dims


def _config(doc: Mapping[str, Any], base: str, err: _Where) -> Any:
    """``config:`` (a robot YAML) and/or ROS files: ``launch:`` with ``args:``, ``params:``
    (``FILE[:NAMESPACE]``), ``nav2_params:``; paths relative to the sweep file."""
    from executive.config import ConfigSources
    robot = None
    if doc.get("config") is not None:
        robot = _paths(doc["config"], base, "config", err, globbing=False)[0]
    ros = [k for k in ("launch", "args", "params", "nav2_params") if doc.get(k) is not None]
    if not ros:
        return robot
    launch = None
    if doc.get("launch") is not None:
        launch = _paths(doc["launch"], base, "launch", err, globbing=False)[0]
    args = doc.get("args") or {}
    if not isinstance(args, Mapping):
        raise err(("args",), "args: expected a mapping of launch argument -> value")
    params = []
    for i, item in enumerate(doc.get("params") or []):
        if not isinstance(item, str):
            raise err(("params", i), "params: expected FILE or FILE:NAMESPACE strings")
        f, sep, ns = item.partition(":")
        path = _paths(f, base, "params", err, globbing=False)[0]
        params.append(path + sep + ns)
    nav2 = _paths(doc["nav2_params"], base, "nav2_params", err, globbing=False) \
        if doc.get("nav2_params") is not None else []
    return ConfigSources(config=robot, launch=launch, args={str(k): str(v)
                                                            for k, v in args.items()},
                         params=params, nav2_params=nav2)


def load_sweep(path: str | os.PathLike) -> SweepSpec:
    """Read and check a sweep file, including every point's robot config and tree ports."""
    path = str(path)
    try:
        if not os.path.isfile(path):
            raise SweepError(f"{path}: no such sweep file")
        if os.path.getsize(path) > 4 * 1024 * 1024:
            raise SweepError(f"{path}: sweep file larger than 4 MiB")
        with open(path, "rb") as f:
            raw = f.read()
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise SweepError(f"{path}: not UTF-8 text (byte {e.start})") from None
    except OSError as e:
        raise SweepError(f"{path}: cannot read sweep file ({e.strerror or e})") from None
    doc, lines = parse_yaml_lines(text, path, error=SweepError)
    err = _Where(path, lines)
    if not isinstance(doc, Mapping):
        raise err((), "a sweep file must be a mapping")
    for k in doc:
        if k not in TOP_KEYS:
            raise err((k,), f"unknown key '{k}'{suggest(str(k), TOP_KEYS)}")
    base = os.path.dirname(os.path.abspath(path))
    if "scenarios" not in doc:
        raise err((), "scenarios: missing (a path, a glob or a list of them)")
    scenarios = _paths(doc["scenarios"], base, "scenarios", err, globbing=True)
    seeds = parse_seeds(doc["seeds"], err) if "seeds" in doc else None
    if "trees" in doc:
        trees = _paths(doc["trees"], base, "trees", err, globbing=False)
    else:
        from executive.tree_loader import shipped_tree
        trees = [shipped_tree("smach_recovery")]
    config = _config(doc, base, err)
    time_limit = doc.get("time_limit")
    if time_limit is not None and (isinstance(time_limit, bool)
                                   or not isinstance(time_limit, (int, float))
                                   or not 0 < time_limit < 1e6):
        raise err(("time_limit",), f"time_limit: expected seconds > 0, got {time_limit!r}")
    trials = doc.get("trials", 20)
    if isinstance(trials, bool) or not isinstance(trials, int) or not 1 <= trials <= 100_000:
        raise err(("trials",), f"trials: expected an integer 1..100000, got {trials!r}")
    sampler_seed = doc.get("sampler_seed", 0)
    if isinstance(sampler_seed, bool) or not isinstance(sampler_seed, int):
        raise err(("sampler_seed",), "sampler_seed: expected an integer")
    origins: list[dict[str, tuple]] = []
    points = expand_points(doc, err, origins)
    search = _search(doc, err)
    spec = SweepSpec(name=str(doc.get("name") or os.path.splitext(os.path.basename(path))[0]),
                     source=path, scenarios=scenarios, seeds=seeds, trees=trees, config=config,
                     points=points, time_limit=None if time_limit is None else float(time_limit),
                     search=search, trials=trials, sampler_seed=sampler_seed,
                     description=str(doc.get("description") or "").strip())
    check_spec(spec, err, origins)
    return spec


def check_spec(spec: SweepSpec, err: _Where,
               origins: list[dict[str, tuple]] | None = None) -> None:
    """Load every scenario and tree, and apply every point (and the search bounds) to them, so
    that a bad name or value is reported now with its line, not after an hour of running.
    ``origins`` (from ``expand_points``) lets the error name the line of the bad value."""
    from executive.tree_loader import TreeLoadError, load_tree_file
    from executive.scenario import ScenarioError, load_scenario

    from executive.sweeps.apply import ApplyError, apply_point, tree_with_ports
    scenarios = []
    for i, s in enumerate(spec.scenarios):
        try:
            scenarios.append(load_scenario(s))
        except ScenarioError as e:
            raise err(("scenarios",), f"scenario: {e}") from None
    for t in spec.trees:
        try:
            load_tree_file(t, namespace="/sweep_check")
        except TreeLoadError as e:
            raise err(("trees",), f"tree: {e}") from None
    probes: list[tuple[tuple, dict[str, Any], dict[str, tuple]]] = []
    for i, p in enumerate(spec.points):
        where = origins[i] if origins is not None else {}
        probes.append((where.get(next(iter(p), ""), ()), p, where))
    for d in spec.search:
        # a value between the bounds too: a float range on an integer parameter fails only there
        for v in (d.choices or (d.low, d.high, (d.low + d.high) / 2)):
            if d.integer and v is not None:
                v = int(v)
            probes.append((("search", d.key), {d.key: v}, {}))
    seen: set[str] = set()
    for path, p, where in probes:
        key = json.dumps(sorted(p.items()), default=repr)
        if key in seen:
            continue
        seen.add(key)
        for sc in scenarios[:1] or []:
            try:
                apply_point(sc, p, spec.config)
            except ApplyError as e:
                raise err(_culprit(p, where, path, lambda q: apply_point(sc, q, spec.config)),
                          str(e)) from None
        for t in spec.trees:
            try:
                tree_with_ports(t, p)
            except ApplyError as e:
                raise err(_culprit(p, where, path, lambda q: tree_with_ports(t, q)),
                          str(e)) from None


def _culprit(p: Mapping[str, Any], where: Mapping[str, tuple], default: tuple,
             apply: Any) -> tuple:
    """Where the value of ``p`` is written that fails on its own (``apply`` raises ApplyError
    for it alone); ``default`` when none does (the values fail only together)."""
    from executive.sweeps.apply import ApplyError
    for k, v in p.items():
        if k in where:
            try:
                apply({k: v})
            except ApplyError:
                return where[k]
    return default
