"""hw.sim motion: kinematics against closed-form arcs, acceleration limits, command timeout,
collisions (no tunnelling, contact stops and is reported)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hw.interfaces import Base, ImuSensor, Laser
from hw.sim import Circle, MovingObstacle, Pole, Polygon, Simulator, SimWorld
from navcore.clock import SimClock
from navcore.maps import OccupancyGrid
from navcore.types import Pose2D, Twist

RES = 0.05
FAST = {"acc_lim_x": 1e6, "acc_lim_y": 1e6, "acc_lim_theta": 1e6, "max_vel_x": 5.0,
        "max_vel_y": 5.0, "max_vel_theta": 5.0, "odom_alpha1": 0.0, "odom_alpha2": 0.0,
        "odom_alpha3": 0.0, "odom_alpha4": 0.0, "odom_alpha5": 0.0,
        "laser": {"enabled": False}, "imu": {"enabled": False}}


def open_world(size: float = 40.0) -> SimWorld:
    n = int(size / RES)
    return SimWorld(OccupancyGrid(np.zeros((n, n), np.int16), RES, Pose2D(-size / 2, -size / 2)))


def drive(sim: Simulator, clock: SimClock, cmd: Twist, seconds: float, period: float = 0.05
          ) -> None:
    for _ in range(int(round(seconds / period))):
        sim.base.send(cmd)
        clock.advance(period)
        sim.step()


def make(world: SimWorld, robot: dict, start: Pose2D = Pose2D(), seed: int = 0
         ) -> tuple[Simulator, SimClock]:
    clock = SimClock()
    return Simulator(world, robot, clock, np.random.default_rng(seed), start=start), clock


def test_implements_the_hw_interfaces():
    sim, _ = make(open_world(), {})
    assert isinstance(sim.base, Base)
    assert isinstance(sim.laser, Laser)
    assert isinstance(sim.imu, ImuSensor)
    assert sim.base.odometry() is not None and sim.laser.scan() is not None
    assert sim.imu.imu() is not None and sim.base.battery().percentage == 1.0


@pytest.mark.parametrize("v,w", [(0.5, 0.4), (0.8, -1.3), (-0.3, 0.7), (0.6, 0.0)])
def test_diff_drive_follows_the_closed_form_arc(v, w):
    start = Pose2D(1.0, -2.0, 0.7)
    sim, clock = make(open_world(), dict(FAST), start)
    drive(sim, clock, Twist(v, 0.3, w), 3.0)  # vy is ignored by a differential drive
    t = 3.0  # a command sent at time t acts from the physics step that starts at t
    th = start.theta + w * t
    if w == 0.0:
        x, y = start.x + v * t * math.cos(th), start.y + v * t * math.sin(th)
    else:
        x = start.x + v / w * (math.sin(th) - math.sin(start.theta))
        y = start.y - v / w * (math.cos(th) - math.cos(start.theta))
    p = sim.true_pose()
    assert p.x == pytest.approx(x, abs=1e-9)
    assert p.y == pytest.approx(y, abs=1e-9)
    assert math.remainder(p.theta - th, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    # noise-free odometry is the same motion seen from the start pose
    o = sim.base.odometry().pose
    rel = p.relative_to(start)
    assert (o.x, o.y) == pytest.approx((rel.x, rel.y), abs=1e-9)
    assert math.remainder(o.theta - rel.theta, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    assert sim.base.odometry().twist.vx == pytest.approx(v, abs=1e-9)
    assert sim.base.odometry().twist.wz == pytest.approx(w, abs=1e-9)


def test_omni_drive_follows_the_closed_form_arc():
    start = Pose2D(0.0, 0.0, -0.4)
    vx, vy, w = 0.4, -0.3, 0.5
    sim, clock = make(open_world(), dict(FAST, kinematics="omni"), start)
    drive(sim, clock, Twist(vx, vy, w), 2.0)
    t = 2.0
    th0, th = start.theta, start.theta + w * t
    # integrate the body velocity rotated into the world: closed form
    x = (vx * (math.sin(th) - math.sin(th0)) + vy * (math.cos(th) - math.cos(th0))) / w
    y = (-vx * (math.cos(th) - math.cos(th0)) + vy * (math.sin(th) - math.sin(th0))) / w
    p = sim.true_pose()
    assert (p.x, p.y, p.theta) == pytest.approx((x, y, th), abs=1e-9)
    assert sim.true_velocity() == Twist(pytest.approx(vx), pytest.approx(vy), pytest.approx(w))


def test_velocity_ramps_within_the_acceleration_limits_and_clamps_to_the_maximum():
    robot = dict(FAST, acc_lim_x=2.0, acc_lim_theta=4.0, max_vel_x=0.8, max_vel_theta=1.0)
    sim, clock = make(open_world(), robot)
    speeds = []
    for _ in range(40):
        sim.base.send(Twist(1.5, 0.0, 3.0))
        clock.advance(0.01)
        sim.step()
        speeds.append((sim.true_velocity().vx, sim.true_velocity().wz))
    speeds = np.array(speeds)
    t = 0.01 * np.arange(1, 41)
    np.testing.assert_allclose(speeds[:, 0], np.minimum(2.0 * t, 0.8), atol=1e-9)
    np.testing.assert_allclose(speeds[:, 1], np.minimum(4.0 * t, 1.0), atol=1e-9)


def test_command_timeout_brakes_to_zero():
    robot = dict(FAST, acc_lim_x=1.0, cmd_vel_timeout=0.3)
    sim, clock = make(open_world(), robot)
    drive(sim, clock, Twist(0.5, 0, 0), 1.0)  # at speed
    assert sim.true_velocity().vx == pytest.approx(0.5)
    clock.advance(0.25)
    sim.step()
    assert sim.true_velocity().vx == pytest.approx(0.5)  # still within the timeout
    clock.advance(0.1)
    sim.step()
    assert 0.0 < sim.true_velocity().vx < 0.5  # braking at acc_lim_x
    clock.advance(0.5)
    sim.step()
    assert sim.true_velocity().vx == 0.0


def wall_world(wall: str) -> tuple[SimWorld, float]:
    """A 10 x 4 m room; a thin obstacle across it at x = 5 m. Returns the world and the x of the
    obstacle's near face."""
    grid = np.zeros((80, 200), np.int16)
    grid[0, :] = grid[-1, :] = 100
    grid[:, 0] = grid[:, -1] = 100
    objects = []
    face = 5.0
    if wall == "map":
        grid[:, 100] = 100  # one cell thick: x in [5.0, 5.05)
    elif wall == "segment":
        objects.append(Polygon(((5.0, -1.0), (5.0, 5.0))))  # zero thickness
    elif wall == "poles":
        # a fence of thin poles, gaps narrower than the robot
        objects += [Pole(5.01, y, 0.01) for y in np.arange(0.1, 4.0, 0.3)]
    return SimWorld(OccupancyGrid(grid, RES), objects), face


