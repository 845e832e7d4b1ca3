"""The executive loop against a kinematic fake robot and hand-written behaviours (no simulator)."""

from __future__ import annotations

import io
import json
import math

import py_trees
import pytest
from py_trees.common import Access, Status

from hw.testing import KinematicRobot
from navcore.clock import SimClock
from navcore.types import Pose2D, Twist
from behaviors.base import Recovery, make as make_node
from executive.executive import Executive
from executive.recorder import Recorder, read_log, statuses_at
from executive.safety import SafetyGate


def wall_ahead(pose: Pose2D) -> list[float]:
    """Three beams at a wall 3 m ahead of the start along x: the ranges change as the robot
    moves (the safety gate stops a robot whose laser repeats itself while it moves)."""
    d = max(0.2, 3.0 - pose.x) + 0.01 * math.sin(pose.theta)
    return [d, d, d]


def wall_ahead_robot(pose: Pose2D = Pose2D()) -> KinematicRobot:
    """The robot I/O of these tests: hw.testing's unicycle, its laser seeing ``wall_ahead``."""
    return KinematicRobot(pose, ranges=wall_ahead, angle_min=-1.0, angle_max=1.0,
                          angle_increment=1.0, range_min=0.1, range_max=5.0)


class DriveToGoal(py_trees.behaviour.Behaviour):
    """Turn toward the goal and drive; SUCCESS within 0.1 m."""

    def setup(self, **kwargs) -> None:
        self.robot = kwargs["robot"]
        self.bb = self.attach_blackboard_client(namespace=kwargs["blackboard_namespace"])
        self.bb.register_key("goal", access=Access.READ)
        self.bb.register_key("cmd_vel", access=Access.WRITE)

    def update(self) -> Status:
        p, g = self.robot.pose(), self.bb.goal
        if p.distance_to(g) < 0.1:
            self.bb.cmd_vel = Twist()
            return Status.SUCCESS
        err = math.atan2(g.y - p.y, g.x - p.x) - p.theta
        err = math.atan2(math.sin(err), math.cos(err))
        self.bb.cmd_vel = Twist(0.4 if abs(err) < 0.3 else 0.0, 0.0, max(-1.0, min(1.0, 2 * err)))
        return Status.RUNNING


class Boom(py_trees.behaviour.Behaviour):
    def update(self) -> Status:
        raise RuntimeError("kaboom")


class Spin(Recovery, py_trees.behaviour.Behaviour):
    """A plain py_trees behaviour marked as a recovery (the executive logs its starts); writes
    a turn command for 3 ticks."""

    def setup(self, **kwargs) -> None:
        self.bb = self.attach_blackboard_client(namespace=kwargs["blackboard_namespace"])
        self.bb.register_key("cmd_vel", access=Access.WRITE)

    def initialise(self) -> None:
        self.n = 0

    def update(self) -> Status:
        self.n += 1
        self.bb.cmd_vel = Twist(0.0, 0.0, 0.5)
        return Status.RUNNING if self.n < 3 else Status.SUCCESS


def make(root, pose=Pose2D(), stream=None):
    clock = SimClock()
    io_ = wall_ahead_robot(pose)
    ex = Executive(py_trees.trees.BehaviourTree(root), io_, clock, 0.1,
                   recorder=Recorder(stream))
    return ex, io_, clock


def test_the_robot_io_double_integrates_its_commands_and_its_laser_follows_it():
    robot = KinematicRobot(Pose2D(1.0, 0.0, 0.0))
    scan0 = robot.laser.scan()
    assert robot.laser.scan() is scan0  # read twice in one cycle: one message
    assert scan0.ranges.tolist() == pytest.approx([4.0])  # the room's wall at x = 5 m
    robot.base.send(Twist(0.5, 0.0, 0.0))
    robot.step_to(2.0)
    assert (robot.pose.x, robot.pose.y, robot.t) == pytest.approx((2.0, 0.0, 2.0))
    assert robot.laser.scan().ranges.tolist() == pytest.approx([3.0])
    robot.base.send(Twist(0.0, 0.0, math.pi / 2))
    robot.step_to(3.0)
    assert robot.pose.theta == pytest.approx(math.pi / 2)
    assert robot.laser.scan().ranges.tolist() == pytest.approx([5.0])  # facing the wall y = 5
    odom = robot.base.odometry()
    assert odom.stamp == 3.0 and odom.pose is robot.pose
    assert odom.twist.wz == pytest.approx(math.pi / 2)
    assert [c.vx for c in robot.sent] == [0.5, 0.0]
    wall = wall_ahead_robot(Pose2D(1.0, 0.0)).laser.scan()
    assert (wall.angle_min, wall.angle_max, wall.range_max) == (-1.0, 1.0, 5.0)
    assert wall.ranges.tolist() == pytest.approx([2.0, 2.0, 2.0])


