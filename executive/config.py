"""The robot config: ROS parameter namespaces per component, from a navbt YAML or ROS files.

A user pastes their ``costmap_common_params.yaml``, ``dwa_local_planner_params.yaml``, amcl and
move_base parameters under the namespaces ROS uses, or brings the ROS files themselves
(``ConfigSources``: a roslaunch file, rosparam files into namespaces, a Nav2 parameter file; read
by executive.ros_launch / ros_params / nav2_params), and they mean the same here. Every value is
checked against the declaring component's ``Param`` table at load time, with ROS's own leniency
(deprecated names, clamps, keys ROS ignores: ros_params.LENIENCY); every error is reported at
once, each naming file:line, namespace and parameter, before any robot moves. The namespaces
owned here are ``robot`` (body and devices), ``move_base``, ``safety`` and ``behavior_server``;
the others come from the component that declares them (found lazily, see
``COMPONENT_NAMESPACES``). The costmaps' footprint is the robot's unless ``robot`` gives one.
The tables of the owned namespaces are in executive.config_params; the costmap namespaces are
checked by executive.config_costmaps.
"""
from __future__ import annotations

import importlib
import math
import os
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import Any, Callable, Iterable, Mapping

from navcore.params import Param, ParameterError, Parameters, suggest
from navcore.safe_read import parse_yaml
from executive.config_params import (BEHAVIOR_SERVER_NODES, MOVE_BASE_IN_TREE, MOVE_BASE_PARAMS,
                                     OWN_NAMESPACES, ROBOT_PARAMS)
from executive.config_params import SAFETY_PARAMS  # noqa: F401 (executive.safety reads it here)
from executive.config_costmaps import ERROR_PATH, check_costmap, deep_copy
from executive.errors import ExecutiveError
from executive.param_files import Findings, Note, ParamsError, read_yaml
from executive.ros_params import LENIENCY


class ConfigError(ExecutiveError, ValueError):
    """The robot config is unreadable or has bad values; the message lists every error, each
    naming file (and line when known), namespace and parameter. ``notes`` holds every finding
    (errors, warnings, ignored keys) of the load."""

    def __init__(self, message: str, notes: list[Note] | None = None) -> None:
        super().__init__(message)
        self.notes = list(notes or [])


DEFAULT_CONFIG = FsPath(__file__).resolve().parent / "data" / "robot.yaml"

# ROS namespace -> (module, attribute) of the component's Param table. Resolved lazily so that the
# executive does not import every component just to read a file, and so a component that is not
# installed only matters when its namespace is used.
COMPONENT_NAMESPACES: dict[str, tuple[tuple[str, str], ...]] = {
    # costmaps carry nested layer namespaces: checked by building one
    # (config_costmaps.check_costmap)
    "global_costmap": (),
    "local_costmap": (),
    "NavfnROS": (("navcore.planners.navfn", "NAVFN_PARAMS"),),
    "GlobalPlanner": (("navcore.planners.global_planner", "GLOBAL_PLANNER_PARAMS"),
                      ("navcore.planners.global_planner", "PARAMS")),
    "CarrotPlanner": (("navcore.planners.carrot_planner", "CARROT_PLANNER_PARAMS"),
                      ("navcore.planners.carrot_planner", "PARAMS")),
    "DWAPlannerROS": (("navcore.controllers.dwa", "DWA_PARAMS"),
                      ("navcore.controllers.dwa", "PARAMS")),
    "TrajectoryPlannerROS": (("navcore.controllers.trajectory_rollout", "TR_PARAMS"),),
    "amcl": (("navcore.localization.amcl_params", "AMCL_PARAMS"),),
    "route_server": (("navcore.route.graph", "ROUTE_SERVER_PARAMS"),),
}

# The simulated body (kinematics, limits, odometry noise, laser/imu/battery sections) is declared
# by the simulator itself (hw/sim/config.py) and validated by its ``robot_config``; the footprint
# defaults to robot.footprint.
SIM_NAMESPACE = "sim"

