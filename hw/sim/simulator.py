"""The simulated robot behind the ``hw`` interfaces: a deterministic world you can script.

``Simulator(world, robot, clock, rng)`` owns one robot in a ``SimWorld``. ``step_to(t)`` runs fixed
physics steps up to time t in chunks that end wherever something happens (a sensor is due, a
fault starts or ends, an object appears); each chunk is one numba call. ``base``, ``laser`` and
``imu`` implement ``hw.interfaces.Base``, ``Laser`` and ``ImuSensor``. Randomness comes only from
``rng``, time only from step counting, so one seed gives one trace.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, Iterable, Mapping

import numpy as np

from hw.interfaces import BaseEvents, BatteryState
from hw.sim import physics as ph
from hw.sim.config import RobotConfig, robot_config
from hw.sim.faults import Fault, fault_from_mapping
from hw.sim.world import SimWorld, first_after
from navcore.clock import Clock
from navcore.types import Imu, LaserScan, Odometry, Pose2D, Twist, normalize_angle

_EPS = 1e-9
# odometry pose covariance: a fixed small diagonal (the pose drifts without bound; consumers such
# as robot_pose_ekf use the relative motion), shared and read-only
_ODOM_POSE_COV = np.diag([1e-3, 1e-3, 1e-3])
_ODOM_POSE_COV.setflags(write=False)
_ODOM_BLOCK = slice(ph.NOX, ph.O_STAMP + 1)
_O_STAMP = ph.O_STAMP
_C_FIRST = ph.C_FIRST
_NEVER = 2 ** 62  # the step of the next scan when there is no laser
_NO_SCAN = np.zeros(0, np.float32)  # "cast no scan" to the physics kernel


@dataclass(frozen=True)
class Contact:
    """A contact that began at ``time`` with the body at ``pose`` moving at ``speed`` m/s."""

    time: float
    pose: Pose2D
    speed: float


def _ceil_step(x: float) -> int:
    return int(math.ceil(x - _EPS))


class SimBase:
    """``hw.interfaces.Base`` of the simulator."""

    def __init__(self, sim: Simulator) -> None:
        self._sim = sim

    def send(self, cmd: Twist) -> None:
        """Command a body velocity from the next physics step on; a non-finite command is a
        stop (counted in ``Simulator.rejected_commands``)."""
        self._sim._command(cmd)

    def odometry(self) -> Odometry | None:
        return self._sim._odometry()

    def battery(self) -> BatteryState | None:
        return self._sim._battery_state()

    def events(self) -> BaseEvents:
        return BaseEvents(bumper=self._sim.bumper_pressed())


class SimLaser:
    """``hw.interfaces.Laser`` of the simulator; ``config`` holds the resolved header values."""

    def __init__(self, sim: Simulator) -> None:
        self._sim = sim
        self.config = sim.config.laser
        self.mount: Pose2D = self.config.mount

    def scan(self) -> LaserScan | None:
        return self._sim._scan_msg


class SimImu:
    """``hw.interfaces.ImuSensor`` of the simulator."""

    def __init__(self, sim: Simulator) -> None:
        self._sim = sim
        self.mount: Pose2D = sim.config.imu_mount

    def imu(self) -> Imu | None:
        return self._sim._imu()


class Simulator:
    """One robot in a ``SimWorld``.

    ``robot`` is a plain dict (see ``hw.sim.config``) or a ``RobotConfig``; ``start`` the initial
    true pose in ``map``. The odometry frame starts at the robot (odometry pose (0, 0, 0)). Sensors
    publish at time ``clock.now()`` of construction and then at their own rates; readers return
    the newest message.
    """

    def __init__(self, world: SimWorld, robot: Mapping[str, Any] | RobotConfig | None,
                 clock: Clock, rng: np.random.Generator, start: Pose2D = Pose2D()) -> None:
        if not isinstance(world, SimWorld):
            raise TypeError("Simulator: world must be a hw.sim.SimWorld, got "
                            f"{type(world).__name__}")
        if not isinstance(rng, np.random.Generator):
            raise TypeError("Simulator: rng must be a numpy.random.Generator (seeded), got "
                            f"{type(rng).__name__}")
        self.world = world
        self.config = robot if isinstance(robot, RobotConfig) else robot_config(robot)
        self.clock = clock
        self.rng = rng
        b = self.config.base
        self._dt = float(b.physics_period)
        self._t0 = float(clock.now())
        self._step = 0
        # state, constants, faults, contact and laser: views of one kernel vector
        self._kv = kv = np.zeros(ph.KV_SIZE)
        self._st = kv[ph.KV_ST:ph.KV_LIM]
        self._st[ph.X], self._st[ph.Y], self._st[ph.TH] = start.x, start.y, start.theta
        fp = self.config.footprint
        self._fp = np.ascontiguousarray(fp, dtype=np.float64)
        rmax = float(np.max(np.hypot(fp[:, 0], fp[:, 1])))
        lim = kv[ph.KV_LIM:ph.KV_F]
        lim[ph.L_ACC_X], lim[ph.L_ACC_Y], lim[ph.L_ACC_TH] = b.acc_lim_x, b.acc_lim_y, \
            b.acc_lim_theta
        lim[ph.L_MAX_X], lim[ph.L_MAX_Y], lim[ph.L_MAX_TH] = b.max_vel_x, b.max_vel_y, \
            b.max_vel_theta
        lim[ph.L_OMNI] = 1.0 if b.kinematics == "omni" else 0.0
        lim[ph.L_SEP] = b.wheel_separation
        # no point of the body moves more than this between two collision checks
        lim[ph.L_STEP] = min(0.5 * world.resolution, 0.025)
        lim[ph.L_RMAX] = rmax
        lim[ph.L_DT] = self._dt
        lim[ph.L_OX], lim[ph.L_OY], lim[ph.L_RES] = world.origin_x, world.origin_y, \
            world.resolution
        self._lim = lim
        # plain copies of values read every chunk (Parameters lookups are slow in a hot loop)
        self._bumper_hold = float(b.bumper_hold)
        self._wheel_slip = float(b.wheel_slip)
        bp = self.config.battery
        self._battery = (bp.idle_power_w, bp.drive_energy_j_per_m, bp.turn_energy_j_per_rad,
                         bp.capacity_wh * 3600.0, bp.initial_percentage, bp.voltage_empty,
                         bp.voltage_full)
        alphas = (b.odom_alpha1, b.odom_alpha2, b.odom_alpha3, b.odom_alpha4, b.odom_alpha5)
        self._cmd = (0.0, 0.0, 0.0)  # (vx, vy, wz), finite floats
        self._cmd_until = 0  # first step at which the current command has timed out
        self._timeout_steps = max(1, _ceil_step(b.cmd_vel_timeout / self._dt))
        self._contact = kv[ph.KV_C:ph.KV_LS]
        self._faultv = kv[ph.KV_F:ph.KV_C]
        self._faultv[ph.F_SLIP] = float(b.wheel_slip)
        self._faults: list[Fault] = []
        self.contacts: list[Contact] = []
        self._last_blocked = -math.inf  # time of the last blocked motion
        self.rejected_commands = 0
        # independent noise streams: what one sensor draws never shifts another's noise, and
        # the trace does not depend on how step_to calls are spread over time
        self._rng_odom, self._rng_laser, self._rng_imu = rng.spawn(3)
        self._odom_normals = np.zeros(0)
        self._imu_normals = np.zeros(0)
        lim[ph.L_ODOM_P] = (1.0 / b.odom_rate) / self._dt
        lim[ph.L_A1:ph.L_A5 + 1] = alphas
        self._noisy_odom = any(a > 0.0 for a in alphas)
        self._odom_msg: Odometry | None = None
        self._odom_msg_step = -1.0
        # laser
        lc = self.config.laser
        self._scan_msg: LaserScan | None = None
        self._scan_k = 0
        self._next_scan = 0 if lc is not None else _NEVER
        self._laser = kv[ph.KV_LS:ph.KV_SIZE]
        if lc is not None:
            self._scan_period = (1.0 / lc.rate) / self._dt
            self._n_beams = len(lc.angles)
            self._noisy_laser = lc.range_noise_stddev > 0
            self._laser[:] = (lc.mount.x, lc.mount.y, lc.mount.theta, lc.angle_min,
                              lc.angle_increment, lc.range_max, lc.range_noise_stddev,
                              math.inf if lc.no_return_inf else lc.range_max)
            self._laser_seeds: list[int] = []
        # imu
        ic = self.config.imu
        self._imu_msg: Imu | None = None
        st = self._st
        st[ph.I_NEXT] = -1.0
        if ic is not None:
            lim[ph.L_IMU_P] = (1.0 / ic.rate) / self._dt
            lim[ph.L_GBIAS], lim[ph.L_GSIG], lim[ph.L_ASIG] = ic.gyro_bias, \
                ic.gyro_noise_stddev, ic.accel_noise_stddev
            st[ph.I_YAW] = normalize_angle(start.theta + self.config.imu_mount.theta)
            st[ph.I_NEXT] = 0.0
        self._odom_period_steps = float(lim[ph.L_ODOM_P])
        self._imu_period_steps = float(lim[ph.L_IMU_P])
        self._normals_until = -1
        self._battery_check_at = -math.inf
        self._refill_normals(0, 1)
        ph.publish_odometry(st, lim, 0, self._dt, self._odom_normals)
        if ic is not None:
            ph.publish_imu(st, lim, 0, self._dt, self._imu_normals)
        self.base = SimBase(self)
        self.laser = SimLaser(self) if lc is not None else None
        self.imu = SimImu(self) if ic is not None else None
        if lc is not None:
            self._publish_scan()
            self._scan_published()

    # ----------------------------------------------------------------- time and stepping
    @property
    def time(self) -> float:
        """Simulated time of the physics state (a whole number of physics periods)."""
        return self._t0 + self._step * self._dt

    @property
    def travelled(self) -> float:
        """Distance the wheels have driven so far (m)."""
        return float(self._st[ph.DIST])

    def step(self) -> None:
        """Step up to the clock's current time."""
        self.step_to(self.clock.now())

    def step_to(self, t: float) -> None:
        """Run physics steps until the next one would pass time ``t``; publish sensors on time."""
        dt = self._dt
        t0 = self._t0
        target = int(math.floor((t - t0) / dt + _EPS))
        world = self.world
        contact = self._contact
        while self._step < target:
            s = self._step
            now = t0 + s * dt
            end = min(target, self._next_scan)
            moving = False
            if world.dynamic or self._faults:
                boundary = min(world.next_change(now), self._next_fault_change(now))
                if boundary < math.inf:
                    end = min(end, max(s + 1, _ceil_step((boundary - t0) / dt)))
                moving = world.has_moving(now)
                if moving:
                    end = min(end, s + 2)  # moving obstacles advance every 20 ms or so
                self._update_fault_vector(now)
            if end > self._normals_until:
                self._refill_normals(s, end)
            circles, segments = world.shapes_at(now)
            n_cmd = self._cmd_until - s
            if now >= self._battery_check_at and self._battery_flat(now):
                n_cmd = 0  # a flat battery: the motors stop
            # a scan due at the end of the chunk is cast in the same call, unless the world
            # changes with time (then it is cast on its own, with the objects of its own time)
            scan_due = end >= self._next_scan
            out, seed = _NO_SCAN, 0
            if scan_due and not moving and not world.dynamic:
                out, seed = self._scan_buffer(t0 + end * dt)
            vx, vy, wz = self._cmd
            ph.physics_steps(self._kv, vx, vy, wz, n_cmd, end - s, s, moving, self._fp,
                             world.blocked, world.clearance, circles, segments,
                             self._odom_normals, self._imu_normals, seed, out)
            if contact[_C_FIRST] >= 0.0:
                self._record_contact(now)
            self._step = end
            if scan_due:
                if out is _NO_SCAN:
                    self._publish_scan()
                else:
                    self._scan_message(out)
                self._scan_published()

    def _record_contact(self, now: float) -> None:
        """Log a new contact (one per push: blocked steps closer than bumper_hold merge)."""
        c = self._contact
        dt = self._dt
        first_t = now + (float(c[ph.C_FIRST]) + 1) * dt
        if first_t - self._last_blocked > self._bumper_hold + _EPS:
            self.contacts.append(Contact(first_t, Pose2D(float(c[ph.C_X]), float(c[ph.C_Y]),
                                                         float(c[ph.C_TH])),
                                         float(c[ph.C_SPEED])))
        self._last_blocked = now + (float(c[ph.C_LAST]) + 1) * dt

    def _battery_flat(self, now: float) -> bool:
        """Whether the battery is empty; if not, when to look again (it cannot run flat before
        the remaining energy is spent at the highest possible power)."""
        f = self._battery_fraction()
        if f <= 0.0:
            return True
        idle, per_m, per_rad, capacity = self._battery[:4]
        lim = self._lim
        top = idle + per_m * math.hypot(lim[ph.L_MAX_X], lim[ph.L_MAX_Y]) \
            + per_rad * lim[ph.L_MAX_TH]
        self._battery_check_at = now + 0.999 * f * capacity / max(top, 1e-12)
        return False

    def _refill_normals(self, s: int, end: int) -> None:
        """Refill the odometry and IMU noise buffers at step s so that they hold the draws of every
        sample due up to step ``end`` and beyond; ``_normals_until`` is then the last step they
        are sure to cover (3 draws a sample, at most one sample more than whole periods fit)."""
        st = self._st
        period = self._odom_period_steps
        if self._imu_period_steps > 0.0:
            period = min(period, self._imu_period_steps)
        n = max(3 * (int((end - s) / period) + 2), 3072)
        c = int(st[ph.O_CUR])
        fresh = self._rng_odom.standard_normal(n) if self._noisy_odom else np.zeros(n)
        self._odom_normals = np.concatenate([self._odom_normals[c:], fresh])
        st[ph.O_CUR] = 0.0
        left = len(self._odom_normals)
        if self._imu_period_steps > 0.0:
            c = int(st[ph.I_CUR])
            fresh = self._rng_imu.standard_normal(n)
            self._imu_normals = np.concatenate([self._imu_normals[c:], fresh])
            st[ph.I_CUR] = 0.0
            left = min(left, len(self._imu_normals))
        self._normals_until = s + int((left // 3 - 1) * period)

    # ----------------------------------------------------------------- commands and faults
    def _command(self, cmd: Twist) -> None:
        try:
            vx, vy, wz = float(cmd.vx), float(cmd.vy), float(cmd.wz)
            ok = math.isfinite(vx) and math.isfinite(vy) and math.isfinite(wz)
        except (TypeError, ValueError, AttributeError):
            ok = False
        if not ok:
            self.rejected_commands += 1
            vx = vy = wz = 0.0
        self._cmd = (vx, vy, wz)
        self._cmd_until = self._step + self._timeout_steps

    def add_fault(self, fault: Fault | Mapping[str, Any]) -> Fault:
        """Schedule a fault (a ``Fault`` or a scenario mapping, see ``hw.sim.faults``)."""
        f = fault if isinstance(fault, Fault) else fault_from_mapping(fault)
        self._faults.append(f)
        self._update_fault_vector(self.time)
        return f

    def inject(self, kind: str, start: float, duration: float = math.inf,
               **params: Any) -> Fault:
        """``add_fault(Fault(kind, start, duration, **params))``."""
        return self.add_fault(Fault(kind, start, duration, **params))

    def add_faults(self, faults: Iterable[Fault | Mapping[str, Any]]) -> list[Fault]:
        return [self.add_fault(f) for f in faults]

    def end_faults(self, kind: str, t: float | None = None) -> int:
        """End every fault of ``kind`` active at t (default: now) at t; returns how many."""
        t = self.time if t is None else t
        kept: list[Fault] = []
        n = 0
        for f in self._faults:
            if f.kind == kind and f.active(t):
                n += 1
                if t > f.start:   # it did happen until t; one that starts at t never does
                    kept.append(dataclasses.replace(f, duration=t - f.start))
            else:
                kept.append(f)
        self._faults = kept
        self._update_fault_vector(t)
        return n

    def fault_active(self, kind: str, t: float | None = None) -> Fault | None:
        """The first fault of ``kind`` active at t (default: now), else None."""
        t = self.time if t is None else t
        for f in self._faults:
            if f.kind == kind and f.active(t):
                return f
        return None

    def _next_fault_change(self, t: float) -> float:
        return first_after(t, (b for f in self._faults for b in (f.start, f.end)))

    def _update_fault_vector(self, t: float) -> None:
        fv = self._faultv
        fv[:] = 0.0
        fv[ph.F_SLIP] = self._wheel_slip
        for f in self._faults:
            if not f.active(t):
                continue
            if f.kind == "odom_slip":
                fv[ph.F_SLIP] = max(fv[ph.F_SLIP], f.slip)
            elif f.kind == "blocked_rotation":
                fv[ph.F_NOROT] = 1.0
            elif f.kind == "stuck_wheel":
                fv[ph.F_STUCK] = 1.0 if f.wheel == "left" else 2.0

    # ----------------------------------------------------------------- ground truth
    def true_pose(self) -> Pose2D:
        """Ground-truth pose of base_link in ``map``."""
        x, y, th = self._st[:3].tolist()
        return Pose2D(x, y, th)

    def true_velocity(self) -> Twist:
        """The body's actual velocity (what the world saw, not what the wheels claim)."""
        st = self._st
        return Twist(float(st[ph.AVX]), float(st[ph.AVY]), float(st[ph.AWZ]))

    def set_pose(self, pose: Pose2D, stop: bool = True) -> bool:
        """Teleport the robot (a kidnapping: odometry does not see it). Returns whether the body
        now overlaps something; it stays put until moved out of it."""
        st = self._st
        st[ph.X], st[ph.Y], st[ph.TH] = pose.x, pose.y, normalize_angle(pose.theta)
        if stop:
            for i in (ph.VX, ph.VY, ph.WZ, ph.AVX, ph.AVY, ph.AWZ):
                st[i] = 0.0
            self._cmd = (0.0, 0.0, 0.0)
        return self.overlapping()

    def overlapping(self) -> bool:
        """Whether the footprint overlaps the map or an object at the current true pose."""
        w = self.world
        c, s = w.shapes_at(self.time)
        st = self._st
        return bool(ph.footprint_hits(self._fp, self._lim[ph.L_RMAX], st[ph.X], st[ph.Y],
                                      st[ph.TH], w.blocked, w.clearance, w.origin_x, w.origin_y,
                                      w.resolution, c, s))

    def bumper_pressed(self) -> bool:
        return self.time - self._last_blocked <= self._bumper_hold + _EPS

    def in_collision(self) -> bool:
        """The bumper is pressed or the body overlaps something (RobotIO of the executive)."""
        return self.bumper_pressed() or self.overlapping()

    # ----------------------------------------------------------------- sensors

    def _odometry(self) -> Odometry:
        """The newest odometry message, built on first read after each publication."""
        st = self._st
        msg = self._odom_msg
        if msg is not None and st.item(_O_STAMP) == self._odom_msg_step:
            return msg
        # the kernel keeps the whole message in one block: a single conversion
        x, y, th, vx, vy, wz, var_x, var_y, var_w, step = st[_ODOM_BLOCK].tolist()
        tc = np.zeros((3, 3))
        tc[0, 0] = var_x
        tc[1, 1] = var_y
        tc[2, 2] = var_w
        self._odom_msg = msg = Odometry(self._t0 + step * self._dt, Pose2D(x, y, th),
                                        Twist(vx, vy, wz), _ODOM_POSE_COV, tc)
        self._odom_msg_step = step
        return msg

    def _imu(self) -> Imu | None:
        """The newest IMU message, built on first read after each sample."""
        ic = self.config.imu
        if ic is None:
            return None
        st = self._st
        stamp = self._t0 + float(st[ph.I_STAMP]) * self._dt
        msg = self._imu_msg
        if msg is not None and msg.stamp == stamp:
            return msg
        m = self.config.imu_mount.theta
        c, s = math.cos(m), math.sin(m)
        ax, ay = float(st[ph.I_AX]), float(st[ph.I_AY])
        var = ic.gyro_noise_stddev ** 2
        elapsed = stamp - self._t0
        self._imu_msg = Imu(stamp, float(st[ph.I_YAW]), float(st[ph.I_RATE]), c * ax + s * ay,
                            -s * ax + c * ay, yaw_variance=max(var * elapsed, 1e-9),
                            angular_velocity_variance=var)
        return self._imu_msg

    def laser_pose(self) -> Pose2D:
        """True pose of the laser frame in ``map``."""
        return Pose2D(*ph.laser_xyt(self._st, self._laser))

    def _next_laser_seed(self) -> int:
        """The next per-scan noise seed, drawn from the laser's stream 256 at a time."""
        if not self._laser_seeds:
            self._laser_seeds = self._rng_laser.integers(0, 2 ** 32, 256).tolist()[::-1]
        return self._laser_seeds.pop()

    def _scan_published(self) -> None:
        """Count the scan due now as done and schedule the next."""
        self._scan_k += 1
        self._next_scan = _ceil_step(self._scan_k * self._scan_period)

    def _scan_buffer(self, t: float) -> tuple[np.ndarray, int]:
        """Where to cast the scan due at time t, and its noise seed; ``_NO_SCAN`` when a fault
        keeps the laser from scanning (drop-out, or frozen on an earlier scan)."""
        if self._faults and (self.fault_active("laser_dropout", t) is not None
                             or (self.fault_active("laser_frozen", t) is not None
                                 and self._scan_msg is not None)):
            return _NO_SCAN, 0
        seed = self._next_laser_seed() if self._noisy_laser else 0
        return np.empty(self._n_beams, np.float32), seed

    def _scan_message(self, out: np.ndarray) -> None:
        """Publish the scan of the current step: ``out`` as cast, or what a fault makes of it."""
        now = self.time
        if out is _NO_SCAN:
            if self.fault_active("laser_dropout", now) is not None:
                return
            out = self._scan_msg.ranges.copy()  # frozen: the last scan again
        lc = self.config.laser
        self._scan_msg = LaserScan(now, lc.angle_min, lc.angle_max, lc.angle_increment,
                                   lc.time_increment, lc.scan_time, lc.range_min, lc.range_max,
                                   out)

    def _publish_scan(self) -> None:
        """Cast and publish a scan at the current step on its own (no motion): at start-up and
        where the world changes with time."""
        out, seed = self._scan_buffer(self.time)
        if out is not _NO_SCAN:
            w = self.world
            circles, segments = w.shapes_at(self.time)
            ph.physics_steps(self._kv, 0.0, 0.0, 0.0, 0, 0, self._step, False, self._fp,
                             w.blocked, w.clearance, circles, segments, self._odom_normals,
                             self._imu_normals, seed, out)
        self._scan_message(out)

    # ----------------------------------------------------------------- battery
    def _battery_fraction(self) -> float:
        idle, per_m, per_rad, capacity, initial, _, _ = self._battery
        st = self._st
        used = (idle * (self.time - self._t0) + per_m * float(st[ph.DIST])
                + per_rad * float(st[ph.ROT]))
        return max(0.0, initial - used / capacity)

    def _battery_state(self) -> BatteryState:
        f = self._battery_fraction()
        v_empty, v_full = self._battery[5], self._battery[6]
        return BatteryState(v_empty + f * (v_full - v_empty), f)