def test_drives_to_goal_and_stops():
    ex, io_, clock = make(DriveToGoal("drive"))
    result = ex.run([Pose2D(2.0, 1.0, 0.0)], time_limit=60.0)
    assert result.succeeded and result.goals_reached == 1
    assert io_.pose.distance_to(Pose2D(2.0, 1.0)) < 0.15
    assert io_.sent[-1].is_zero()
    assert result.distance == pytest.approx(math.hypot(2, 1), abs=0.3)
    assert 3.0 < result.sim_time < 20.0
    assert clock.now() == pytest.approx(result.ticks * 0.1)


def test_multiple_goals_in_turn():
    ex, io_, _ = make(DriveToGoal("drive"))
    result = ex.run([Pose2D(1.0, 0.0), Pose2D(1.0, 1.0), Pose2D(0.0, 0.0)], time_limit=60.0)
    assert result.goals_reached == 3 and result.succeeded
    assert io_.pose.distance_to(Pose2D()) < 0.15


def test_exception_in_node_is_an_internal_error_that_ends_the_mission():
    # Before, the raising node FAILed and the Selector drove on to the goal: a bug looked like
    # a navigation failure that a fallback (or a recovery) answers. Now the mission ends.
    root = py_trees.composites.Selector("sel", memory=False,
                                        children=[Boom("boom"), DriveToGoal("drive")])
    ex, io_, _ = make(root)
    result = ex.run([Pose2D(1.0, 0.0)], time_limit=30.0)
    assert result.outcome == "failed" and result.ticks == 1
    assert result.reason == "INTERNAL_ERROR in 'boom' (update): RuntimeError: kaboom"
    assert 'in update\n    raise RuntimeError("kaboom")' in result.traceback
    assert ex.trace.errors[0]["node"] == "boom" and "kaboom" in ex.trace.errors[0]["error"]
    assert all(c.is_zero() for c in io_.sent)


class BrokenPerception:
    """Localisation (``estimate``) or a costmap update (``perceive``) with a bug: it raises from
    the third cycle on."""

    def __init__(self, phase: str) -> None:
        self.phase, self.cycles = phase, 0

    def estimate(self, odom, scan):
        self.cycles += 1
        if self.phase == "estimate" and self.cycles >= 3:
            raise TypeError("unsupported operand type(s) for +: 'float' and 'NoneType'")
        return None  # the robot I/O's ground truth

    def perceive(self, pose, scan, now) -> None:
        if self.phase == "perceive" and self.cycles >= 3:
            raise IndexError("index 120 is out of bounds for axis 0 with size 120")


@pytest.mark.parametrize("phase", ["estimate", "perceive"])
def test_a_bug_in_localisation_or_a_costmap_update_ends_the_mission(phase):
    # Before, the robot stopped each cycle and the tree ticked on until the time limit: the
    # mission ended in a timeout that did not say why. Now it ends at once with INTERNAL_ERROR.
    stream = io.StringIO()
    io_ = wall_ahead_robot(Pose2D())
    ex = Executive(py_trees.trees.BehaviourTree(DriveToGoal("drive")), io_, SimClock(), 0.1,
                   perception=BrokenPerception(phase), recorder=Recorder(stream))
    result = ex.run([Pose2D(2.0, 0.0)], time_limit=30.0)
    assert result.outcome == "failed" and result.ticks == 3
    error = ("TypeError: unsupported operand" if phase == "estimate"
             else "IndexError: index 120 is out of bounds")
    assert result.reason.startswith(f"INTERNAL_ERROR in 'executive' ({phase}): {error}")
    assert f"in {phase}\n" in result.traceback and result.traceback.startswith("Traceback")
    # driving for two cycles, zero from the third on (the end of the task sends one more)
    assert [c.is_zero() for c in io_.sent] == [False, False, True, True]
    lines = [json.loads(s) for s in stream.getvalue().splitlines()]
    assert lines[-1]["footer"]["traceback"] == result.traceback
    ex.shutdown()