# Keys a ROS file carries in a namespace that are structure rather than parameters here.
STRUCTURAL_KEYS = frozenset({"plugins"})


def _component_specs(namespace: str) -> tuple[Param, ...] | None:
    """The Param table declared by the component behind ``namespace``, or None if unavailable."""
    for module_name, attr in COMPONENT_NAMESPACES[namespace]:
        try:
            module = importlib.import_module(module_name)
        except ImportError:
            continue
        specs = getattr(module, attr, None)
        if specs is not None:
            return tuple(specs)
    return None


# Tests and other engineers can point a namespace at a table without the module layout above.
SPEC_OVERRIDES: dict[str, Callable[[], tuple[Param, ...]]] = {}


def specs_for(namespace: str) -> tuple[Param, ...] | None:
    if namespace in SPEC_OVERRIDES:
        return SPEC_OVERRIDES[namespace]()
    if namespace in OWN_NAMESPACES:
        return OWN_NAMESPACES[namespace]
    if namespace in COMPONENT_NAMESPACES:
        return _component_specs(namespace)
    return None


@dataclass
class RobotConfig:
    """A loaded, validated robot config.

    ``robot``, ``move_base`` and ``safety`` are live ``Parameters``; ``namespaces`` holds the raw
    (validated) mapping of every component namespace present, and ``parameters`` the
    ``Parameters`` objects built for those whose component declares its table.
    """

    source: str
    robot: Parameters
    move_base: Parameters
    safety: Parameters
    namespaces: dict[str, dict[str, Any]] = field(default_factory=dict)
    parameters: dict[str, Parameters] = field(default_factory=dict)
    devices: dict[str, Any] = field(default_factory=dict)  # robot.devices for hw.devices
    origins: dict[tuple, str] = field(default_factory=dict)  # key path -> "file:line"
    report: list[Note] = field(default_factory=list)  # warnings, notes, ignored keys of the load

    def ns(self, name: str) -> dict[str, Any]:
        """The user's values for a component namespace ({} when absent)."""
        return dict(self.namespaces.get(name, {}))

    def footprint(self) -> list[tuple[float, float]]:
        """Footprint polygon; a 16-gon of ``robot_radius`` when the footprint list is empty."""
        fp = self.robot.footprint
        if fp:
            return [(float(p[0]), float(p[1])) for p in fp]
        r = self.robot.robot_radius
        return [(r * math.cos(2 * math.pi * i / 16), r * math.sin(2 * math.pi * i / 16))
                for i in range(16)]

    def circumscribed_radius(self) -> float:
        return max(math.hypot(x, y) for x, y in self.footprint())

    def control_period(self) -> float:
        return 1.0 / self.move_base.controller_frequency

    def global_planner_namespace(self) -> str:
        return {"navfn/NavfnROS": "NavfnROS", "global_planner/GlobalPlanner": "GlobalPlanner",
                "carrot_planner/CarrotPlanner": "CarrotPlanner"}[self.move_base.base_global_planner]

    def local_planner_namespace(self) -> str:
        return {"base_local_planner/TrajectoryPlannerROS": "TrajectoryPlannerROS",
                "dwa_local_planner/DWAPlannerROS": "DWAPlannerROS"}[
            self.move_base.base_local_planner]

    def port_defaults(self) -> dict[str, dict[str, Any]]:
        """Node type -> {port: value} for ports the tree leaves unset: the ``behavior_server``
        values given (Nav2's server parameters are these nodes' ports here). Plus, under
        "Type/name" keys, the ``move_base`` values that differ from move_base's defaults for the
        nodes trees/move_base.yaml names after them (move_base_port_values)."""
        out: dict[str, dict[str, Any]] = move_base_port_values(self.move_base)
        given = self.namespaces.get("behavior_server") or {}
        if not given:
            return out
        from behaviors.registry import node_classes
        for name, cls in node_classes().items():
            if name in BEHAVIOR_SERVER_NODES:
                ports = cls.input_ports()
                values = {k: float(v) for k, v in given.items() if k in ports}
                if values:
                    out[name] = values
        return out

    def all_parameters(self) -> dict[str, Parameters]:
        """Every live Parameters object by namespace (what SetParameters may change)."""
        out = {"robot": self.robot, "move_base": self.move_base, "safety": self.safety}
        out.update(self.parameters)
        return out


