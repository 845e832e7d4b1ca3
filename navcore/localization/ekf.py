"""Odometry + IMU (+ visual odometry) fusion with robot_pose_ekf's semantics, in the plane.

robot_pose_ekf runs an EKF whose system model is a random walk with huge process noise
(sigma 1000 per axis), so the state is carried by the measurements, and every sensor enters as a
*relative* measurement: the filter's previous estimate composed with the sensor's own change since
its previous reading, with the message covariance scaled by dt^2. Wheel odometry and VO measure
(x, y, yaw); the IMU measures yaw. The node's timer (``freq``) fuses at the newest time for which
*every active sensor* has data (the minimum of their stamps); a sensor is active from its second
message after a filter cycle and drops out after ``sensor_timeout`` without data, and a sensor
that comes back re-anchors (its first reading after a gap is not a measurement). The filter
initialises from the first active odometry (or VO when odometry is not used).
Here the state is (x, y, yaw); robot_pose_ekf's z, roll and pitch have no planar counterpart.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from navcore.params import Param, Parameters
from navcore.types import Imu, Odometry, Pose2D, normalize_angle

EKF_PARAMS: tuple[Param, ...] = (
    Param("output_frame", "odom_combined", str, "frame of the fused pose"),
    Param("base_footprint_frame", "base_footprint", str, "robot frame"),
    Param("freq", 30.0, float, "filter cycles per second", min=1e-6),
    Param("sensor_timeout", 1.0, float, "seconds without data before a sensor is dropped",
          min=0.0),
    Param("odom_used", True, bool, "fuse wheel odometry"),
    Param("imu_used", True, bool, "fuse IMU yaw"),
    Param("vo_used", True, bool, "fuse visual odometry"),
    Param("gps_used", False, bool, "fuse GPS (not available in the planar filter)"),
    Param("debug", False, bool, "verbose output (no effect here)"),
    Param("self_diagnose", False, bool, "diagnostics (no effect here)"),
)

_PROCESS_VAR = 1000.0 ** 2
_PRIOR_VAR = 0.001 ** 2


@dataclass
class _Sensor:
    """One input: its history (for interpolation at the filter time) and activation state."""

    name: str
    history: deque = field(default_factory=lambda: deque(maxlen=64))  # (stamp, x, y, yaw, cov)
    active: bool = False
    initializing: bool = False
    init_stamp: float = 0.0
    anchored: bool = False  # has a previous reading to measure change against
    old: np.ndarray = field(default_factory=lambda: np.zeros(3))

    @property
    def stamp(self) -> float:
        return self.history[-1][0] if self.history else -math.inf

    def at(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Reading at time t, linearly interpolated between the two messages around it."""
        h = self.history
        if t >= h[-1][0] or len(h) == 1:
            return np.array(h[-1][1:4]), h[-1][4]
        for i in range(len(h) - 1, 0, -1):
            t0, t1 = h[i - 1][0], h[i][0]
            if t0 <= t <= t1:
                f = 0.0 if t1 == t0 else (t - t0) / (t1 - t0)
                a, b = np.array(h[i - 1][1:4]), np.array(h[i][1:4])
                yaw = a[2] + f * normalize_angle(b[2] - a[2])
                return np.array([a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]),
                                 normalize_angle(yaw)]), h[i][4]
        return np.array(h[0][1:4]), h[0][4]