class Exploding:
    """A component that raises: a costmap that cannot reset, a controller that cannot start."""

    def reset_layers(self) -> None:
        raise RuntimeError("kaboom")

    def reset(self) -> None:
        raise ValueError("bad start")


@pytest.mark.parametrize("where", ["initialise", "update"])
def test_exception_in_a_navbt_leaf_ends_the_mission_with_its_traceback(where):
    # FollowPath's initialise resets its controller, ClearEntireCostmap's update resets the
    # costmap: either raising ends the mission (the fallback does not drive on), the tick
    # record and the summary keep the traceback, and the robot gets zero.
    ns = f"/leafboom_{where}"
    leaf = (make_node("FollowPath", name="leafboom", namespace=ns) if where == "initialise"
            else make_node("ClearEntireCostmap", name="leafboom", namespace=ns, costmap="local"))
    root = py_trees.composites.Selector("sel", memory=False,
                                        children=[leaf, DriveToGoal("drive")])
    stream = io.StringIO()
    io_ = wall_ahead_robot(Pose2D())
    ex = Executive(py_trees.trees.BehaviourTree(root), io_, SimClock(), 0.1,
                   {"local_costmap": Exploding(), "controllers": {"FollowPath": Exploding()}},
                   namespace=ns, recorder=Recorder(stream))
    result = ex.run([Pose2D(1.0, 0.0)], time_limit=30.0)
    assert result.outcome == "failed" and result.ticks == 1
    error = "ValueError: bad start" if where == "initialise" else "RuntimeError: kaboom"
    assert result.reason == f"INTERNAL_ERROR in 'leafboom' ({where}): {error}"
    lines = [json.loads(s) for s in stream.getvalue().splitlines()]
    event = next(e for e in lines[1]["events"] if "error" in e)
    assert event["node"] == "leafboom" and event["in"] == where
    assert event["traceback"].startswith("Traceback") and event["traceback"].endswith(error)
    assert lines[-1]["footer"]["traceback"] == event["traceback"]
    assert io_.sent and all(c.is_zero() for c in io_.sent)
    # a failed initialise skips update (FollowPath's update would write its error code)
    assert ex.blackboard_get("follow_path_error_code") is None
    ex.shutdown()
    plain = make_node("ClearEntireCostmap", namespace=f"{ns}_plain", costmap="local")
    plain.setup(clock=SimClock(), local_costmap=Exploding())
    with pytest.raises(RuntimeError, match="kaboom"):   # outside an executive it propagates
        plain.tick_once()


def test_exception_in_a_control_nodes_own_tick_names_the_node_and_tick():
    # a control node's own tick code (not a lifecycle method of a leaf) raising: the record
    # names the node and "tick"
    from executive.tree_loader import LeanBehaviourTree

    class Brittle(py_trees.composites.Sequence):
        def tick(self):
            raise KeyError("no child")
            yield self

    ns = "/brittle"
    root = Brittle(name="brittle", memory=False, children=[DriveToGoal("drive")])
    # unrecorded: no visitor, the tree handle drains the root's tick generator itself
    ex = Executive(LeanBehaviourTree(root), wall_ahead_robot(Pose2D()), SimClock(), 0.1,
                   namespace=ns)
    result = ex.run([Pose2D(1.0, 0.0)], time_limit=5.0)
    assert result.outcome == "failed" and result.ticks == 1
    assert result.reason == "INTERNAL_ERROR in 'brittle' (tick): KeyError: 'no child'"
    ex.shutdown()


def test_only_failing_tree_stops_robot_with_reason():
    ex, io_, _ = make(Boom("boom"))
    result = ex.run([Pose2D(1.0, 0.0)], time_limit=5.0)
    assert result.outcome == "failed"
    assert "kaboom" in result.reason
    assert all(c.is_zero() for c in io_.sent)