def move_base_port_values(mb: Parameters) -> dict[str, dict[str, Any]]:
    """"Type/name" -> {port: value} for the move_base parameters set to other than move_base's
    defaults, in the units of the ports of the nodes trees/move_base.yaml names after them; the
    tree loader gives them to that node even over the tree's literal (which is move_base's
    default), so the move_base namespace drives the tree as it drives move_base."""
    changed = {p.name for p in mb.specs() if getattr(mb, p.name) != p.default}
    table: list[tuple[str, str, str, Any]] = [
        ("controller_patience", "FollowPath/ControllerPatience", "failure_tolerance",
         float(mb.controller_patience)),
        # move_base restarts its recovery list at the first valid command after a recovery; the
        # tree counts navigation that ran longer than controller_patience (+5 s) as that
        ("controller_patience", "RecoveryNode/MoveBase", "reset_after",
         float(mb.controller_patience) + 5.0),
        ("planner_patience", "Timeout/PlannerPatience", "msec",
         int(round(mb.planner_patience * 1000.0))),
        # move_base plans once and retries max_planning_retries more times
        ("max_planning_retries", "RetryUntilSuccessful/MaxPlanningRetries", "num_attempts",
         -1 if mb.max_planning_retries < 0 else int(mb.max_planning_retries) + 1),
        ("oscillation_timeout", "IsOscillating/OscillationCheck", "oscillation_timeout",
         float(mb.oscillation_timeout)),
        ("oscillation_distance", "IsOscillating/OscillationCheck", "oscillation_distance",
         float(mb.oscillation_distance)),
        ("conservative_reset_dist", "ClearCostmapExceptRegion/conservative_reset",
         "reset_distance", float(mb.conservative_reset_dist)),
        # without recovery behaviours move_base aborts at the first failure
        ("recovery_behavior_enabled", "RecoveryNode/MoveBase", "number_of_retries",
         4 if mb.recovery_behavior_enabled else 0),
    ]
    out: dict[str, dict[str, Any]] = {}
    for param, key, port, value in table:
        if param in changed:
            out.setdefault(key, {})[port] = value
    return out


def _check_footprint(fp: list, where: str) -> str | None:
    """An error message for a bad footprint polygon, or None."""
    if fp == []:
        return None
    if len(fp) < 3:
        return f"{where}: parameter 'footprint' needs at least 3 points, got {len(fp)}"
    for i, p in enumerate(fp):
        if (not isinstance(p, (list, tuple)) or len(p) != 2
                or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in p)):
            return f"{where}: parameter 'footprint' point {i} must be [x, y], got {p!r}"
    return None


def footprint_list(value: Any) -> Any:
    """A footprint as ROS allows it (a list, or the string "[[x, y], ...]") as a list of [x, y];
    anything unparsable is returned unchanged for the checks to report."""
    if isinstance(value, str):
        try:
            parsed = parse_yaml(value, "footprint", error=ValueError)
        except ValueError:
            return value
        return [] if parsed is None else parsed
    return value


def _checked(ns: str, specs: tuple[Param, ...], body: Mapping[str, Any], report: Findings,
             ignore: Iterable[str] = STRUCTURAL_KEYS) -> Parameters:
    """Parameters of ``specs`` from ``body``; every bad key is reported (not only the first)
    and left at its default."""
    good: dict[str, Any] = {}
    by_name = {s.name: s for s in specs}
    for key, value in body.items():
        if key in ignore:
            continue
        where = report.where((ns, key))
        spec = by_name.get(key)
        extra = LENIENCY[ns].known() if ns in LENIENCY else ()
        if spec is None:
            report.notes.append(Note("error", where, f"{ns}: unknown parameter '{key}'"
                                     f"{suggest(str(key), tuple(by_name) + extra)}"))
            continue
        try:
            good[key] = spec.check(value, ns)
        except ParameterError as e:
            report.notes.append(Note("error", where, str(e)))
    return Parameters(specs, good, where=f"{report.source}: {ns}", ignore=ignore)


