"""The simulated robot's configuration: one plain dict, every key declared once with a default.

Top-level keys describe the base (kinematics, footprint, limits, odometry noise); ``laser``,
``imu`` and ``battery`` are nested dicts. Unknown keys, wrong types and out-of-range values raise
``ParameterError`` naming the key (and the closest known one). Limit names follow
base_local_planner (``acc_lim_x``, ``max_vel_x``, ...) because users know them, but here they are
the *body's* physical limits, not a planner's.

Laser presets carry the ``LaserScan`` header values of the ROS navigation tuning guide
(section 5.1, SICK LMS 200 / 291) and of the Hokuyo URG-04LX's own parameters (PP reply:
steps 44..725 of 1024 around step 384, 600 rpm, 20..5600 mm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from navcore.costmap.footprint import make_footprint
from navcore.params import Param, ParameterError, Parameters, suggest
from navcore.types import Pose2D

_URG_STEP = 2.0 * math.pi / 1024.0

LASER_PRESETS: dict[str, dict[str, float]] = {
    "urg04lx": {
        "angle_min": (44 - 384) * _URG_STEP,
        "angle_max": (725 - 384) * _URG_STEP,
        "angle_increment": _URG_STEP,
        "time_increment": 60.0 / (600.0 * 1024.0),
        "scan_time": 0.1,
        "range_min": 0.02,
        "range_max": 5.6,
    },
    "lms200": {
        "angle_min": -1.57079637051,
        "angle_max": 1.57079637051,
        "angle_increment": 0.0174532923847,
        "time_increment": 3.70370362361e-05,
        "scan_time": 0.0133333336562,
        "range_min": 0.0,
        "range_max": 81.0,
    },
    "lms291": {
        "angle_min": -1.57079637051,
        "angle_max": 1.57079637051,
        "angle_increment": 0.00872664619235,
        "time_increment": 7.40740724722e-05,
        "scan_time": 0.0133333336562,
        "range_min": 0.0,
        "range_max": 81.0,
    },
}

DEFAULT_FOOTPRINT = [[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]]

ROBOT_PARAMS = (
    Param("kinematics", "diff", str, "drive type: differential (vy = 0) or holonomic",
          choices=("diff", "omni")),
    Param("footprint", DEFAULT_FOOTPRINT, list, "body polygon [[x, y], ...] in base_link (m); "
          "empty: a circle of robot_radius"),
    Param("robot_radius", 0.0, float, "body radius (m) when footprint is empty", min=0.0),
    Param("acc_lim_x", 2.5, float, "forward acceleration and braking limit (m/s^2)", min=1e-3),
    Param("acc_lim_y", 2.5, float, "sideways acceleration limit, omni only (m/s^2)", min=1e-3),
    Param("acc_lim_theta", 3.2, float, "yaw acceleration limit (rad/s^2)", min=1e-3),
    Param("max_vel_x", 1.0, float, "fastest the wheels drive forward or back (m/s)", min=0.0),
    Param("max_vel_y", 1.0, float, "fastest sideways speed, omni only (m/s)", min=0.0),
    Param("max_vel_theta", 2.0, float, "fastest yaw rate (rad/s)", min=0.0),
    Param("cmd_vel_timeout", 0.5, float, "no command for this long (s) and the base brakes to "
          "zero", min=1e-3),
    Param("wheel_separation", 0.4, float, "distance between the drive wheels (m); used by the "
          "stuck_wheel fault", min=1e-3),
    Param("physics_period", 0.01, float, "fixed physics step (s)", min=1e-4, max=0.1),
    Param("odom_rate", 50.0, float, "odometry publication rate (Hz)", min=0.1, max=1000.0),
    # amcl's names; sampled per odometry period with the corrected (sqrt) model. The amcl default
    # 0.2 describes a filter update every >= 0.2 m; per 20 ms period it would be a very bad robot.
    Param("odom_alpha1", 0.01, float, "rotation noise from rotation", min=0.0),
    Param("odom_alpha2", 0.01, float, "rotation noise from translation", min=0.0),
    Param("odom_alpha3", 0.01, float, "translation noise from translation", min=0.0),
    Param("odom_alpha4", 0.01, float, "translation noise from rotation", min=0.0),
    Param("odom_alpha5", 0.01, float, "strafe noise from translation, omni only", min=0.0),
    Param("wheel_slip", 0.0, float, "fraction of wheel motion that never moves the robot "
          "(odometry over-reads by it)", min=0.0, max=1.0),
    Param("bumper_hold", 0.1, float, "the bumper reads pressed for this long (s) after the last "
          "blocked motion", min=0.0),
)

LASER_PARAMS = (
    Param("enabled", True, bool, "simulate a laser"),
    Param("preset", "urg04lx", str, "header values to start from", choices=tuple(LASER_PRESETS)),
    Param("angle_min", None, float, "first beam angle in the laser frame (rad)"),
    Param("angle_max", None, float, "last beam angle (rad)"),
    Param("angle_increment", None, float, "angle between beams (rad)", min=1e-6),
    Param("beams", 0, int, "beam count; if > 0 it sets angle_increment over "
          "[angle_min, angle_max]", min=0, max=100000),
    Param("time_increment", None, float, "time between beams (s), header only", min=0.0),
    Param("scan_time", None, float, "time between scans (s)", min=1e-4),
    Param("rate", 0.0, float, "scans per second; 0 = 1 / scan_time", min=0.0, max=1000.0),
    Param("range_min", None, float, "minimum valid range (m)", min=0.0),
    Param("range_max", None, float, "maximum range (m)", min=1e-3),
    Param("range_noise_stddev", 0.01, float, "Gaussian range noise (m)", min=0.0),
    Param("no_return", "inf", str, "what a beam that hits nothing reads",
          choices=("inf", "range_max")),
    Param("mount", [0.0, 0.0, 0.0], list, "laser pose [x, y, yaw] in base_link"),
)

IMU_PARAMS = (
    Param("enabled", True, bool, "simulate an IMU"),
    Param("rate", 50.0, float, "IMU publication rate (Hz)", min=0.1, max=1000.0),
    Param("gyro_noise_stddev", 0.005, float, "yaw-rate white noise (rad/s)", min=0.0),
    Param("gyro_bias", 0.001, float, "constant yaw-rate bias (rad/s)"),
    Param("accel_noise_stddev", 0.02, float, "linear acceleration noise (m/s^2)", min=0.0),
    Param("mount", [0.0, 0.0, 0.0], list, "IMU pose [x, y, yaw] in base_link"),
)

BATTERY_PARAMS = (
    Param("capacity_wh", 50.0, float, "usable energy when full (Wh)", min=1e-3),
    Param("initial_percentage", 1.0, float, "charge at start, 0..1", min=0.0, max=1.0),
    Param("idle_power_w", 5.0, float, "drain while standing (W)", min=0.0),
    Param("drive_energy_j_per_m", 20.0, float, "extra energy per metre driven (J/m)", min=0.0),
    Param("turn_energy_j_per_rad", 5.0, float, "extra energy per radian turned (J/rad)",
          min=0.0),
    Param("voltage_full", 16.7, float, "voltage when full (V)", min=0.0),
    Param("voltage_empty", 13.2, float, "voltage when empty (V)", min=0.0),
)

SECTIONS = {"laser": LASER_PARAMS, "imu": IMU_PARAMS, "battery": BATTERY_PARAMS}


def _pose(value: list, where: str) -> Pose2D:
    if len(value) != 3 or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                  and math.isfinite(v) for v in value):
        raise ParameterError(f"{where}: parameter 'mount' must be [x, y, yaw] numbers, "
                             f"got {value!r}")
    return Pose2D(float(value[0]), float(value[1]), float(value[2]))


@dataclass(frozen=True)
class LaserConfig:
    """The resolved laser: header values, beam angles in the laser frame, rate and mount."""

    angle_min: float
    angle_max: float
    angle_increment: float
    time_increment: float
    scan_time: float
    range_min: float
    range_max: float
    rate: float
    range_noise_stddev: float
    no_return_inf: bool
    mount: Pose2D
    angles: np.ndarray  # (n,) beam angles in the laser frame


def resolve_laser(p: Parameters) -> LaserConfig:
    """Preset values overridden by the given ones; the beam count follows from the angles."""
    where = "sim.laser"
    v = dict(LASER_PRESETS[p.preset])
    for k in ("angle_min", "angle_max", "angle_increment", "time_increment", "scan_time",
              "range_min", "range_max"):
        if getattr(p, k) is not None:
            v[k] = float(getattr(p, k))
    if v["angle_max"] < v["angle_min"]:
        raise ParameterError(f"{where}: angle_max {v['angle_max']} < angle_min {v['angle_min']}")
    if v["range_max"] <= v["range_min"]:
        raise ParameterError(f"{where}: range_max {v['range_max']} <= range_min "
                             f"{v['range_min']}")
    if p.beams > 0:
        if p.beams == 1:
            raise ParameterError(f"{where}: beams must be >= 2")
        v["angle_increment"] = (v["angle_max"] - v["angle_min"]) / (p.beams - 1)
        n = p.beams
    else:
        n = int(round((v["angle_max"] - v["angle_min"]) / v["angle_increment"])) + 1
    angles = v["angle_min"] + v["angle_increment"] * np.arange(n, dtype=np.float64)
    rate = p.rate if p.rate > 0 else 1.0 / v["scan_time"]
    return LaserConfig(v["angle_min"], float(angles[-1]), v["angle_increment"],
                       v["time_increment"], v["scan_time"], v["range_min"], v["range_max"], rate,
                       p.range_noise_stddev, p.no_return == "inf", _pose(p.mount, where), angles)


@dataclass(frozen=True)
class RobotConfig:
    """Validated simulator configuration: ``base`` Parameters, the footprint polygon, the
    resolved laser (None if disabled), and the imu / battery Parameters (imu None if disabled)."""

    base: Parameters
    footprint: np.ndarray
    laser: LaserConfig | None
    imu: Parameters | None
    imu_mount: Pose2D
    battery: Parameters


def robot_config(values: Mapping[str, Any] | None = None) -> RobotConfig:
    """Validate a plain robot dict (see the module docstring) into a ``RobotConfig``."""
    values = dict(values or {})
    sections: dict[str, Mapping[str, Any]] = {}
    for name in SECTIONS:
        sub = values.pop(name, None) or {}
        if not isinstance(sub, Mapping):
            raise ParameterError(f"sim: '{name}' must be a mapping of parameters, got {sub!r}")
        sections[name] = sub
    known = [p.name for p in ROBOT_PARAMS] + list(SECTIONS)
    for k in values:
        if k not in known:
            raise ParameterError(f"sim: unknown parameter '{k}'{suggest(str(k), known)}")
    base = Parameters(ROBOT_PARAMS, values, where="sim")
    try:
        fp = make_footprint(base.footprint, base.robot_radius if base.robot_radius > 0 else 0.46,
                            footprint_padding=0.0)
    except ValueError as e:
        raise ParameterError(f"sim: {e}") from None
    lp = Parameters(LASER_PARAMS, sections["laser"], where="sim.laser")
    ip = Parameters(IMU_PARAMS, sections["imu"], where="sim.imu")
    bp = Parameters(BATTERY_PARAMS, sections["battery"], where="sim.battery")
    if bp.voltage_empty > bp.voltage_full:
        raise ParameterError("sim.battery: voltage_empty is above voltage_full")
    return RobotConfig(base, fp, resolve_laser(lp) if lp.enabled else None,
                       ip if ip.enabled else None, _pose(ip.mount, "sim.imu"), bp)