def test_timeout_outcome():
    root = py_trees.behaviours.Running("forever")
    ex, io_, _ = make(root)
    result = ex.run([Pose2D(1.0, 0.0)], time_limit=2.0)
    assert result.outcome == "timeout"
    assert result.sim_time == pytest.approx(2.0, abs=0.11)


def test_no_command_means_zero_velocity():
    class Silent(py_trees.behaviour.Behaviour):
        def update(self):
            return Status.RUNNING
    ex, io_, _ = make(Silent("quiet"))
    for _ in range(5):
        ex.step()
    assert len(io_.sent) == 5 and all(c.is_zero() for c in io_.sent)


def test_two_executives_have_separate_blackboards():
    a, _, _ = make(DriveToGoal("a"))
    b, _, _ = make(DriveToGoal("b"))
    a.set_goal(Pose2D(1.0, 0.0))
    b.set_goal(Pose2D(-3.0, 2.0))
    assert a.namespace != b.namespace
    assert a.blackboard_get("goal") == Pose2D(1.0, 0.0)
    assert b.blackboard_get("goal") == Pose2D(-3.0, 2.0)
    a.step()
    b.step()
    assert a.last_cmd.wz == pytest.approx(0.0)  # straight ahead
    assert b.last_cmd.wz > 0.5                   # turning around
    a.shutdown()
    assert a.blackboard_get("goal") is None and b.blackboard_get("goal") is not None


def test_recorder_log_roundtrip_and_recoveries():
    stream = io.StringIO()
    root = py_trees.composites.Sequence("seq", memory=True,
                                        children=[Spin("spin_once"), DriveToGoal("drive")])
    ex, io_, _ = make(root, stream=stream)
    result = ex.run([Pose2D(1.0, 0.0)], time_limit=30.0)
    assert result.succeeded and result.recoveries == ["spin_once"]
    lines = [json.loads(s) for s in stream.getvalue().splitlines()]
    header = lines[0]["header"]
    assert [n[0] for n in header["nodes"]] == ["seq", "spin_once", "drive"]
    assert [n[2] for n in header["nodes"]] == [0, 1, 1]
    ticks = lines[1:-1]
    assert len(ticks) == result.ticks and lines[-1]["footer"]["outcome"] == "succeeded"
    assert ticks[0]["status"] == {"0": "RUNNING", "1": "RUNNING"}
    assert ticks[0]["cmd"] == [0.0, 0.0, 0.5]
    assert "goal" in ticks[0]["bb"]
    assert any(e.get("recovery") == "spin_once" for e in ticks[0]["events"])
    # replay: statuses after tick 3 (the spin succeeded on tick 2, drive running)
    statuses = statuses_at(header, ticks, 3)
    assert statuses == ["RUNNING", "SUCCESS", "RUNNING"]


def test_read_log_errors(tmp_path):
    p = tmp_path / "ticks.jsonl"
    p.write_text('{"tick": 0}\n')
    with pytest.raises(ValueError, match="no header"):
        read_log(str(p))
    p.write_text('{"header": {"nodes": []}}\nnot json\n')
    with pytest.raises(ValueError, match=r"ticks.jsonl:2: not a JSON line"):
        read_log(str(p))


def test_safety_gate_limits_and_watchdogs():
    gate = SafetyGate()
    r = gate.filter(Twist(2.0, 0.0, -5.0), 1.0, scan_stamp=0.9, odom_stamp=0.95,
                    measured=Twist(0.3, 0, 0))
    assert r.cmd == Twist(0.55, 0.0, -1.5) and r.clipped and not r.faults
    r = gate.filter(Twist(0.2, 0, 0), 2.0, scan_stamp=1.0, odom_stamp=1.99, measured=Twist())
    assert r.cmd.is_zero() and r.faults == ["stale_laser"]
    r = gate.filter(Twist(0.2, 0, 0), 2.0, scan_stamp=None, odom_stamp=None, measured=None)
    assert r.cmd.is_zero() and set(r.faults) == {"stale_laser", "stale_odometry"}
    r = gate.filter(Twist(float("nan"), 0, 0), 2.0, scan_stamp=2.0, odom_stamp=2.0,
                    measured=Twist())
    assert r.cmd.is_zero() and "non_finite_command" in r.faults
    # bumper blocks forward motion only
    r = gate.filter(Twist(0.2, 0, 0.3), 3.0, scan_stamp=3.0, odom_stamp=3.0,
                    measured=Twist(0.2, 0, 0), bumper=True)
    assert r.cmd == Twist(0.0, 0.0, 0.3) and r.faults == ["bumper"]
    r = gate.filter(Twist(-0.1, 0, 0), 3.0, scan_stamp=3.0, odom_stamp=3.0,
                    measured=Twist(0.2, 0, 0), bumper=True)
    assert r.cmd == Twist(-0.1, 0, 0) and not r.faults