def _lenient(ns: str, body: dict[str, Any], report: Findings) -> dict[str, Any]:
    """``body`` with ROS's own leniency for ``ns`` applied (renames, clamps, ignored keys). A
    clamp that would still leave the value unacceptable here is not applied: the error then
    names the value the user wrote."""
    if ns not in LENIENCY:
        return body
    out, found = LENIENCY[ns].apply(body)
    specs = {s.name: s for s in (specs_for(ns) or ())}
    for kind, level, key, text in found:
        new = LENIENCY[ns].renamed.get(key)
        if kind == "renamed" and new is not None and (ns, key) in report.origins:
            report.origins.setdefault((ns, new), report.origins[(ns, key)])
        if kind == "clamped" and key in specs and key in body:
            try:
                specs[key].check(out[key])
            except ParameterError:
                out[key] = body[key]
                continue
        report.add(level, (ns, key), f"{ns}: {text}")
    return out


def _footprint_of(body: Mapping[str, Any]) -> tuple[list, float] | None:
    """(polygon, radius) a costmap namespace declares, or None when it declares neither."""
    fp = footprint_list(body.get("footprint")) if "footprint" in body else None
    if isinstance(fp, list) and fp:
        return fp, 0.0
    r = body.get("robot_radius")
    if isinstance(r, (int, float)) and not isinstance(r, bool) and r > 0:
        return [], float(r)
    return None


def _resolve_footprint(doc: Mapping[str, Any], robot: dict[str, Any], report: Findings) -> None:
    """One footprint: robot.footprint / robot_radius when given, else the local costmap's, else
    the global costmap's (ROS puts it there), so the simulated body, the costmaps and the
    recoveries all use the same outline."""
    if "footprint" in robot:
        robot["footprint"] = footprint_list(robot["footprint"])
        return
    if "robot_radius" in robot:
        robot["footprint"] = []
        return
    for cm in ("local_costmap", "global_costmap"):
        body = doc.get(cm)
        found = _footprint_of(body) if isinstance(body, Mapping) else None
        if found is None:
            continue
        fp, r = found
        key = "footprint" if fp else "robot_radius"
        robot["footprint"] = fp
        if not fp:
            robot["robot_radius"] = r
        report.origins.setdefault(("robot", "footprint"), report.where((cm, key)))
        other = "global_costmap" if cm == "local_costmap" else None
        if other and isinstance(doc.get(other), Mapping):
            theirs = _footprint_of(doc[other])
            if theirs is not None and theirs != found:
                report.add("warning", (other, key), f"{other} declares another footprint than "
                           f"{cm}; the robot's body and recoveries use {cm}'s")
        return


def _misplaced(key: str, known: Iterable[str]) -> str:
    """The hint for a top-level key that is not a namespace: where a ROS parameter of that name
    belongs (a costmap file pasted without its namespace), else the closest namespace."""
    from executive.ros_params import COSTMAP_ONLY, SEARCHED_BY_COSTMAPS
    if key in COSTMAP_ONLY or key in SEARCHED_BY_COSTMAPS:
        return (f": '{key}' is a costmap parameter; put it under global_costmap: / "
                "local_costmap: (or load the ROS file with --params FILE:local_costmap)")
    if key in {p.name for p in MOVE_BASE_PARAMS}:
        return (f": '{key}' is a move_base parameter; put it under move_base: (or load the "
                "ROS file with --params FILE)")
    return suggest(key, known)


