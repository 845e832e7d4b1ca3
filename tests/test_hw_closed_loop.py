"""Closed loop through the real drivers: the simulator drives the Kobuki and URG-04LX emulators,
the executive talks to ``KobukiDriver`` and ``Urg04lxDriver`` over their ``sim://`` byte streams,
polled in lock-step on the simulated clock (``build_mission(..., hardware="emulated")``).

Nothing here reads the wall clock: one seed gives one run.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hw.devices import open_devices, poll_devices
from hw.drivers.kobuki import KobukiDriver
from hw.drivers.urg04lx import Urg04lxDriver
from hw.sim import Box, Simulator, SimWorld
from hw.sim.emulated_devices import SimDevices, lockstep_start
from navcore.clock import SimClock
from navcore.synthetic_maps import ascii_map
from navcore.types import Pose2D, Twist

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "tests" / "scenarios" / "goal_minus_x.yaml"
TREE = ROOT / "trees" / "move_base.yaml"

ROOM = "\n".join(["#" * 40] + ["#" + "." * 38 + "#"] * 28 + ["#" * 40])   # 4 m x 3 m


def _bench(tag: str, objects=(), start=Pose2D(1.0, 1.5, 0.0), **robot):
    """A simulator in a room with both emulators plugged and both drivers started in lock-step."""
    clock = SimClock()
    cfg = {"odom_alpha1": 0.0, "odom_alpha2": 0.0, "odom_alpha3": 0.0, "odom_alpha4": 0.0,
           "laser": {"preset": "urg04lx", "range_noise_stddev": 0.0, "mount": [0.1, 0.0, 0.0]}}
    cfg.update(robot)
    sim = Simulator(SimWorld(ascii_map(ROOM), list(objects)), cfg, clock,
                    np.random.default_rng(3), start=start)
    bridge = SimDevices(sim, np.random.default_rng(4), tag)
    urls = bridge.plug()
    drivers = open_devices({"base": urls["base"],
                            "laser": {"url": urls["laser"], "mount": [0.1, 0.0, 0.0]}},
                           clock, lockstep=True)
    lockstep_start(drivers, clock)
    return clock, sim, bridge, drivers


def _close(bridge, drivers) -> None:
    for d in drivers.values():
        d.close()
    bridge.unplug()


def test_emulated_laser_measures_the_simulated_world() -> None:
    """The URG driver's scan (SCIP bytes from the emulator) agrees beam by beam with the
    simulator's own laser, including a box only on the robot's left (no mirror, no offset)."""
    clock, sim, bridge, drivers = _bench("hcl-laser", [Box(1.4, 2.0, 1.8, 2.4)])
    try:
        for _ in range(3):
            clock.advance(0.1)
            poll_devices(drivers)
        sim.step_to(clock.now())
        scan, ref = drivers["laser"].scan(), sim.laser.scan()
        assert isinstance(drivers["laser"], Urg04lxDriver) and scan.range_max == 5.6
        a = ref.angle_min + ref.angle_increment * np.arange(len(ref.ranges))
        idx = np.round((a - scan.angle_min) / scan.angle_increment).astype(int)
        got, want = scan.ranges[idx], ref.ranges
        # sampled beams sit up to half a driver step (0.18 deg) apart; mm resolution on the wire
        assert np.all(np.isfinite(want))
        close = np.abs(got - want) < 0.02 + 0.004 * want
        assert close.mean() > 0.97, np.c_[a, got, want][~close]
        left = np.abs(a - math.atan2(0.7, 0.5)) < 0.05          # the box, up and to the left
        right = np.abs(a + math.atan2(0.7, 0.5)) < 0.05
        assert np.all(got[left] < 0.95) and np.all(got[right] > 1.0)
    finally:
        _close(bridge, drivers)


def test_emulated_base_moves_the_simulator_and_reports_its_contacts() -> None:
    """Kobuki commands become simulator motion; the encoders report the simulator's wheel
    odometry; driving into a wall presses the bumper the driver decodes."""
    clock, sim, bridge, drivers = _bench("hcl-base", max_vel_x=0.5)
    base = drivers["base"]
    try:
        assert isinstance(base, KobukiDriver) and base._thread is None
        for _ in range(20):                          # 2 s on an arc
            base.send(Twist(0.3, 0.0, 0.4))
            clock.advance(0.1)
            poll_devices(drivers)
        truth, odo = sim.true_pose(), base.odometry()
        assert 0.45 < truth.distance_to(Pose2D(1.0, 1.5)) < 0.65
        assert 0.55 < truth.theta < 0.85                    # 0.4 rad/s for 2 s, less the ramp
        # odometry starts at (0, 0, 0): compare motions (noise-free odometry, tick quantisation)
        moved = truth.relative_to(Pose2D(1.0, 1.5, 0.0))
        assert odo.pose.x == pytest.approx(moved.x, abs=0.005)
        assert odo.pose.y == pytest.approx(moved.y, abs=0.005)
        assert odo.pose.theta == pytest.approx(moved.theta, abs=0.01)
        assert bridge.base.commands and bridge.base.commands[-1][1:] == base.commanded()
        assert not base.events().bumper
        for _ in range(80):                          # straight on into the wall at x = 3.9
            base.send(Twist(0.4, 0.0, 0.0))
            clock.advance(0.1)
            poll_devices(drivers)
            if base.events().bumper:
                break
        assert base.events().bumper and sim.contacts
        assert sim.true_pose().x < 3.9
    finally:
        _close(bridge, drivers)


def test_laser_dropout_unplugs_the_emulated_laser_and_the_driver_reconnects() -> None:
    clock, sim, bridge, drivers = _bench("hcl-drop")
    laser = drivers["laser"]
    sim.inject("laser_dropout", start=clock.now() + 0.5, duration=1.0)
    try:
        stamps, connected = [], []
        for _ in range(30):
            clock.advance(0.1)
            poll_devices(drivers)
            stamps.append(laser.scan().stamp)
            connected.append(laser.connected)
        assert connected[:4] == [True] * 4 and not any(connected[6:14])
        assert connected[-1] and laser.connects == 2
        assert stamps[13] == stamps[6]                      # no scan while unplugged
        assert stamps[-1] > stamps[13] + 1.0                # scans again after the replug
        assert drivers["base"].connects == 1 and drivers["base"].rejected == 0
    finally:
        _close(bridge, drivers)


def test_frozen_laser_repeats_its_ranges_under_fresh_stamps() -> None:
    clock, sim, bridge, drivers = _bench("hcl-frozen", max_vel_x=0.5)
    laser, base = drivers["laser"], drivers["base"]
    sim.inject("laser_frozen", start=clock.now() + 0.3, duration=1.0)
    try:
        scans = []
        for _ in range(16):                                 # drive towards the far wall
            base.send(Twist(0.4, 0.0, 0.0))
            clock.advance(0.1)
            poll_devices(drivers)
            scans.append(laser.scan())
        frozen, live = scans[5:12], scans[13:]
        assert len({s.stamp for s in frozen}) == len(frozen)            # still streaming
        assert all(np.array_equal(s.ranges, frozen[0].ranges) for s in frozen)
        assert not np.array_equal(live[-1].ranges, live[0].ranges)       # moving again
        assert laser.connects == 1 and laser.rejected == 0
    finally:
        _close(bridge, drivers)


def test_simulator_without_a_laser_is_refused() -> None:
    sim = Simulator(SimWorld(ascii_map(ROOM)), {"laser": {"enabled": False}}, SimClock(),
                    np.random.default_rng(0), start=Pose2D(1.0, 1.5, 0.0))
    with pytest.raises(ValueError, match="no laser"):
        SimDevices(sim, np.random.default_rng(0))


def test_hardware_mode_names_the_choices() -> None:
    from executive.mission import WiringError, hardware_mode
    assert [hardware_mode(h) for h in (False, True, "emulated", "devices")] == \
        ["sim", "devices", "emulated", "devices"]
    with pytest.raises(WiringError, match="'emulated'"):
        hardware_mode("emulate")


def _run_scenario_through_drivers():
    from executive.world import World
    from executive.mission import build_mission, run_mission
    from executive.scenario import load_scenario, scenario_config
    s = load_scenario(SCENARIO)
    m = build_mission(str(TREE), scenario_config(s), s.grid, s.start,
                      world=World(s.objects, s.moving, s.phantoms, s.faults),
                      seed=s.seed, hardware="emulated")
    result = run_mission(m, s.goals, s.time_limit)
    return s, m, result


@pytest.fixture(scope="module")
def scenario_run():
    s, m, result = _run_scenario_through_drivers()
    yield s, m, result
    m.executive.shutdown()
    m.executive.io.close()


def test_catalogue_scenario_runs_end_to_end_through_the_drivers(scenario_run) -> None:
    """goal_minus_x with the move_base tree: the executive sees only the drivers (AMCL over the
    Kobuki odometry and URG scans), the simulator's truth confirms the robot got there."""
    from executive.mission import EmulatedIO
    s, m, result = scenario_run
    ex, io = m.executive, m.executive.io
    assert isinstance(io, EmulatedIO) and isinstance(ex.clock, SimClock)
    assert isinstance(io.base.driver, KobukiDriver) and isinstance(io.laser, Urg04lxDriver)
    assert all(d._thread is None and d.polling for d in io.devices.values())
    assert m.components["localizer"] is not None
    assert result.outcome == "succeeded", result.reason
    assert result.collisions == 0 and not m.sim.contacts
    goal, truth = s.goals[-1], m.sim.true_pose()
    assert truth.distance_to(goal) < 0.4                    # xy tolerance 0.25 + AMCL error
    assert truth.distance_to(ex.robot.pose()) < 0.1         # AMCL over the drivers' data
    # the bytes really flowed: 50 Hz feedback, 10 Hz scans, commands that moved the robot
    base, laser = io.devices["base"], io.devices["laser"]
    t = result.sim_time
    assert base.delivered >= 45 * t and laser.delivered >= 9 * t
    assert base.rejected == 0 and laser.rejected == 0 and base.connects == laser.connects == 1
    speeds = [c[1] for c in io.bridge.base.commands]
    assert max(speeds) >= 200 and speeds[-1] == 0            # drove (mm/s), stopped at the end
    assert result.distance >= s.start.distance_to(goal) - 0.3