def test_safety_gate_stall():
    gate = SafetyGate()
    t, stalled_at = 0.0, None
    while t < 5.0:
        r = gate.filter(Twist(0.3, 0, 0), t, scan_stamp=t, odom_stamp=t, measured=Twist())
        if "stall" in r.faults:
            stalled_at = t
            assert r.cmd.is_zero()
            break
        assert r.cmd.vx == pytest.approx(0.3)
        t += 0.1
    assert stalled_at == pytest.approx(2.0, abs=0.11)
    # motion measured: no stall however long
    for i in range(60):
        r = gate.filter(Twist(0.3, 0, 0), 10 + 0.1 * i, scan_stamp=10 + 0.1 * i,
                        odom_stamp=10 + 0.1 * i, measured=Twist(0.3, 0, 0))
        assert not r.faults


def test_run_folder_files(tmp_path):
    from PIL import Image

    from navcore.synthetic_maps import ascii_map
    from executive.run_folder import finish, open_log
    grid = ascii_map("#########\n#.......#\n#.......#\n#.......#\n#########\n", resolution=0.5)
    log = open_log(tmp_path / "run")
    root = py_trees.composites.Sequence("seq", memory=True,
                                        children=[Spin("spin"), DriveToGoal("drive")])
    clock = SimClock()
    ex = Executive(py_trees.trees.BehaviourTree(root), wall_ahead_robot(Pose2D(1.0, 1.0)), clock,
                   0.1, recorder=Recorder(log))
    result = ex.run([Pose2D(3.0, 1.5)], time_limit=30)
    log.close()
    ex.trace.contacts.append({"t": 1.0, "pose": [2.0, 1.2, 0.0]})
    summary = finish(tmp_path / "run", ex, result, grid, [(0.2, 0.2), (0.2, -0.2), (-0.2, -0.2),
                                                           (-0.2, 0.2)])
    files = sorted(p.name for p in (tmp_path / "run").iterdir())
    assert files == ["replay.html", "run.png", "summary.json", "ticks.jsonl", "tree.svg"]
    saved = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert saved["outcome"] == "succeeded" and saved["recoveries"] == ["spin"]
    assert saved["recovery_events"][0]["type"] == "Spin"
    assert saved == summary
    img = Image.open(tmp_path / "run" / "run.png")
    assert img.mode == "RGB" and max(img.size) >= 200
    px = img.load()
    colours = {px[x, y] for x in range(0, img.width, 2) for y in range(0, img.height, 2)}
    assert (20, 150, 40) in colours      # trajectory drawn
    assert (230, 120, 0) in colours      # recovery marker
    assert b"<svg" in (tmp_path / "run" / "tree.svg").read_bytes()


def test_overrun_is_recorded():
    class SlowWall:
        """Each reading is 0.15 s later: every tick takes longer than the 0.1 s period."""

        def __init__(self):
            self.t = 0.0

        def now(self):
            self.t += 0.15
            return self.t

        def sleep_until(self, t):
            pass

    stream, timing = io.StringIO(), io.StringIO()
    ex = Executive(py_trees.trees.BehaviourTree(DriveToGoal("drive")), wall_ahead_robot(),
                   SimClock(), 0.1, recorder=Recorder(stream, timing=timing), wall_clock=SlowWall())
    ex.set_goal(Pose2D(1.0, 0.0))
    for _ in range(3):
        ex.step()
    # wall-clock figures stay out of the (deterministic) tick log
    assert "overrun" not in stream.getvalue()
    lines = [json.loads(s) for s in timing.getvalue().splitlines()]
    assert lines == [{"tick": i, "overrun_ms": 150.0} for i in range(3)]
    assert ex.trace.overruns == 3
    ex.recorder.footer({"outcome": "stopped"})   # the count closes the timing stream, not the log
    assert json.loads(timing.getvalue().splitlines()[-1]) == {"footer": {"ticks": 3,
                                                                         "overruns": 3}}
    assert "overrun" not in stream.getvalue()


