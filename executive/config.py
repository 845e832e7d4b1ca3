"""The robot config: one YAML file with a ROS parameter namespace per component.

A user pastes their ``costmap_common_params.yaml``, ``dwa_local_planner_params.yaml``, amcl and
move_base parameters under the namespaces ROS uses, and they mean the same here. Every value is
checked against the declaring component's ``Param`` table at load time, so a typo or an
out-of-range value is an error naming the file, the namespace and the parameter, before any robot
moves. The namespaces owned here are ``robot`` (body and devices), ``move_base`` and ``safety``;
the others come from the component that declares them (found lazily, see ``COMPONENT_NAMESPACES``).
"""

from __future__ import annotations

import importlib
import importlib.util
import math
import os
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import Any, Callable, Mapping

from navcore.safe_read import load_yaml
from navcore.params import Param, ParameterError, Parameters, suggest


class ConfigError(ValueError):
    """The robot config is unreadable or has a bad value; the message names file and namespace."""


DEFAULT_CONFIG = FsPath(__file__).resolve().parent / "data" / "robot.yaml"

ROBOT_PARAMS: tuple[Param, ...] = (
    Param("footprint", [[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]], list,
          "robot outline in base_link, counter- or clockwise [[x, y], ...] (m); [] to use "
          "robot_radius"),
    Param("robot_radius", 0.0, float, "circular robot radius (m), used when footprint is []",
          min=0.0, max=5.0),
    Param("devices", "sim", str, "'sim' for the simulator (real devices: see 'base'/'laser' URLs)"),
    Param("base", "", str, "URL of the base driver (from devices: {base: ...})"),
    Param("laser", "", str, "URL of the laser driver (from devices: {laser: ...})"),
)

MOVE_BASE_PARAMS: tuple[Param, ...] = (
    Param("base_global_planner", "navfn/NavfnROS", str, "global planner plugin",
          choices=("navfn/NavfnROS", "global_planner/GlobalPlanner",
                   "carrot_planner/CarrotPlanner")),
    Param("base_local_planner", "base_local_planner/TrajectoryPlannerROS", str,
          "local planner plugin",
          choices=("base_local_planner/TrajectoryPlannerROS", "dwa_local_planner/DWAPlannerROS")),
    Param("controller_frequency", 20.0, float, "control loop rate (Hz)", min=0.1, max=1000.0),
    Param("planner_frequency", 0.0, float, "replanning rate (Hz); 0 plans on new goals/failures",
          min=0.0, max=100.0),
    Param("planner_patience", 5.0, float, "time to find a valid plan before recovery (s)",
          min=0.0),
    Param("controller_patience", 15.0, float, "time without a valid command before recovery (s)",
          min=0.0),
    Param("max_planning_retries", -1, int, "planning retries before recovery; -1 = unlimited",
          min=-1),
    Param("oscillation_timeout", 0.0, float, "time allowed to oscillate before recovery; 0 off",
          min=0.0),
    Param("oscillation_distance", 0.5, float, "distance that resets the oscillation timer (m)",
          min=0.0),
    Param("conservative_reset_dist", 3.0, float, "conservative clear_costmap reset distance (m)",
          min=0.0),
    Param("clearing_radius", -1.0, float, "clearing radius; -1 = circumscribed radius"),
    Param("recovery_behavior_enabled", True, bool, "run recovery behaviours"),
    Param("clearing_rotation_allowed", True, bool, "allow rotate_recovery"),
    Param("shutdown_costmaps", False, bool, "stop costmaps when inactive (kept for parity)"),
    Param("make_plan_clear_costmap", True, bool, "kept for parity"),
    Param("make_plan_add_unreachable_goal", True, bool, "kept for parity"),
)