def _note_move_base_in_tree(body: Mapping[str, Any], report: Findings) -> None:
    """move_base parameters that the tree decides here: a value other than move_base's default
    (which trees/move_base.yaml already has) is listed as ignored, saying where to set it."""
    defaults = {p.name: p.default for p in MOVE_BASE_PARAMS}
    for key, value in body.items():
        where = MOVE_BASE_IN_TREE.get(key)
        if where is None:
            continue
        if value != defaults[key]:
            report.add("ignored", ("move_base", key), f"move_base: {key} = {value!r} is not "
                       f"applied: in navbt the tree decides it ({where}; trees/move_base.yaml has "
                       f"move_base's default {defaults[key]!r})")


def _note_safety_clips(values: Mapping[str, Parameters], report: Findings) -> None:
    """A note for each local planner limit the safety gate's hard limit is tighter than (the
    gate clips such commands; ROS has no gate, so a ROS file does not say)."""
    safety = values.get("safety")
    for ns in ("DWAPlannerROS", "TrajectoryPlannerROS"):
        planner = values.get(ns)
        if planner is None or safety is None:
            continue
        for key in ("max_vel_x", "max_vel_theta"):
            mine, gate = abs(getattr(planner, key, 0.0)), getattr(safety, key)
            if mine > gate:
                report.add("note", (ns, key), f"safety: {key} = {gate:g} clips {ns}.{key} = "
                           f"{mine:g} (the gate's hard limit; raise safety.{key} if the base "
                           "allows)")