def test_setup_failure_is_a_wiring_error(tmp_path):
    """A tree whose node cannot set up (here: a component it needs is missing) is one clear
    error naming the tree, not a traceback."""
    from executive.config import load_config
    from executive.mission import WiringError, build_mission
    from navcore.synthetic_maps import ascii_map

    class Broken(py_trees.behaviour.Behaviour):
        def setup(self, **kwargs):
            raise RuntimeError("needs a 'gripper' component")

        def update(self):
            return Status.SUCCESS

    import executive.mission as mission
    tree_file = tmp_path / "t.yaml"
    tree_file.write_text("main_tree: T\ntrees:\n  T:\n    Wait: {wait_duration: 1.0}\n")
    original = mission.load_tree_file
    mission.load_tree_file = lambda path, namespace, **_: py_trees.trees.BehaviourTree(Broken("b"))
    try:
        grid = ascii_map("########\n#......#\n#......#\n########\n", resolution=0.5)
        with pytest.raises(WiringError, match=r"t.yaml: tree setup failed: needs a 'gripper'"):
            build_mission(str(tree_file), load_config(), grid, Pose2D(1.0, 1.0))
    finally:
        mission.load_tree_file = original


@pytest.mark.parametrize("tree", ["nav2", "move_base"])
def test_a_controller_bug_ends_the_mission_instead_of_firing_recoveries(tree):
    # Before, the controller caught the TypeError and said "no valid trajectory", and the
    # shipped trees answered with Spin and BackUp. A bug now ends the mission: INTERNAL_ERROR,
    # no recovery fired, the robot stopped.
    from executive.tree_loader import load_tree_file
    from behaviors.testing import noop_components
    from executive.config import config_from_mapping

    class BuggyController:
        def set_plan(self, path) -> None:
            pass

        def reset(self) -> None:
            pass

        def is_goal_reached(self) -> bool:
            return False

        def compute_velocity(self, pose, velocity, path=None):
            return pose.x + None  # TypeError

    ns = f"/buggy_{tree}"
    components = dict(noop_components(config_from_mapping({}, "<noop>").all_parameters()),
                      controllers={"FollowPath": BuggyController()})
    robot = KinematicRobot()
    ex = Executive(load_tree_file(f"trees/{tree}.yaml", namespace=ns), robot, SimClock(), 0.05,
                   components, namespace=ns)
    result = ex.run([Pose2D(3.0, 0.0)], time_limit=30.0)
    ex.shutdown()
    assert result.outcome == "failed" and result.recoveries == []
    assert result.reason.startswith("INTERNAL_ERROR in '") and "TypeError" in result.reason
    assert "compute_velocity" in result.traceback
    assert robot.sent and all(c.is_zero() for c in robot.sent)


@pytest.mark.parametrize("tree", ["nav2", "smach_recovery"])
def test_the_noop_robot_drives_its_goals_through_the_safety_gate(tree):
    # bench_executive times these trees driving the no-op robot to and fro. Its laser used to
    # repeat one scan while the robot moved: a frozen sensor to the safety gate, which held the
    # robot still while the tree spun through its recoveries.
    from executive.tree_loader import load_tree_file
    from behaviors.testing import noop_components
    from executive.config import config_from_mapping

    ns = f"/noop_drive_{tree}"
    robot = KinematicRobot()
    ex = Executive(load_tree_file(f"trees/{tree}.yaml", namespace=ns), robot, SimClock(), 0.05,
                   noop_components(config_from_mapping({}, "<noop>").all_parameters()),
                   namespace=ns)
    result = ex.run([Pose2D(3.0, 0.0), Pose2D(0.0, 0.0)], time_limit=60.0)
    ex.shutdown()
    assert result.outcome == "succeeded" and result.goals_reached == 2
    assert result.recoveries == [] and "laser_frozen" not in ex.trace.faults
    assert math.hypot(robot.pose.x, robot.pose.y) < 0.15
