"""hw.sim world and configuration: determinism, moving obstacles, clear errors for bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hw.sim import (Box, Circle, FaultError, MovingObstacle, Polygon, Simulator, SimWorld,
                    WorldError, fault_from_mapping, robot_config)
from navcore.clock import SimClock
from navcore.params import ParameterError
from navcore.synthetic_maps import office_map
from navcore.types import Pose2D, Twist


def office_world() -> SimWorld:
    w = SimWorld(office_map(200), unknown_is_obstacle=True)
    w.add(Circle(4.5, 1.5, 0.2))  # the 6 m room has a desk around (3, 2.8)
    w.add(MovingObstacle(((1.5, 4.5), (4.5, 4.5)), speed=0.6, radius=0.2, loop=True))
    return w


def trace(seed: int, period: float = 0.05, seconds: float = 6.0, world: SimWorld | None = None
          ) -> dict[str, list]:
    """Drive a scripted command sequence (changing every 0.1 s) and record everything."""
    world = world or office_world()
    clock = SimClock()
    sim = Simulator(world, {}, clock, np.random.default_rng(seed), start=Pose2D(1.5, 1.5, 0.3))
    out: dict[str, list] = {"true": [], "odom": [], "scan": [], "imu": []}
    n = int(round(seconds / period))
    for k in range(n):
        t = k * period
        if abs(t / 0.1 - round(t / 0.1)) < 1e-9:  # the command changes on a 0.1 s grid
            j = int(round(t / 0.1))
            sim.base.send(Twist(0.3 + 0.2 * math.sin(j * 0.3), 0.0, 0.8 * math.cos(j * 0.2)))
        clock.advance(period)
        sim.step()
        if abs((t + period) / 0.1 - round((t + period) / 0.1)) < 1e-9:
            out["true"].append(sim.true_pose().as_array())
            out["odom"].append(sim.base.odometry().pose.as_array())
            out["scan"].append(sim.laser.scan().ranges.copy())
            out["imu"].append(sim.imu.imu().angular_velocity_z)
    out["contacts"] = [(c.time, c.pose.x) for c in sim.contacts]
    return out


def same(a: dict, b: dict) -> bool:
    return all(np.array_equal(np.array(a[k]), np.array(b[k])) for k in a)


def test_same_seed_same_trace_other_seed_differs():
    world = office_world()
    a, b = trace(1, world=world), trace(1, world=world)
    assert np.ptp(np.array(a["true"])[:, 0]) > 0.5  # it really went somewhere
    assert same(a, b)
    c = trace(2, world=world)
    assert not np.array_equal(np.array(a["odom"]), np.array(c["odom"]))
    assert not np.array_equal(np.array(a["scan"]), np.array(c["scan"]))
    # the truth does not depend on sensor noise
    np.testing.assert_array_equal(np.array(a["true"]), np.array(c["true"]))


def test_trace_does_not_depend_on_how_time_is_stepped():
    world = office_world()
    coarse, fine = trace(5, period=0.1, world=world), trace(5, period=0.01, world=world)
    assert same(coarse, fine)


def test_moving_obstacle_waypoints_speed_pauses_and_loop():
    m = MovingObstacle(((0, 0), (2, 0), (2, 1)), speed=1.0, pauses=(0.0, 0.5, 1.0),
                       start_time=1.0)
    assert m.position(0.5) == (0, 0)  # waiting for its start
    assert m.position(2.0) == pytest.approx((1.0, 0.0))
    assert m.position(3.2) == pytest.approx((2.0, 0.0))  # pausing at waypoint 1
    assert m.position(4.0) == pytest.approx((2.0, 0.5))
    assert m.position(99.0) == pytest.approx((2.0, 1.0))  # stays at the end
    loop = MovingObstacle(((0, 0), (1, 0)), speed=0.5, loop=True)
    assert loop.position(1.0) == pytest.approx((0.5, 0.0))
    assert loop.position(3.0) == pytest.approx((0.5, 0.0))  # on the way back
    assert loop.position(4.0) == pytest.approx((0.0, 0.0))


def test_world_shapes_reduce_to_circles_and_segments():
    w = SimWorld(office_map(100))
    w.add(Box(1.0, 1.0, 2.0, 1.5))
    w.add(Polygon(((3, 3), (4, 3))))
    w.add(Circle(1.0, 1.0, 0.1, appear=5.0))
    w.add(MovingObstacle(((0.0, 0.0), (10.0, 0.0)), speed=1.0, half_extents=(0.2, 0.1)))
    c, s = w.shapes_at(2.0)
    assert c.shape == (0, 3) and s.shape == (4 + 1 + 4, 4)
    assert s[-4:, 0].min() == pytest.approx(1.8) and s[-4:, 0].max() == pytest.approx(2.2)
    c, s = w.shapes_at(6.0)
    assert c.shape == (1, 3)
    assert w.next_change(0.0) == 5.0 and w.next_change(5.0) == math.inf


def test_bad_world_input_gets_clear_errors():
    with pytest.raises(WorldError, match="radius"):
        Circle(0, 0, -1.0)
    with pytest.raises(WorldError, match="zero width"):
        Box(0, 0, 0, 1)
    with pytest.raises(WorldError, match="x must be a finite"):
        Circle(float("nan"), 0, 1)
    with pytest.raises(WorldError, match="pauses"):
        MovingObstacle(((0, 0), (1, 1)), pauses=(1.0,))
    with pytest.raises(WorldError, match="speed"):
        MovingObstacle(((0, 0), (1, 1)), speed=0.0)
    with pytest.raises(WorldError, match="expected Circle"):
        SimWorld(office_map(50)).add("a box")  # type: ignore[arg-type]


def test_robot_config_rejects_unknown_and_bad_keys():
    with pytest.raises(ParameterError, match="unknown parameter 'acc_lim_xx'.*acc_lim_x"):
        robot_config({"acc_lim_xx": 1.0})
    with pytest.raises(ParameterError, match="sim.laser: unknown parameter 'rang_max'"):
        robot_config({"laser": {"rang_max": 10.0}})
    with pytest.raises(ParameterError, match="kinematics"):
        robot_config({"kinematics": "ackermann"})
    with pytest.raises(ParameterError, match="must be a number"):
        robot_config({"max_vel_x": "fast"})
    with pytest.raises(ParameterError, match="mount"):
        robot_config({"laser": {"mount": [0.1, 0.0]}})
    with pytest.raises(ParameterError, match="preset"):
        robot_config({"laser": {"preset": "velodyne"}})
    with pytest.raises(ParameterError, match="footprint"):
        robot_config({"footprint": [[0.1, 0.1], [0.2]]})
    cfg = robot_config({"kinematics": "omni", "laser": {"preset": "lms291", "beams": 100},
                        "imu": {"enabled": False}})
    assert cfg.imu is None and len(cfg.laser.angles) == 100
    assert cfg.laser.angles[-1] == pytest.approx(1.57079637051)


def test_faults_from_scenario_mappings():
    f = fault_from_mapping({"type": "stuck_wheel", "start": 2, "duration": 3, "wheel": "right"})
    assert (f.kind, f.start, f.end, f.wheel) == ("stuck_wheel", 2, 5, "right")
    assert f.active(2.0) and f.active(4.99) and not f.active(5.0)
    with pytest.raises(FaultError, match="did you mean 'laser_dropout'"):
        fault_from_mapping({"kind": "laser_drop", "start": 1})
    with pytest.raises(FaultError, match="unknown key 'duraton'"):
        fault_from_mapping({"kind": "laser_dropout", "start": 1, "duraton": 2})
    with pytest.raises(FaultError, match="needs 'kind' and 'start'"):
        fault_from_mapping({"kind": "laser_dropout"})
    with pytest.raises(FaultError, match="slip"):
        fault_from_mapping({"kind": "odom_slip", "start": 0, "slip": 1.5})


def test_simulator_requires_a_seeded_generator_and_survives_bad_commands():
    world = SimWorld(office_map(100))
    with pytest.raises(TypeError, match="Generator"):
        Simulator(world, {}, SimClock(), 42)  # type: ignore[arg-type]
    clock = SimClock()
    sim = Simulator(world, {}, clock, np.random.default_rng(0), start=Pose2D(1.0, 1.0, 0.0))
    sim.base.send(Twist(float("nan"), 0.0, 0.0))
    clock.advance(0.5)
    sim.step()
    assert sim.rejected_commands == 1
    assert sim.true_pose() == Pose2D(1.0, 1.0, 0.0)


def test_set_pose_teleports_without_odometry_noticing():
    world = SimWorld(office_map(200))
    clock = SimClock()
    sim = Simulator(world, {}, clock, np.random.default_rng(0), start=Pose2D(1.0, 1.0, 0.0))
    assert sim.set_pose(Pose2D(4.0, 4.0, 1.0)) is False
    clock.advance(0.1)
    sim.step()
    assert sim.true_pose() == Pose2D(4.0, 4.0, 1.0)
    assert sim.base.odometry().pose == Pose2D()
    assert sim.set_pose(Pose2D(0.0, 0.0, 0.0)) is True  # in the outer wall