def config_from_mapping(doc: Mapping[str, Any], source: str = "<config>",
                        origins: Mapping[tuple, str] | None = None,
                        notes: list[Note] | None = None) -> RobotConfig:
    """Validate a parsed robot config; raise ConfigError listing every error (each naming
    file:line when ``origins`` knows it, else ``source``, with namespace and parameter).

    ``origins`` maps key paths (``("DWAPlannerROS", "vy_samples")``) to ``file:line``;
    ``notes`` are findings from reading the sources, kept in the config's ``report``."""
    report = Findings(source, origins or {}, list(notes or []))
    if doc is None:
        doc = {}
    if not isinstance(doc, Mapping):
        raise ConfigError(f"{source}: the robot config must be a mapping of namespaces, "
                          f"got {type(doc).__name__}")
    known = set(OWN_NAMESPACES) | set(COMPONENT_NAMESPACES) | {SIM_NAMESPACE}
    device_map: dict[str, Any] = {}
    values: dict[str, Parameters] = {}
    raw: dict[str, dict[str, Any]] = {}
    for ns, body in doc.items():
        if ns not in known:
            report.add("error", (ns,), f"unknown namespace '{ns}'{_misplaced(str(ns), known)}")
            continue
        if body is None:
            body = {}
        if not isinstance(body, Mapping):
            report.add("error", (ns,), f"{ns}: must be a mapping of parameters, got {body!r}")
            continue
        body = _lenient(ns, dict(body), report)
        if ns == "robot" and isinstance(body.get("devices"), Mapping):
            # devices: {base: URL, laser: URL, imu: ...} (hw/devices.py) means real hardware
            dev = dict(body.pop("devices"))
            body["devices"] = "hw"
            for k, v in dev.items():
                if k not in ("base", "laser", "imu"):
                    report.add("error", (ns, "devices", k), f"robot: devices: unknown device "
                               f"'{k}'{suggest(str(k), ('base', 'laser', 'imu'))}")
                    continue
                url = v.get("url") if isinstance(v, Mapping) else v
                if not isinstance(url, str):
                    report.add("error", (ns, "devices", k), f"robot: devices: {k} must be a URL "
                               f"string or {{url: URL, ...}}, got {v!r}")
                    continue
                if k in ("base", "laser"):
                    body[k] = url
            device_map = dev
        if ns == "robot":
            _resolve_footprint(doc, body, report)
        raw[ns] = body
        if ns in (SIM_NAMESPACE, "global_costmap", "local_costmap"):
            continue  # checked below, once the footprint is known
        specs = specs_for(ns)
        if specs is None:
            continue  # component not installed: its own constructor validates when built
        values[ns] = _checked(ns, specs, body, report)
        if ns == "move_base":
            _note_move_base_in_tree({k: getattr(values[ns], k) for k in body
                                     if k in values[ns]}, report)
    if "robot" not in raw:
        robot_body: dict[str, Any] = {}
        _resolve_footprint(doc, robot_body, report)
        if robot_body:
            raw["robot"] = robot_body
            values["robot"] = _checked("robot", ROBOT_PARAMS, robot_body, report)
    for ns in OWN_NAMESPACES:
        if ns not in values:
            values[ns] = Parameters(OWN_NAMESPACES[ns], {}, where=f"{source}: {ns}")
    robot = values["robot"]
    bad = _check_footprint(robot.footprint, "robot")
    if bad:
        report.add("error", ("robot", "footprint"), bad)
    elif not robot.footprint and robot.robot_radius <= 0:
        report.add("error", ("robot",), "robot: give a footprint or a robot_radius > 0")
    if robot.devices not in ("sim", "hw"):
        report.add("error", ("robot", "devices"), f"robot: parameter 'devices' must be 'sim', "
                   f"'hw' or a mapping {{base: URL, laser: URL}}, got {robot.devices!r}")
    raw.setdefault(SIM_NAMESPACE, {})
    sim_values = dict(raw[SIM_NAMESPACE])
    if "footprint" not in sim_values and ("robot", "footprint") in report.origins:
        report.origins[(SIM_NAMESPACE, "footprint")] = report.origins[("robot", "footprint")]
    sim_values.setdefault("footprint", robot.footprint)
    if not robot.footprint:
        sim_values.setdefault("robot_radius", robot.robot_radius)
    raw[SIM_NAMESPACE] = sim_values
    try:
        from hw.sim.config import robot_config
    except ImportError:
        robot_config = None
    if robot_config is not None and not bad:
        try:
            robot_config(sim_values)
        except (ParameterError, ValueError) as e:
            m = ERROR_PATH.match(str(e))
            path = tuple(m.group(1).split(".")[1:]) + (m.group(2),) if m else ()
            report.add("error", (SIM_NAMESPACE,) + path, str(e))
    for ns in ("global_costmap", "local_costmap"):
        if ns in raw:
            raw[ns] = check_costmap(raw[ns], ns, robot.footprint, robot.robot_radius, report)
    _note_safety_clips(values, report)
    amcl = values.get("amcl")
    if amcl is not None and amcl.min_particles > amcl.max_particles:
        report.add("error", ("amcl", "min_particles"), f"amcl: min_particles "
                   f"({amcl.min_particles}) must not exceed max_particles ({amcl.max_particles})")
    errors = report.errors()
    if errors:
        raise ConfigError("\n".join(str(n) for n in errors), report.notes)
    component_params = {ns: p for ns, p in values.items() if ns not in OWN_NAMESPACES}
    return RobotConfig(source, values["robot"], values["move_base"], values["safety"], raw,
                       component_params, device_map, report.origins, report.notes)


def load_config(path: str | os.PathLike | None = None) -> RobotConfig:
    """Read and validate a robot config YAML (the bundled default when ``path`` is None)."""
    path = FsPath(path) if path is not None else DEFAULT_CONFIG
    doc, origins = read_config_lines(path)
    return config_from_mapping(doc, str(path), origins)


def read_config_doc(path: str | os.PathLike) -> Any:
    """The YAML document of a robot config file, not yet validated (ConfigError names the file
    and line when it cannot be read or parsed)."""
    return read_config_lines(path)[0]


def read_config_lines(path: str | os.PathLike) -> tuple[Any, dict[tuple, str]]:
    """The YAML document of a robot config file and the ``file:line`` of each of its keys."""
    doc, lines = read_yaml(path, what="robot config", error=ConfigError)
    return doc, {k: f"{path}:{n}" for k, n in lines.items()}