SAFETY_PARAMS: tuple[Param, ...] = (
    Param("max_vel_x", 0.55, float, "hard forward speed limit (m/s)", min=0.0, max=10.0),
    Param("min_vel_x", -0.3, float, "hard reverse speed limit (m/s, <= 0)", min=-10.0, max=0.0),
    Param("max_vel_y", 0.0, float, "hard lateral speed limit (m/s)", min=0.0, max=10.0),
    Param("max_vel_theta", 1.5, float, "hard yaw rate limit (rad/s)", min=0.0, max=20.0),
    Param("sensor_timeout", 0.5, float, "laser/odometry older than this stops the robot (s)",
          min=0.001, max=10.0),
    Param("stall_timeout", 2.0, float, "commanded motion without measured motion for this long "
          "is a stall (s); 0 = no stall check", min=0.0, max=60.0),
    Param("stall_speed", 0.02, float, "measured speed below which a commanded robot counts as "
          "stalled (m/s or rad/s)", min=0.0, max=1.0),
    Param("stop_on_bumper", True, bool, "a pressed bumper blocks forward motion"),
    Param("stamp_tolerance", 0.02, float, "a sensor stamp further than this in the future is "
          "invalid (s)", min=0.0, max=1.0),
    Param("frozen_scans", 2, int, "this many consecutive fresh scans with identical ranges while "
          "odometry reports motion mean a frozen laser", min=2, max=1000),
    Param("watchdog_periods", 1.5, float, "a control cycle taking longer than this many periods "
          "of wall time stops the robot (wall clock only)", min=1.0, max=100.0),
)

# ROS namespace -> (module, attribute) of the component's Param table. Resolved lazily so that the
# executive does not import every component just to read a file, and so a component that is not
# installed only matters when its namespace is used.
COMPONENT_NAMESPACES: dict[str, tuple[tuple[str, str], ...]] = {
    # costmaps carry nested layer namespaces: checked by building one (see _check_costmap)
    "global_costmap": (),
    "local_costmap": (),
    "NavfnROS": (("navcore.planners.navfn", "NAVFN_PARAMS"),),
    "GlobalPlanner": (("navcore.planners.global_planner", "GLOBAL_PLANNER_PARAMS"),
                      ("navcore.planners.global_planner", "PARAMS")),
    "CarrotPlanner": (("navcore.planners.carrot_planner", "CARROT_PLANNER_PARAMS"),
                      ("navcore.planners.carrot_planner", "PARAMS")),
    "DWAPlannerROS": (("navcore.controllers.dwa", "DWA_PARAMS"),
                      ("navcore.controllers.dwa", "PARAMS")),
    "TrajectoryPlannerROS": (("navcore.controllers.trajectory_planner", "TRAJECTORY_PLANNER_PARAMS"),
                             ("navcore.controllers.trajectory_planner", "PARAMS")),
    "amcl": (("navcore.localization.amcl_params", "AMCL_PARAMS"),),
}

# The simulated body (kinematics, limits, odometry noise, laser/imu/battery sections) is declared
# by the simulator itself (hw/sim/config.py) and validated by its ``robot_config``; the footprint
# defaults to robot.footprint.
SIM_NAMESPACE = "sim"

OWN_NAMESPACES: dict[str, tuple[Param, ...]] = {
    "robot": ROBOT_PARAMS,
    "move_base": MOVE_BASE_PARAMS,
    "safety": SAFETY_PARAMS,
}

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

    def all_parameters(self) -> dict[str, Parameters]:
        """Every live Parameters object by namespace (what SetParameters may change)."""
        out = {"robot": self.robot, "move_base": self.move_base, "safety": self.safety}
        out.update(self.parameters)
        return out


def _check_footprint(fp: list, where: str) -> None:
    if fp == []:
        return
    if len(fp) < 3:
        raise ConfigError(f"{where}: parameter 'footprint' needs at least 3 points, got {len(fp)}")
    for i, p in enumerate(fp):
        if (not isinstance(p, (list, tuple)) or len(p) != 2
                or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in p)):
            raise ConfigError(f"{where}: parameter 'footprint' point {i} must be [x, y], got {p!r}")


def _check_costmap(body: dict[str, Any], ns: str, robot: Parameters, source: str) -> None:
    """Build the costmap once on a tiny map: every layer validates its own namespace."""
    if importlib.util.find_spec("navcore.costmap.layered") is None:
        return  # the costmap component is not installed: nothing to check against
    from navcore.maps import OccupancyGrid
    import numpy as np
    trial = dict(body)
    if robot.footprint:
        trial.setdefault("footprint", robot.footprint)
    else:
        trial.setdefault("robot_radius", robot.robot_radius)
    try:
        make_costmap(trial, OccupancyGrid(np.zeros((4, 4)), 0.05), ns)
    except (ParameterError, ValueError, KeyError) as e:
        raise ConfigError(f"{source}: {e}") from None