def test_catalogue_scenario_through_the_drivers_is_deterministic(scenario_run) -> None:
    """Same seed, same run: every pose of the trace and every command byte the base got."""
    _, m1, r1 = scenario_run
    _, m2, r2 = _run_scenario_through_drivers()
    try:
        assert r2 == r1
        assert m2.executive.trace.poses == m1.executive.trace.poses
        assert m2.executive.io.bridge.base.commands == m1.executive.io.bridge.base.commands
        assert m2.sim.true_pose() == m1.sim.true_pose()
    finally:
        m2.executive.shutdown()
        m2.executive.io.close()


def test_catalogue_scenario_runs_from_the_cli(scenario_run, capsys) -> None:
    """``mission scenario run --hw-emulated``: the user's command gives the same run."""
    from executive.cli import main
    _, _, first = scenario_run
    code = main(["scenario", "run", str(SCENARIO), "--tree", str(TREE), "--hw-emulated",
                 "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out[0]["outcome"] == "succeeded"
    assert out[0]["sim_time_s"] == round(first.sim_time, 3)
    assert out[0]["recoveries"] == first.recoveries


def test_closing_the_emulated_robot_unplugs_it_for_good(scenario_run) -> None:
    """After ``io.close()`` the emulators are gone from the registry and a late stop command
    (e.g. an executive shutdown) does not open the port again."""
    from executive.world import World
    from executive.mission import build_mission
    from executive.scenario import scenario_config
    from hw.emulators import lookup
    s, _, _ = scenario_run
    m = build_mission(str(TREE), scenario_config(s), s.grid, s.start, world=World(),
                      seed=1, hardware="emulated")
    io = m.executive.io
    ident = io.bridge.ident
    assert lookup(f"{ident}-base") is not None and io.devices["base"].connected
    io.close()
    m.executive.shutdown()                                  # sends a stop after the close
    assert lookup(f"{ident}-base") is None and lookup(f"{ident}-laser") is None
    assert not io.devices["base"].connected and not io.devices["laser"].connected


def test_scenario_through_noisy_serial_lines_from_the_config() -> None:
    """``robot.devices`` fault options on ``sim`` ports reach the emulated wires: corrupted and
    garbage bytes are rejected by the drivers' checks and the scenario still succeeds."""
    from executive.world import World
    from executive.mission import build_mission, run_mission
    from executive.scenario import load_scenario, scenario_config
    s = load_scenario(SCENARIO)
    s.robot["devices"] = {"base": "kobuki://sim?corrupt=0.0002",
                          "laser": {"url": "urg04lx://sim?corrupt=0.0002&garbage=0.05",
                                    "params": {"cluster": 2}}}
    m = build_mission(str(TREE), scenario_config(s), s.grid, s.start, world=World(),
                      seed=s.seed, hardware="emulated")
    try:
        result = run_mission(m, s.goals, s.time_limit)
        io = m.executive.io
        base, laser = io.devices["base"], io.devices["laser"]
        assert result.outcome == "succeeded", result.reason
        assert m.sim.true_pose().distance_to(s.goals[-1]) < 0.4
        assert io.bridge.links["laser"].bytes_corrupted > 0 and laser.rejected > 0
        assert io.bridge.links["base"].bytes_corrupted > 0 and base.rejected > 0
        assert laser.params.cluster == 2 and len(laser.scan().ranges) == 341
    finally:
        m.executive.shutdown()
        m.executive.io.close()