@dataclass
class ConfigSources:
    """Where a robot config comes from: a navbt robot YAML and/or ROS files.

    Merged in this order, later values winning key by key as rosparam merges: ``config`` (the
    bundled robot when nothing else is given), the ``launch`` file with its ``args``, each
    ``params`` entry (``FILE[:NAMESPACE]``, into the move_base node), each ``nav2_params`` file.
    ``package_path``: folders where ``$(find pkg)`` looks first (then the launch file's folder
    and its parents, then ROS_PACKAGE_PATH)."""

    config: str | None = None
    launch: str | None = None
    args: dict[str, str] = field(default_factory=dict)
    params: list[str] = field(default_factory=list)
    nav2_params: list[str] = field(default_factory=list)
    package_path: list[str] = field(default_factory=list)

    def has_ros(self) -> bool:
        return bool(self.launch or self.params or self.nav2_params)

    def describe(self) -> str:
        parts = [self.config] if self.config else []
        if self.launch:
            args = " ".join(f"{k}:={v}" for k, v in self.args.items())
            parts.append(self.launch + (f" {args}" if args else ""))
        parts += list(self.params) + list(self.nav2_params)
        return " + ".join(parts) if parts else str(DEFAULT_CONFIG)


def _merge(doc: dict[str, Any], origins: dict[tuple, str], add: Mapping[str, Any],
           add_origins: Mapping[tuple, str], path: tuple = ()) -> None:
    """Merge ``add`` into ``doc`` key by key (mappings recursively), as rosparam does."""
    for k, v in add.items():
        p = path + (k,)
        if isinstance(v, Mapping) and isinstance(doc.get(k), dict):
            _merge(doc[k], origins, v, add_origins, p)
        else:
            doc[k] = deep_copy(v)
            for op in [op for op in origins if op[:len(p)] == p]:
                del origins[op]
        for op, o in add_origins.items():
            if op[:len(p)] == p and (op not in origins or op == p):
                origins[op] = o


def merged_doc(sources: ConfigSources) -> tuple[dict[str, Any], dict[tuple, str], list[Note]]:
    """Every source read and merged into one navbt config document, not yet validated: the
    document, the ``file:line`` of each key and the findings of reading (ConfigError when a
    file cannot be read at all)."""
    from executive.ros_params import (ParamTree, load_params_file, move_base_to_config,
                                      split_params_arg)
    doc: dict[str, Any] = {}
    origins: dict[tuple, str] = {}
    notes: list[Note] = []
    if sources.config or not sources.has_ros():
        base, base_origins = read_config_lines(sources.config or DEFAULT_CONFIG)
        if base is not None and not isinstance(base, Mapping):
            raise ConfigError(f"{sources.config}: the robot config must be a mapping of "
                              f"namespaces, got {type(base).__name__}")
        _merge(doc, origins, base or {}, base_origins)
    try:
        if sources.launch or sources.params:
            tree, node_ns, amcl_ns = ParamTree(), ("move_base",), ("amcl",)
            if sources.launch:
                from executive.ros_launch import read_launch
                launched = read_launch(sources.launch, sources.args, sources.package_path)
                tree = launched.tree
                node_ns = launched.move_base_ns or node_ns
                amcl_ns = launched.amcl_ns or amcl_ns
                notes += launched.notes
            for spec in sources.params:
                notes += load_params_file(tree, spec, node_ns)
            files = frozenset(split_params_arg(spec)[0] for spec in sources.params)
            converted = move_base_to_config(tree, node_ns, amcl_ns, outside_files=files)
            _merge(doc, origins, converted.doc, converted.origins)
            notes += converted.notes
        for path in sources.nav2_params:
            from executive.nav2_params import read_nav2_params
            converted = read_nav2_params(path)
            _merge(doc, origins, converted.doc, converted.origins)
            notes += converted.notes
    except ParamsError as e:
        raise ConfigError(str(e), notes) from None
    return doc, origins, notes


def load_config_sources(sources: ConfigSources) -> RobotConfig:
    """Read every source, merge them and validate once; ConfigError lists every error (those
    found while reading the sources too)."""
    doc, origins, notes = merged_doc(sources)
    return config_from_mapping(doc, sources.describe(), origins, notes)
