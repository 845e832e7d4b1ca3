"""hw.sim sensors: laser ranges against analytic distances, presets, rates, noise; odometry noise
statistics against the amcl alpha model; IMU; battery; scripted faults."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hw.sim import Circle, Simulator, SimWorld
from hw.sim.noise import standard_normals
from hw.sim.sensors import odometry_noise_step
from navcore.clock import SimClock
from navcore.maps import OccupancyGrid
from navcore.types import Pose2D, Twist
from tests.test_raycast import analytic_box_range as box_range
from tests.test_raycast import box_world as box_cells

RES = 0.05
QUIET = {"odom_alpha1": 0.0, "odom_alpha2": 0.0, "odom_alpha3": 0.0, "odom_alpha4": 0.0,
         "odom_alpha5": 0.0}


def box_world(n: int = 100) -> SimWorld:
    """n x n cells, 2-cell walls: the free inside is [0.1, (n - 2) * RES]^2."""
    return SimWorld(OccupancyGrid(box_cells(n).astype(np.int16) * 100, RES))


def make(world: SimWorld, robot: dict, start: Pose2D = Pose2D(), seed: int = 0
         ) -> tuple[Simulator, SimClock]:
    clock = SimClock()
    return Simulator(world, robot, clock, np.random.default_rng(seed), start=start), clock


@pytest.mark.parametrize("preset", ["urg04lx", "lms200", "lms291"])
def test_ranges_in_a_box_world_match_the_analytic_distances(preset):
    world = box_world()
    start = Pose2D(2.1, 1.7, 0.6)
    laser = {"preset": preset, "range_noise_stddev": 0.0, "mount": [0.12, -0.05, 0.3]}
    sim, _ = make(world, {"laser": laser}, start)
    scan = sim.laser.scan()
    lp = start.compose(Pose2D(0.12, -0.05, 0.3))
    want = [box_range(lp.x, lp.y, lp.theta + a, 0.1, 4.9) for a in scan.angles()]
    np.testing.assert_allclose(scan.ranges, want, atol=2e-6)


def test_ranges_around_a_circle_match_the_analytic_distances():
    world = box_world(200)
    cx, cy, r = 6.0, 5.0, 0.7
    world.add(Circle(cx, cy, r))
    start = Pose2D(3.0, 4.4, 0.1)
    sim, _ = make(world, {"laser": {"preset": "lms291", "range_noise_stddev": 0.0}}, start)
    scan = sim.laser.scan()
    hits = 0
    for a, got in zip(scan.angles(), scan.ranges):
        dx, dy = math.cos(start.theta + a), math.sin(start.theta + a)
        ox, oy = start.x - cx, start.y - cy
        b = ox * dx + oy * dy
        disc = b * b - (ox * ox + oy * oy - r * r)
        if disc > 1e-9 and -b - math.sqrt(disc) > 0:
            assert got == pytest.approx(-b - math.sqrt(disc), abs=2e-6)
            hits += 1
        else:
            assert got == pytest.approx(box_range(start.x, start.y, start.theta + a, 0.1, 9.9),
                                        abs=2e-6)
    assert hits > 20  # the circle spans about 27 degrees, 54 beams of 0.5 degrees


def test_presets_carry_the_tuning_guide_header_values():
    world = box_world()
    for preset, beams, inc, t_inc, rmax in [
            ("lms200", 181, 0.0174532923847, 3.70370362361e-05, 81.0),
            ("lms291", 361, 0.00872664619235, 7.40740724722e-05, 81.0),
            ("urg04lx", 682, 2 * math.pi / 1024, 60 / (600 * 1024), 5.6)]:
        sim, _ = make(world, {"laser": {"preset": preset}}, Pose2D(2.5, 2.5, 0))
        s = sim.laser.scan()
        assert len(s.ranges) == beams
        assert s.angle_increment == pytest.approx(inc, rel=1e-9)
        assert s.time_increment == pytest.approx(t_inc, rel=1e-9)
        assert s.range_max == rmax
        if preset != "urg04lx":
            assert (s.angle_min, s.scan_time, s.range_min) == (-1.57079637051, 0.0133333336562, 0.0)
        else:
            assert s.angle_min == pytest.approx(-119.53125 * math.pi / 180)
            assert (s.scan_time, s.range_min) == (0.1, 0.02)


def test_scans_arrive_at_the_scan_rate_and_beams_can_be_overridden():
    world = box_world()
    sim, clock = make(world, {"laser": {"preset": "lms200", "beams": 90, "rate": 20.0}},
                      Pose2D(2.5, 2.5, 0))
    assert len(sim.laser.scan().ranges) == 90
    stamps = []
    for _ in range(50):
        clock.advance(0.01)
        sim.step()
        stamps.append(sim.laser.scan().stamp)
    assert sorted(set(stamps)) == pytest.approx([0.05 * k for k in range(0, 11)])


def test_beams_that_hit_nothing_read_inf_or_range_max():
    world = SimWorld(OccupancyGrid(np.zeros((400, 400), np.int16), RES))
    for no_return, want in (("inf", math.inf), ("range_max", 5.6)):
        sim, _ = make(world, {"laser": {"no_return": no_return}}, Pose2D(10, 10, 0))
        assert np.all(sim.laser.scan().ranges == np.float32(want))


def test_range_noise_has_the_configured_spread():
    world = box_world()
    start = Pose2D(2.5, 2.5, 0.0)
    sim, clock = make(world, {"laser": {"preset": "lms291", "range_noise_stddev": 0.03}}, start)
    truth = np.array([box_range(2.5, 2.5, a, 0.1, 4.9) for a in sim.laser.scan().angles()])
    errs = []
    for _ in range(20):
        clock.advance(0.1)
        sim.step()
        errs.append(sim.laser.scan().ranges - truth)
    errs = np.concatenate(errs)
    assert abs(errs.mean()) < 0.002
    assert errs.std() == pytest.approx(0.03, rel=0.05)


def test_laser_noise_stream_is_seeded_and_standard_normal():
    """The kernel's own generator: one seed one stream (a prefix of a longer draw), other seeds
    other streams, and the draws are N(0, 1): moments, tail mass beyond the ziggurat's base
    strip, no lag-one correlation, and a Kolmogorov-Smirnov distance below its 1% critical
    value."""
    for n in (0, 1, 2, 7, 720):
        a = standard_normals(12345, n)
        assert a.shape == (n,) and np.array_equal(a, standard_normals(12345, n))
        assert np.array_equal(a, standard_normals(12345, 2500)[:n])
    assert not np.array_equal(standard_normals(1, 720), standard_normals(2, 720))
    # neighbouring seeds (the laser draws one a scan) start unrelated streams, not shifted copies
    a, b = standard_normals(5, 400), standard_normals(6, 400)
    assert not np.isin(a, b).any()
    r = 3.6541528853610088
    tail = math.erfc(r / math.sqrt(2.0))  # P(|z| > r)
    for seed in (0, 2 ** 32 - 1):
        z = standard_normals(seed, 400_000)
        n = len(z)
        assert abs(z.mean()) < 4.0 / math.sqrt(n)
        assert abs(z.var() - 1.0) < 4.0 * math.sqrt(2.0 / n)
        assert abs((z ** 4).mean() - 3.0) < 4.0 * math.sqrt(96.0 / n)
        assert abs(np.mean(np.abs(z) > r) - tail) < 4.0 * math.sqrt(tail / n)
        assert abs(np.corrcoef(z[:-1], z[1:])[0, 1]) < 4.0 / math.sqrt(n)
        s = np.sort(z[:100_000])
        cdf = 0.5 * (1.0 + np.array([math.erf(v / math.sqrt(2.0)) for v in s]))
        k = np.arange(len(s))
        d = max(np.max((k + 1) / len(s) - cdf), np.max(cdf - k / len(s)))
        assert d < 1.63 / math.sqrt(len(s))


# --------------------------------------------------------------------------- odometry noise

def _odometry_increments(robot: dict, cmd: Twist, runs: int, periods: int) -> np.ndarray:
    """Per-period odometry increments (in the previous odometry frame) over many seeded runs;
    the true motion per period is the same in every one."""
    world = SimWorld(OccupancyGrid(np.zeros((40, 40), np.int16), 1.0, Pose2D(-20, -20)))
    robot = dict(robot, acc_lim_x=1e6, acc_lim_y=1e6, acc_lim_theta=1e6,
                 laser={"enabled": False}, imu={"enabled": False})
    incs = []
    for seed in range(runs):
        sim, clock = make(world, robot, seed=seed)
        prev = sim.base.odometry().pose
        for _ in range(periods):
            sim.base.send(cmd)
            clock.advance(0.02)
            sim.step()
            pose = sim.base.odometry().pose
            d = pose.relative_to(prev)
            incs.append((d.x, d.y, d.theta))
            prev = pose
    return np.array(incs)


ALPHAS = {"odom_alpha1": 0.2, "odom_alpha2": 0.1, "odom_alpha3": 0.3, "odom_alpha4": 0.15,
          "odom_alpha5": 0.25}


def test_diff_odometry_noise_matches_the_alpha_model_driving_straight():
    v, T = 0.5, 0.02
    inc = _odometry_increments(ALPHAS, Twist(v, 0, 0), runs=150, periods=20)
    t = v * T
    # straight: rot1 = rot2 = 0, so trans ~ N(t, a3 t^2), heading ~ N(0, 2 a2 t^2)
    assert inc[:, 0].mean() == pytest.approx(t, abs=4 * math.sqrt(0.3 * t * t / len(inc)))
    assert inc[:, 0].var() == pytest.approx(0.3 * t * t, rel=0.1)
    assert inc[:, 2].mean() == pytest.approx(0.0, abs=4 * math.sqrt(0.2 * t * t / len(inc)))
    assert inc[:, 2].var() == pytest.approx(2 * 0.1 * t * t, rel=0.1)


def test_diff_odometry_noise_matches_the_alpha_model_turning_in_place():
    w, T = 1.0, 0.02
    inc = _odometry_increments(ALPHAS, Twist(0, 0, w), runs=150, periods=20)
    r = w * T
    # in place: rot1 = 0, rot2 = r; heading ~ N(r, a1 r^2); translation noise a4 r^2
    assert inc[:, 2].mean() == pytest.approx(r, abs=4 * math.sqrt(0.2 * r * r / len(inc)))
    assert inc[:, 2].var() == pytest.approx(0.2 * r * r, rel=0.1)
    assert inc[:, 0].var() == pytest.approx(0.15 * r * r, rel=0.1)


def test_omni_odometry_noise_matches_the_alpha_model():
    v, T = 0.4, 0.02
    inc = _odometry_increments(dict(ALPHAS, kinematics="omni"), Twist(v, 0, 0), runs=150,
                               periods=20)
    t = v * T
    # omni-corrected: trans ~ N(t, a3 t^2), rot ~ N(0, a2 t^2), strafe ~ N(0, a5 t^2)
    assert inc[:, 0].var() == pytest.approx(0.3 * t * t, rel=0.1)
    assert inc[:, 2].var() == pytest.approx(0.1 * t * t, rel=0.1)
    assert inc[:, 1].var() == pytest.approx(0.25 * t * t, rel=0.1)


@pytest.mark.parametrize("kinematics", ["diff", "omni"])
def test_odometry_twist_covariance_is_the_alpha_model_over_one_period(kinematics):
    """Each message's twist covariance is amcl's variance of one odometry period's motion at the
    published twist, divided by the period squared; the pose covariance is the fixed diagonal."""
    world = SimWorld(OccupancyGrid(np.zeros((40, 40), np.int16), 1.0, Pose2D(-20, -20)))
    robot = dict(ALPHAS, kinematics=kinematics, odom_rate=50.0, laser={"enabled": False},
                 imu={"enabled": False})
    sim, clock = make(world, robot)
    a1, a2, a3, a4, a5 = 0.2, 0.1, 0.3, 0.15, 0.25
    p = 0.02
    seen, strafe_var = set(), []
    for k in range(40):
        sim.base.send(Twist(0.4, 0.1 if kinematics == "omni" else 0.0, 0.6 if k < 20 else -0.3))
        clock.advance(0.05)
        sim.step()
        odom = sim.base.odometry()
        seen.add(odom.stamp)
        tw = odom.twist
        t2 = (tw.vx ** 2 + tw.vy ** 2) * p * p
        r2 = (tw.wz * p) ** 2
        strafe = (a4 * r2 + a5 * t2) / (p * p) if kinematics == "omni" else 0.0
        expect = np.diag([(a3 * t2 + a4 * r2) / (p * p) + 1e-9, strafe + 1e-9,
                          (a1 * r2 + a2 * t2) / (p * p) + 1e-9])
        np.testing.assert_allclose(odom.twist_covariance, expect, rtol=1e-12, atol=0.0)
        np.testing.assert_array_equal(odom.pose_covariance, np.diag([1e-3] * 3))
        assert sim.base.odometry() is odom  # read again before the next publication: same
        strafe_var.append(odom.twist_covariance[1, 1])
    assert len(seen) == 40  # a new message every read (odometry 50 Hz, reads 20 Hz)
    assert (max(strafe_var) > 1e-3) == (kinematics == "omni")


def test_odometry_noise_step_drives_backwards_without_half_turn_noise():
    # straight back 1 cm: rot1 = pi, but its noise term uses the distance to pi, i.e. 0
    n = np.array([1.0, 0.0, 1.0])
    x, y, th = odometry_noise_step(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.01, 0.0, 0.0,
                                   0.0, 0.0, 0.0, 0.0, 0.0, False, n[0], n[1], n[2])
    assert (x, y, th) == pytest.approx((-0.01, 0.0, 0.0), abs=1e-12)
    x, y, th = odometry_noise_step(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.01, 0.0, 0.0,
                                   1.0, 0.0, 0.0, 0.0, 0.0, False, n[0], n[1], n[2])
    assert th == pytest.approx(0.0, abs=1e-12)


# --------------------------------------------------------------------------- imu and battery

def test_imu_reads_yaw_rate_with_bias_and_integrates_it():
    world = SimWorld(OccupancyGrid(np.zeros((40, 40), np.int16), 1.0, Pose2D(-20, -20)))
    imu = {"gyro_noise_stddev": 0.01, "gyro_bias": 0.02, "rate": 100.0}
    sim, clock = make(world, dict(QUIET, laser={"enabled": False}, imu=imu))
    rates = []
    for _ in range(200):
        sim.base.send(Twist(0.0, 0.0, 0.5))
        clock.advance(0.01)
        sim.step()
        rates.append(sim.imu.imu().angular_velocity_z)
    rates = np.array(rates[50:])  # after the acceleration ramp
    assert rates.mean() == pytest.approx(0.52, abs=0.003)
    assert rates.std() == pytest.approx(0.01, rel=0.2)
    # the gyro's yaw drifts from the truth by the bias integral (0.02 rad/s for 2 s)
    drift = math.remainder(sim.imu.imu().yaw - sim.true_pose().theta, 2 * math.pi)
    assert drift == pytest.approx(0.04, abs=0.005)


def test_battery_drains_faster_when_moving():
    world = SimWorld(OccupancyGrid(np.zeros((200, 200), np.int16), 0.5, Pose2D(-50, -50)))
    robot = {"laser": {"enabled": False}, "battery": {"capacity_wh": 1.0}}
    idle, c1 = make(world, robot)
    busy, c2 = make(world, robot)
    for _ in range(200):
        busy.base.send(Twist(1.0, 0.0, 0.5))
        c1.advance(0.05)
        c2.advance(0.05)
        idle.step()
        busy.step()
    used_idle = 1.0 - idle.base.battery().percentage
    used_busy = 1.0 - busy.base.battery().percentage
    assert used_idle == pytest.approx(5.0 * 10.0 / 3600.0, rel=1e-6)  # idle_power_w * 10 s
    assert used_busy > used_idle + 20.0 * 9.0 / 3600.0  # 20 J/m for about 9.5 m more
    assert busy.base.battery().voltage < idle.base.battery().voltage


# --------------------------------------------------------------------------- faults

def test_laser_dropout_and_frozen_laser():
    world = box_world()
    sim, clock = make(world, dict(QUIET, laser={"range_noise_stddev": 0.0}),
                      Pose2D(2.5, 2.5, 0.0))
    sim.inject("laser_dropout", start=1.0, duration=1.0)
    sim.add_fault({"kind": "laser_frozen", "start": 3.0, "duration": 1.0})
    log = {}
    for k in range(50):
        sim.base.send(Twist(0.0, 0.0, 0.5))
        clock.advance(0.1)
        sim.step()
        s = sim.laser.scan()
        log[round(clock.now(), 1)] = (s.stamp, s.ranges.copy())
    assert log[1.5][0] == pytest.approx(0.9)  # nothing new during the drop-out
    assert log[2.0][0] == pytest.approx(2.0)  # back on time
    assert log[3.5][0] == pytest.approx(3.5)  # frozen: fresh stamps ...
    np.testing.assert_array_equal(log[3.5][1], log[2.9][1])  # ... but stale ranges
    assert not np.array_equal(log[4.0][1], log[2.9][1])  # the robot turned meanwhile


def test_odometry_slip_wheels_turn_robot_stands():
    world = SimWorld(OccupancyGrid(np.zeros((40, 40), np.int16), 1.0, Pose2D(-20, -20)))
    sim, clock = make(world, dict(QUIET, laser={"enabled": False}))
    sim.inject("odom_slip", start=0.0, duration=2.0)
    for _ in range(60):
        sim.base.send(Twist(0.4, 0, 0))
        clock.advance(0.05)
        sim.step()
    # 2 s of spinning wheels (less 3 cm lost on the 16-step ramp: sum of 0.025 k * 0.01 m is
    # 3.4 cm instead of 6.4), then 1 s of real driving
    assert sim.base.odometry().pose.x == pytest.approx(1.2 - 0.064 + 0.034, abs=1e-9)
    assert sim.true_pose().x == pytest.approx(0.4, abs=1e-9)


def test_blocked_rotation_turns_the_wheels_not_the_body():
    world = SimWorld(OccupancyGrid(np.zeros((40, 40), np.int16), 1.0, Pose2D(-20, -20)))
    sim, clock = make(world, dict(QUIET, laser={"enabled": False},
                                  imu={"gyro_bias": 0.0, "gyro_noise_stddev": 0.0}))
    sim.inject("blocked_rotation", start=0.0)
    for _ in range(20):
        sim.base.send(Twist(0.0, 0.0, 1.0))
        clock.advance(0.05)
        sim.step()
    assert sim.true_pose().theta == 0.0
    assert sim.imu.imu().angular_velocity_z == 0.0
    assert sim.base.odometry().pose.theta > 0.5


def test_stuck_wheel_pivots_about_it():
    world = SimWorld(OccupancyGrid(np.zeros((40, 40), np.int16), 1.0, Pose2D(-20, -20)))
    sim, clock = make(world, dict(QUIET, wheel_separation=0.4, acc_lim_x=1e6,
                                  acc_lim_theta=1e6, laser={"enabled": False}))
    sim.inject("stuck_wheel", start=0.0, duration=10.0, wheel="left")
    for _ in range(20):
        sim.base.send(Twist(0.2, 0.0, 0.0))
        clock.advance(0.05)
        sim.step()
    # right wheel at 0.2 m/s, left stopped: v = 0.1 m/s, w = 0.5 rad/s about the left wheel
    assert sim.true_velocity().vx == pytest.approx(0.1)
    assert sim.true_velocity().wz == pytest.approx(0.5)
    p = sim.true_pose()
    assert p.theta == pytest.approx(0.5)
    assert math.hypot(p.x - 0.0, p.y - 0.2) == pytest.approx(0.2, abs=1e-9)  # circle about it
    o = sim.base.odometry().pose
    assert (o.x, o.y, o.theta) == pytest.approx((p.x, p.y, p.theta), abs=1e-9)


def test_constant_wheel_slip_makes_odometry_over_read():
    world = SimWorld(OccupancyGrid(np.zeros((40, 40), np.int16), 1.0, Pose2D(-20, -20)))
    sim, clock = make(world, dict(QUIET, wheel_slip=0.1, laser={"enabled": False}))
    for _ in range(40):
        sim.base.send(Twist(0.5, 0, 0))
        clock.advance(0.05)
        sim.step()
    assert sim.true_pose().x == pytest.approx(0.9 * sim.base.odometry().pose.x, rel=1e-9)
    assert sim.travelled == pytest.approx(sim.base.odometry().pose.x, rel=1e-9)