@pytest.mark.parametrize("wall", ["map", "segment", "poles"])
def test_no_tunnelling_through_thin_walls_at_full_speed(wall):
    world, face = wall_world(wall)
    # a coarse physics period and a fast robot: 10 cm per step, twice the map cell
    robot = dict(FAST, physics_period=0.05, max_vel_x=2.0)
    sim, clock = make(world, robot, Pose2D(1.0, 2.0, 0.0))
    drive(sim, clock, Twist(2.0, 0, 0), 4.0)
    p = sim.true_pose()
    assert p.x + 0.25 <= face + 1e-9  # the front edge (0.25 m ahead) never passed the wall
    assert p.x + 0.25 > face - 0.02  # ... and it stopped touching it, not short of it
    assert len(sim.contacts) == 1
    c = sim.contacts[0]
    assert c.speed == pytest.approx(2.0)
    assert 1.0 < c.time < 2.1
    assert c.pose.x == pytest.approx(p.x, abs=1e-3)  # then it crept into full contact


def test_contact_stops_the_robot_presses_the_bumper_and_it_can_back_away():
    world, face = wall_world("map")
    sim, clock = make(world, dict(FAST, bumper_hold=0.1), Pose2D(4.0, 2.0, 0.0))
    drive(sim, clock, Twist(0.5, 0, 0), 3.0)
    assert sim.true_velocity().vx == 0.0
    assert sim.base.events().bumper and sim.in_collision()
    assert len(sim.contacts) == 1  # pushing on is one contact, not one per step
    assert not sim.overlapping()
    x_stuck = sim.true_pose().x
    odo_stuck = sim.base.odometry().pose.x
    drive(sim, clock, Twist(0.5, 0, 0), 1.0)  # pushing on: no motion, wheels stalled
    assert sim.true_pose().x == pytest.approx(x_stuck, abs=1e-3)
    assert sim.base.odometry().pose.x == pytest.approx(odo_stuck, abs=1e-3)
    drive(sim, clock, Twist(-0.3, 0, 0), 1.0)
    assert sim.true_pose().x < x_stuck - 0.25
    assert not sim.base.events().bumper
    assert len(sim.contacts) == 1


def test_rotation_into_a_wall_is_a_contact():
    grid = np.zeros((60, 60), np.int16)
    grid[:, 35] = 100  # wall at x = 1.75
    world = SimWorld(OccupancyGrid(grid, RES))
    # 0.25 m half-length body, centre 1.45: fits along x, but its corners sweep to 0.33 m
    sim, clock = make(world, dict(FAST), Pose2D(1.45, 1.5, 0.0))
    drive(sim, clock, Twist(0, 0, 1.0), 1.0)
    assert len(sim.contacts) == 1
    assert 0.0 < sim.true_pose().theta < 1.0


def test_a_moving_obstacle_that_runs_into_a_standing_robot_is_a_contact():
    world = open_world(20.0)
    world.add(MovingObstacle(((3.0, 0.0), (-3.0, 0.0)), speed=1.0, radius=0.2))
    sim, clock = make(world, dict(FAST))
    drive(sim, clock, Twist(), 4.0)
    assert len(sim.contacts) >= 1
    assert 2.0 < sim.contacts[0].time < 3.0  # its rim reaches the body's front at ~2.55 s
    assert sim.true_pose() == Pose2D()  # a standing robot is not pushed


def test_objects_appear_and_disappear_on_time():
    world = open_world(20.0)
    box = world.add(Circle(2.0, 0.0, 0.3, appear=1.0, disappear=2.0))
    sim, clock = make(world, {"laser": {"range_noise_stddev": 0.0, "range_max": 5.0,
                                        "no_return": "range_max"}})
    mid = int(np.argmin(np.abs(sim.config.laser.angles)))  # the beam pointing straight ahead
    seen = {}
    for t in (0.5, 1.5, 2.5):
        clock.sleep_until(t)
        sim.step()
        seen[t] = float(sim.laser.scan().ranges[mid])
    assert seen[0.5] == pytest.approx(5.0)
    assert seen[1.5] == pytest.approx(1.7, abs=1e-4)
    assert seen[2.5] == pytest.approx(5.0)
    world.remove(box)
    assert world.objects == ()