def make_costmap(params: dict[str, Any], grid: Any, name: str, clock: Any = None) -> Any:
    """A LayeredCostmap from a ROS namespace; the map goes to it only if it has a static layer."""
    from navcore.costmap.layered import LayeredCostmap
    try:
        return LayeredCostmap.from_params(params, static_map=None, name=name, clock=clock)
    except ParameterError as e:
        if "needs a map" not in str(e):
            raise
    return LayeredCostmap.from_params(params, static_map=grid, name=name, clock=clock)


def config_from_mapping(doc: Mapping[str, Any], source: str = "<config>") -> RobotConfig:
    """Validate a parsed robot config; raise ConfigError naming source, namespace and parameter."""
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
            raise ConfigError(f"{source}: unknown namespace '{ns}'{suggest(str(ns), known)}")
        if body is None:
            body = {}
        if not isinstance(body, Mapping):
            raise ConfigError(f"{source}: {ns}: must be a mapping of parameters, got {body!r}")
        body = dict(body)
        if ns == "robot" and isinstance(body.get("devices"), Mapping):
            # devices: {base: URL, laser: URL, imu: ...} (hw/devices.py) means real hardware
            dev = dict(body.pop("devices"))
            body["devices"] = "hw"
            for k, v in dev.items():
                if k not in ("base", "laser", "imu"):
                    raise ConfigError(f"{source}: robot: devices: unknown device '{k}'"
                                      f"{suggest(str(k), ('base', 'laser', 'imu'))}")
                if k in ("base", "laser"):
                    body[k] = v if isinstance(v, str) else str(dict(v).get("url", ""))
            device_map = dev
        raw[ns] = body
        if ns == SIM_NAMESPACE:
            continue  # checked below, once the footprint is known
        if ns in ("global_costmap", "local_costmap"):
            continue  # checked below, with the footprint
        specs = specs_for(ns)
        if specs is None:
            continue  # component not installed: its own constructor validates when built
        try:
            values[ns] = Parameters(specs, body, where=f"{source}: {ns}", ignore=STRUCTURAL_KEYS)
        except ParameterError as e:
            raise ConfigError(str(e)) from None
    for ns in OWN_NAMESPACES:
        if ns not in values:
            values[ns] = Parameters(OWN_NAMESPACES[ns], {}, where=f"{source}: {ns}")
    _check_footprint(values["robot"].footprint, f"{source}: robot")
    if not values["robot"].footprint and values["robot"].robot_radius <= 0:
        raise ConfigError(f"{source}: robot: give a footprint or a robot_radius > 0")
    if values["robot"].devices not in ("sim", "hw"):
        raise ConfigError(f"{source}: robot: parameter 'devices' must be 'sim', 'hw' or a mapping "
                          f"{{base: URL, laser: URL}}, got {values['robot'].devices!r}")
    raw.setdefault(SIM_NAMESPACE, {})
    sim_values = dict(raw[SIM_NAMESPACE])
    sim_values.setdefault("footprint", values["robot"].footprint)
    if not values["robot"].footprint:
        sim_values.setdefault("robot_radius", values["robot"].robot_radius)
    raw[SIM_NAMESPACE] = sim_values
    try:
        from hw.sim.config import robot_config
    except ImportError:
        robot_config = None
    if robot_config is not None:
        try:
            robot_config(sim_values)
        except (ParameterError, ValueError) as e:
            raise ConfigError(f"{source}: {e}") from None
    for ns in ("global_costmap", "local_costmap"):
        if ns in raw:
            _check_costmap(raw[ns], ns, values["robot"], source)
    component_params = {ns: p for ns, p in values.items() if ns not in OWN_NAMESPACES}
    return RobotConfig(source, values["robot"], values["move_base"], values["safety"], raw,
                       component_params, device_map)


def load_config(path: str | os.PathLike | None = None) -> RobotConfig:
    """Read and validate a robot config YAML (the bundled default when ``path`` is None)."""
    path = FsPath(path) if path is not None else DEFAULT_CONFIG
    return config_from_mapping(read_config_doc(path), str(path))


def read_config_doc(path: str | os.PathLike) -> Any:
    """The YAML document of a robot config file, not yet validated (ConfigError names the file
    and line when it cannot be read or parsed)."""
    return load_yaml(path, what="robot config", error=ConfigError)