class Ekf:
    """robot_pose_ekf in the plane. Feed messages with ``add_odometry``/``add_imu``/``add_vo``
    and call ``update(now)`` from the control loop; it runs one filter cycle when 1/freq has passed
    and returns True when the fused pose changed."""

    def __init__(self, params: Mapping[str, Any] | None = None) -> None:
        self.params = Parameters(EKF_PARAMS, params, where="robot_pose_ekf")
        self._sensors = {n: _Sensor(n) for n in ("odom", "imu", "vo")}
        self._x = np.zeros(3)
        self._P = np.eye(3) * _PRIOR_VAR
        self.initialized = False
        self._filter_time = -math.inf  # time of the current estimate
        self._cycle_stamp = -math.inf  # the node's filter_stamp_ of the last cycle
        self._last_cycle = -math.inf
        self.last_error = ""

    # ----------------------------------------------------------------- inputs
    def add_odometry(self, odom: Odometry) -> bool:
        """Wheel odometry (pose and its 3x3 covariance). False, with ``last_error``, if unusable."""
        return self._add("odom", odom.stamp, odom.pose, np.asarray(odom.pose_covariance, float))

    def add_vo(self, vo: Odometry) -> bool:
        """Visual odometry, treated like wheel odometry."""
        return self._add("vo", vo.stamp, vo.pose, np.asarray(vo.pose_covariance, float))

    def add_imu(self, imu: Imu) -> bool:
        """IMU orientation (yaw) with its variance; messages without orientation are refused."""
        if imu.yaw_variance < 0.0:
            self.last_error = "imu: message has no orientation estimate (yaw_variance < 0)"
            return False
        cov = np.diag([0.0, 0.0, imu.yaw_variance])
        return self._add("imu", imu.stamp, Pose2D(0.0, 0.0, imu.yaw), cov)

    def _add(self, name: str, stamp: float, pose: Pose2D, cov: np.ndarray) -> bool:
        s = self._sensors[name]
        if not self.params.__getattr__(f"{name}_used"):
            self.last_error = f"{name}: not used ({name}_used is false)"
            return False
        if cov.shape != (3, 3) or not np.all(np.isfinite(cov)):
            self.last_error = f"{name}: covariance must be a finite 3x3 array"
            return False
        needed = [2] if name == "imu" else [0, 1, 2]
        if np.any(np.diag(cov)[needed] <= 0.0):
            self.last_error = f"{name}: covariance of the measured axes is zero"
            return False
        if not all(math.isfinite(v) for v in (stamp, pose.x, pose.y, pose.theta)):
            self.last_error = f"{name}: non-finite stamp or pose"
            return False
        if s.history and stamp <= s.stamp:
            self.last_error = f"{name}: stamp {stamp} is not newer than {s.stamp}"
            return False
        s.history.append((stamp, pose.x, pose.y, pose.theta, cov.copy()))
        if not s.active:
            if not s.initializing:
                s.initializing, s.init_stamp = True, stamp
            if self._cycle_stamp >= s.init_stamp:
                s.active, s.initializing = True, False
        return True

    # ----------------------------------------------------------------- the filter cycle
    def update(self, now: float) -> bool:
        """One timer callback of the node at time ``now`` (at most ``freq`` per second)."""
        if now - self._last_cycle < 1.0 / self.params.freq - 1e-9:
            return False
        self._last_cycle = now
        stamp = now
        used = [n for n in ("odom", "imu", "vo") if self.params.__getattr__(f"{n}_used")]
        for n in used:
            s = self._sensors[n]
            if s.active and stamp - s.stamp > self.params.sensor_timeout:
                s.active = False  # dropped: it re-anchors when data returns
        active = [n for n in used if self._sensors[n].active]
        self._cycle_stamp = stamp
        if not active:
            return False
        stamp = min(stamp, *(self._sensors[n].stamp for n in active))
        if self.initialized:
            return self._fuse(active, stamp)
        if "odom" in active:
            return self._initialize("odom", stamp)
        if "vo" in active and not self.params.odom_used:
            return self._initialize("vo", stamp)
        return False

    def _initialize(self, name: str, stamp: float) -> bool:
        s = self._sensors[name]
        z, _ = s.at(stamp)
        # anchor the initialising sensor here (robot_pose_ekf anchors it one cycle later and so
        # drops the motion of that first cycle)
        s.old, s.anchored = z, True
        self._x = z.copy()
        self._P = np.eye(3) * _PRIOR_VAR
        self._filter_time = stamp
        self.initialized = True
        return True

    def _fuse(self, active: list[str], stamp: float) -> bool:
        dt = stamp - self._filter_time
        if dt <= 0.0:
            return False
        old = Pose2D(*self._x)
        x = self._x.copy()
        P = self._P + np.eye(3) * _PROCESS_VAR  # zero-velocity system model, huge noise
        for name in ("odom", "imu", "vo"):
            s = self._sensors[name]
            if name not in active:
                s.anchored = False
                continue
            z_now, cov = s.at(stamp)
            if not s.anchored:
                s.old, s.anchored = z_now, True
                continue
            if name == "imu":
                yaw = old.theta + normalize_angle(z_now[2] - s.old[2])
                H = np.array([[0.0, 0.0, 1.0]])
                z = np.array([x[2] + normalize_angle(yaw - x[2])])  # angle overflow correction
                R = np.array([[cov[2, 2]]]) * dt * dt
            else:
                rel = Pose2D(*z_now).relative_to(Pose2D(*s.old))
                m = old.compose(rel)
                H = np.eye(3)
                z = np.array([m.x, m.y, x[2] + normalize_angle(m.theta - x[2])])
                R = cov * dt * dt
            y = z - H @ x
            S = H @ P @ H.T + R
            K = P @ H.T @ np.linalg.inv(S)
            x = x + K @ y
            P = (np.eye(3) - K @ H) @ P
            s.old = z_now
        x[2] = normalize_angle(x[2])
        self._x, self._P = x, 0.5 * (P + P.T)
        self._filter_time = stamp
        return True

    # ----------------------------------------------------------------- outputs
    def pose(self) -> Pose2D:
        """Fused pose in ``output_frame`` at ``stamp``."""
        return Pose2D(float(self._x[0]), float(self._x[1]), float(self._x[2]))

    def covariance(self) -> np.ndarray:
        return self._P.copy()

    @property
    def stamp(self) -> float:
        return self._filter_time

    def active(self, name: str) -> bool:
        """Whether sensor ``name`` ("odom", "imu", "vo") is currently fused."""
        return self._sensors[name].active
