"""Ports of Nav2's node unit tests (nav2_behavior_tree/test/plugins/...) for the Nav2 nodes
navbt has, with scripted children and a simulated clock. Each test names the Nav2 test it
follows (at the commits of ../shared/data/SOURCES.md section 6); where Nav2's test sleeps,
the clock is advanced instead."""

from __future__ import annotations

import itertools
import math

import py_trees
import pytest
from py_trees.common import Status

from behaviors.base import make
from behaviors.testing import ScriptedWorld
from navcore.path_ops import TrackingFeedback
from navcore.route import find_route, load_route_graph
from navcore.types import Path, Pose2D, Twist

S, F, R, I = Status.SUCCESS, Status.FAILURE, Status.RUNNING, Status.INVALID
_ns = itertools.count()


class Dummy(py_trees.behaviour.Behaviour):
    """Nav2's DummyNode (test/utils/test_dummy_tree_node.hpp): returns the status it is set
    to, each tick."""

    def __init__(self, name: str = "dummy") -> None:
        super().__init__(name=name)
        self.next = S

    def change(self, status: Status) -> None:
        self.next = status

    def update(self) -> Status:
        return self.next


def node(node_type: str, world: ScriptedWorld | None = None, **kwargs):
    ns = f"/n2p{next(_ns)}"
    n = make(node_type, namespace=ns, **kwargs)
    comps = (world or ScriptedWorld()).components()
    for m in n.iterate():
        if hasattr(m, "setup"):
            m.setup(**comps)
    n.ns_for_test = ns
    return n


def bb_set(n, key: str, value) -> None:
    py_trees.blackboard.Blackboard.storage[f"{n.ns_for_test}/{key}"] = value


def bb_get(n, key: str):
    return py_trees.blackboard.Blackboard.storage.get(f"{n.ns_for_test}/{key}")


def tick(n) -> Status:
    n.tick_once()
    return n.status


def path_of(xs, ys=None) -> Path:
    ys = ys or [0.0] * len(xs)
    return Path.from_poses([Pose2D(x, y, 0.0) for x, y in zip(xs, ys)])


# --------------------------------------------------------------------- controls / decorators

def _round_robin(**ports):
    kids = [Dummy("first"), Dummy("second"), Dummy("third")]
    return node("RoundRobin", children=kids, **ports), kids


def test_round_robin_failure_jazzy():
    """test/plugins/control/test_round_robin_node.cpp (jazzy) test_failure: Jazzy's
    RoundRobin always wraps (the loader sets wrap_around for jazzy files)."""
    rr, (a, b, c) = _round_robin(wrap_around=True)
    a.change(F), b.change(R)
    assert tick(rr) == R
    b.change(F), c.change(R)
    assert tick(rr) == R
    c.change(F)
    assert tick(rr) == F
    # Nav2 resets the children to IDLE at once; navbt keeps finished children's statuses
    # until the next run (py_trees, docs/trees.md "How a tick works"): none is left RUNNING
    assert R not in (a.status, b.status, c.status)


def test_round_robin_behavior_jazzy_is_R_R_S_R_R_S():
    """test_round_robin_node.cpp (jazzy) test_behavior: R R S R R S, children halted after."""
    rr, (a, b, c) = _round_robin(wrap_around=True)
    out = []
    a.change(R)
    out.append(tick(rr))
    a.change(F), b.change(R)
    out.append(tick(rr))
    a.change(F), b.change(S)
    out.append(tick(rr))
    c.change(R)
    out.append(tick(rr))
    a.change(R), c.change(F)
    out.append(tick(rr))
    a.change(F), b.change(S), c.change(F)
    out.append(tick(rr))
    assert out == [R, R, S, R, R, S]
    rr.stop(I)
    assert a.status == b.status == c.status == I


def test_round_robin_wrap_around_disabled_main():
    """test_round_robin_node.cpp (main) test_wrap_around_disabled: all fail -> FAILURE; and
    main's end-of-list rule: without wrap, a successful last child gives FAILURE too."""
    rr, (a, b, c) = _round_robin(wrap_around=False, nav2_distro="main")
    a.change(F), b.change(F), c.change(F)
    assert tick(rr) == F
    a.change(S), b.change(S), c.change(S)
    assert [tick(rr), tick(rr), tick(rr)] == [S, S, F]   # first, second, then the end
    assert tick(rr) == S                                  # starts over at the first


def test_rate_controller_returns_running_while_throttled():
    """test/plugins/decorator/test_rate_controller.cpp: the child is ticked at most hz times
    a second (the test sleeps; here the clock advances) and the node is RUNNING between."""
    w = ScriptedWorld()
    child = Dummy()
    rc = node("RateController", world=w, child=child, hz=10.0)
    seen = []
    for _ in range(8):                      # 0.35 s at 50 ms
        seen.append(tick(rc))
        w.clock.advance(0.05)
    assert seen == [S, R, S, R, S, R, S, R]


def test_path_longer_on_approach():
    """test/plugins/decorator/test_path_longer_on_approach.cpp test_tick."""
    new_path = path_of([1.5 * i for i in range(10)])
    d = node("PathLongerOnApproach", child=Dummy(), prox_len=5.0, length_factor=2.0)
    bb_set(d, "path", new_path)
    assert tick(d) == S
    child = Dummy()
    child.change(F)
    d = node("PathLongerOnApproach", child=child, prox_len=20.0, length_factor=1.0)
    bb_set(d, "path", path_of([3.0 * i for i in range(1, 6)]))   # 12 m, goal at 15
    tick(d)
    bb_set(d, "path", path_of([1.5 * i for i in range(11)]))     # 15 m, same goal
    assert tick(d) == F


def test_nonblocking_sequence():
    """test/plugins/control/test_nonblocking_sequence.cpp: every child ticked every tick; a
    FAILURE fails at once, all SUCCESS succeeds, otherwise RUNNING."""
    a, b, c = Dummy("a"), Dummy("b"), Dummy("c")
    seq = node("NonblockingSequence", children=[a, b, c])
    a.change(S), b.change(R), c.change(S)
    assert tick(seq) == R and c.status == S        # c ticked although b runs
    b.change(S)
    assert tick(seq) == S
    a.change(F)
    assert tick(seq) == F


def test_persistent_sequence_resumes_from_the_blackboard_index():
    """test/plugins/control/test_persistent_sequence.cpp: the position is current_child_idx."""
    a, b = Dummy("a"), Dummy("b")
    seq = node("PersistentSequence", children=[a, b], current_child_idx="{idx}")
    bb_set(seq, "idx", 0)
    b.change(R)
    assert tick(seq) == R and bb_get(seq, "idx") == 1
    seq.stop(I)                                     # a halt keeps the index
    a.change(F)                                     # a is not ticked again
    b.change(S)
    assert tick(seq) == S and bb_get(seq, "idx") == 0
    assert tick(seq) == F and bb_get(seq, "idx") == 0


# --------------------------------------------------------------------- conditions

def test_globally_updated_goal():
    """test/plugins/condition/test_globally_updated_goal.cpp test_behavior."""
    n = node("GlobalUpdatedGoal")
    bb_set(n, "goal", Pose2D(0.0, 0.0, 0.0))
    assert tick(n) == S
    bb_set(n, "goal", Pose2D(1.0, 0.0, 0.0))
    assert tick(n) == S
    assert tick(n) == F
    n.stop(I)                                       # unlike GoalUpdated, a halt forgets nothing
    assert tick(n) == F


def test_path_expiring_timer():
    """test/plugins/condition/test_path_expiring_timer.cpp test_behavior (sleeps -> clock)."""
    w = ScriptedWorld()
    n = node("PathExpiringTimer", world=w)
    assert tick(n) == F
    for i in range(20):
        w.clock.advance(0.5)
        assert tick(n) == (S if i % 2 else F)
    bb_set(n, "path", path_of([1.0]))
    assert tick(n) == F
    w.clock.advance(1.5)
    assert tick(n) == S


def test_is_within_path_tracking_bounds():
    """test/plugins/condition/test_is_within_path_tracking_bounds.cpp: left/right/heading
    bounds, SUCCESS without feedback."""
    n = node("IsWithinPathTrackingBounds", max_error_left=0.5, max_error_right=0.3,
             max_error_heading=0.5)
    assert tick(n) == S
    for err, head, want in [(0.4, 0.0, S), (0.6, 0.0, F), (-0.25, 0.0, S), (-0.35, 0.0, F),
                            (0.0, 0.6, F), (0.0, -0.4, S)]:
        bb_set(n, "tracking_feedback", TrackingFeedback(err, head, 0, Pose2D(), 1.0, 0.0, 1.0))
        assert tick(n) == want, (err, head)


def test_are_poses_near():
    """test/plugins/condition/test_are_poses_near.cpp."""
    n = node("ArePosesNear", ref_pose="{a}", target_pose="{b}", tolerance=0.5)
    bb_set(n, "a", Pose2D(0.0, 0.0, 0.0))
    bb_set(n, "b", Pose2D(0.3, 0.3, 1.0))
    assert tick(n) == S
    bb_set(n, "b", Pose2D(0.4, 0.4, 0.0))
    assert tick(n) == F


def test_would_a_route_recovery_help():
    """test/plugins/condition/test_would_a_route_recovery_help.cpp: UNKNOWN, TIMEOUT and
    NO_VALID_ROUTE help; NONE and the others do not."""
    n = node("WouldARouteRecoveryHelp", error_code="{code}")
    for code, want in [(400, S), (404, S), (405, S), (0, F), (401, F), (402, F), (403, F)]:
        bb_set(n, "code", code)
        assert tick(n) == want, code


def test_is_stopped():
    """test/plugins/condition/test_is_stopped.cpp (kilted): RUNNING while stopped for less
    than duration_stopped, then SUCCESS; FAILURE when moving."""
    w = ScriptedWorld()
    n = node("IsStopped", world=w, velocity_threshold=0.1, duration_stopped=500)
    assert tick(n) == R
    w.clock.advance(0.6)
    assert tick(n) == S
    w.robot.apply(Twist(0.5, 0.0, 0.0), 0.05)
    assert tick(n) == F


def test_is_goal_nearby_with_pose_search_distance():
    """test/plugins/condition/test_is_goal_nearby.cpp: remaining length from the closest pose
    against proximity_threshold; max_robot_pose_search_dist bounds the search."""
    w = ScriptedWorld()
    n = node("IsGoalNearby", world=w, proximity_threshold=1.0, max_robot_pose_search_dist=2.0)
    bb_set(n, "path", path_of([0.1 * i for i in range(51)]))     # 5 m
    assert tick(n) == F
    w.robot.teleport(Pose2D(4.5, 0.0, 0.0))
    assert tick(n) == F            # searched only 2 m ahead of the last closest pose (x=0)
    w.robot.teleport(Pose2D(1.9, 0.0, 0.0))
    tick(n)
    w.robot.teleport(Pose2D(3.8, 0.0, 0.0))
    tick(n)
    w.robot.teleport(Pose2D(4.5, 0.0, 0.0))
    assert tick(n) == S


# --------------------------------------------------------------------- actions

def test_truncate_path():
    """test/plugins/action/test_truncate_path_action.cpp test_tick."""
    n = node("TruncatePath", distance=1.0, input_path="{path}", output_path="{truncated}")
    bb_set(n, "path", path_of([0.0, 0.5, 0.9, 1.5], [0.0, 0.0, 0.0, 0.5]))
    assert tick(n) == S
    out = bb_get(n, "truncated")
    assert len(out) == 2
    assert out.poses[-1, 2] == pytest.approx(0.463, abs=1e-3)


def test_truncate_path_local():
    """test/plugins/action/test_truncate_path_local_action.cpp: the window around the robot
    pose, forward and backward distances along the path."""
    n = node("TruncatePathLocal", input_path="{path}", output_path="{out}",
             distance_forward=2.0, distance_backward=1.0, pose="{pose}")
    bb_set(n, "path", path_of([0.5 * i for i in range(20)]))    # 0 .. 9.5 m
    bb_set(n, "pose", Pose2D(3.1, 0.2, 0.0))
    assert tick(n) == S
    out = bb_get(n, "out")
    assert out.poses[0, 0] == pytest.approx(2.0) and out.poses[-1, 0] == pytest.approx(5.0)
    bb_set(n, "pose", Pose2D(-3.0, 0.0, 0.0))
    tick(n)
    out = bb_get(n, "out")
    assert out.poses[0, 0] == 0.0 and out.poses[-1, 0] == pytest.approx(2.0)


def test_truncate_path_local_pruning_ignores_a_later_loop():
    """max_robot_pose_search_dist: a path that comes back past the robot is not matched
    beyond the searched length (the reason Nav2 added it)."""
    xs = [0.5 * i for i in range(9)] + [4.0 - 0.5 * i for i in range(1, 9)]
    ys = [0.0] * 9 + [0.3] * 8
    n = node("TruncatePathLocal", input_path="{path}", output_path="{out}", pose="{pose}",
             distance_forward=1.0, distance_backward=0.0, max_robot_pose_search_dist=1.0)
    bb_set(n, "path", path_of(xs, ys))
    bb_set(n, "pose", Pose2D(0.5, 0.25, 0.0))       # nearer the return leg's (0.5, 0.3)
    tick(n)
    assert bb_get(n, "out").poses[0, 0] == pytest.approx(0.5)
    assert bb_get(n, "out").poses[0, 1] == 0.0      # matched on the outbound leg


def test_remove_passed_goals():
    """test/plugins/action/test_remove_passed_goals_action.cpp test_tick and the waypoint
    statuses case."""
    w = ScriptedWorld()
    w.robot.teleport(Pose2D(0.25, 0.0, 0.0))
    goals = [Pose2D(0.0, 0.0), Pose2D(0.5, 0.0), Pose2D(1.0, 0.0), Pose2D(2.0, 0.0)]
    n = node("RemovePassedGoals", world=w, radius=0.5, input_goals="{goals}",
             output_goals="{goals}", input_waypoint_statuses="{st}",
             output_waypoint_statuses="{st}")
    bb_set(n, "goals", goals)
    bb_set(n, "st", [{"waypoint_pose": g, "waypoint_index": i, "waypoint_status": 0}
                     for i, g in enumerate(goals)])
    assert tick(n) == S
    assert bb_get(n, "goals") == goals[2:]
    assert [s["waypoint_status"] for s in bb_get(n, "st")] == [1, 1, 0, 0]


def test_get_pose_from_path():
    """test/plugins/action/test_get_pose_from_path_action.cpp: index 0, -1, out of range."""
    n = node("GetPoseFromPath", path="{path}", pose="{pose}", index="{i}")
    bb_set(n, "path", path_of([0.0, 1.0, 2.0]))
    for i, x in [(0, 0.0), (-1, 2.0), (1, 1.0)]:
        bb_set(n, "i", i)
        assert tick(n) == S and bb_get(n, "pose").x == x
    bb_set(n, "i", 3)
    assert tick(n) == F


def test_concatenate_paths():
    """test/plugins/action/test_concatenate_paths_action.cpp."""
    n = node("ConcatenatePaths", input_path1="{a}", input_path2="{b}", output_path="{c}")
    bb_set(n, "a", path_of([0.0, 1.0]))
    bb_set(n, "b", path_of([2.0, 3.0, 4.0]))
    assert tick(n) == S
    assert list(bb_get(n, "c").poses[:, 0]) == [0.0, 1.0, 2.0, 3.0, 4.0]
    bb_set(n, "a", path_of([]))
    bb_set(n, "b", path_of([]))
    assert tick(n) == F


def test_goal_list_actions():
    """test_append_goal_pose_to_goals_action.cpp, test_get_next_few_goals_action.cpp,
    test_get_current_pose_action.cpp."""
    goals = [Pose2D(float(i), 0.0) for i in range(5)]
    n = node("AppendGoalPoseToGoals", goal_pose="{g}", input_goals="{gs}", output_goals="{out}")
    bb_set(n, "g", Pose2D(9.0, 9.0))
    bb_set(n, "gs", goals)
    assert tick(n) == S and bb_get(n, "out") == goals + [Pose2D(9.0, 9.0)]
    n = node("GetNextFewGoals", input_goals="{gs}", num_goals=2, output_goals="{out}")
    bb_set(n, "gs", goals)
    assert tick(n) == S and bb_get(n, "out") == goals[:2]
    bb_set(n, "gs", [])
    assert tick(n) == F
    w = ScriptedWorld()
    w.robot.teleport(Pose2D(1.0, 2.0, 0.5))
    n = node("GetCurrentPose", world=w, current_pose="{p}")
    assert tick(n) == S and bb_get(n, "p") == Pose2D(1.0, 2.0, 0.5)


def test_selectors():
    """test_progress_checker_selector_node.cpp, test_goal_checker_selector_node.cpp,
    test_path_handler_selector_node.cpp, test_smoother_selector_node.cpp: the default until a
    selection arrives."""
    for kind in ("progress_checker", "goal_checker", "path_handler", "smoother"):
        name = "".join(p.capitalize() for p in kind.split("_")) + "Selector"
        n = node(name, **{f"default_{kind}": "Default", f"selected_{kind}": "{sel}"})
        assert tick(n) == S and bb_get(n, "sel") == "Default"
        bb_set(n, f"{kind}_selection", "Precise")
        assert tick(n) == S and bb_get(n, "sel") == "Precise"


def test_cancel_nodes_stop_the_base():
    """test_controller_cancel_node.cpp and the behaviour cancel tests: SUCCESS, zero command."""
    for name in ("CancelControl", "CancelSpin", "CancelBackUp", "CancelDriveOnHeading",
                 "CancelWait"):
        n = node(name)
        bb_set(n, "cmd_vel", Twist(0.3, 0.0, 0.2))
        assert tick(n) == S and bb_get(n, "cmd_vel").is_zero()


def test_wait_reports_success_codes():
    """test/plugins/action/test_wait_action.cpp (kilted+ outputs): error_code_id 0 and an
    empty error_msg once the wait is over."""
    w = ScriptedWorld()
    n = node("Wait", world=w, wait_duration=0.1, error_code_id="{code}", error_msg="{msg}")
    assert tick(n) == R
    w.clock.advance(0.1)
    assert tick(n) == S and bb_get(n, "code") == 0 and bb_get(n, "msg") == ""


ROUTE_GRAPH = "executive/data/maps/office_route_graph.geojson"


def test_compute_route_and_extract_nodes():
    """test_compute_route_action.cpp and test_extract_route_nodes_as_goals_action.cpp, on the
    route graph shipped with the office map: ids and poses, path along the nodes."""
    from pathlib import Path as FsPath
    graph = load_route_graph(FsPath(__file__).resolve().parent.parent / ROUTE_GRAPH)
    w = ScriptedWorld()
    comps = dict(w.components(), route_graph=graph, route_path_density=0.05)
    n = make("ComputeRoute", namespace="/cr", start_id=0, goal_id=15, path="{p}",
             route="{r}", error_code_id="{e}")
    n.setup(**comps)
    n.tick_once()
    assert n.status == S
    storage = py_trees.blackboard.Blackboard.storage
    route, path = storage["/cr/r"], storage["/cr/p"]
    assert [x.id for x in route.nodes] == [x.id for x in find_route(graph, 0, 15).nodes]
    assert route.nodes[0].id == 0 and route.nodes[-1].id == 15
    assert path.length() == pytest.approx(route.cost, rel=1e-9)
    steps = [math.dist(path.poses[i, :2], path.poses[i + 1, :2]) for i in range(len(path) - 1)]
    assert max(steps) <= 0.05 + 1e-9 and storage["/cr/e"] == 0
    ex = make("ExtractRouteNodesAsGoals", namespace="/cr", route="{r}", goals="{g}")
    ex.setup(**comps)
    ex.tick_once()
    assert [(g.x, g.y) for g in storage["/cr/g"]] == [(x.x, x.y) for x in route.nodes]
    bad = make("ComputeRoute", namespace="/cr2", start_id=0, goal_id=999, path="{p}",
               error_code_id="{e}")
    bad.setup(**comps)
    bad.tick_once()
    assert bad.status == F and storage["/cr2/e"] == 403
    nograph = make("ComputeRoute", namespace="/cr3", use_poses=True, goal="{g}", path="{p}",
                   error_code_id="{e}")
    nograph.setup(**w.components())
    nograph.tick_once()
    assert nograph.status == F and storage["/cr3/e"] == 402


class Scripted(Dummy):
    """Nav2's RecoveryDummy: the next statuses in order, then the last one again."""

    def __init__(self, name: str, statuses: list[Status]) -> None:
        super().__init__(name)
        self.script = list(statuses)

    def update(self) -> Status:
        if len(self.script) > 1:
            return self.script.pop(0)
        return self.script[0]


def test_pipeline_sequence_failure():
    """test/plugins/control/test_pipeline_sequence.cpp test_failure."""
    a, b, c = Dummy("a"), Dummy("b"), Dummy("c")
    ps = node("PipelineSequence", children=[a, b, c])
    for statuses in ([F, S, S], [S, F, S], [S, S, F]):
        for child, st in zip((a, b, c), statuses):
            child.change(st)
        assert tick(ps) == F
        assert R not in (a.status, b.status, c.status)
    a.change(S), b.change(S), c.change(R)
    assert tick(ps) == R
    a.change(F)
    assert tick(ps) == F and c.status == I          # the running child is halted


def test_pipeline_sequence_behavior():
    """test_pipeline_sequence.cpp test_behavior: earlier children are re-ticked while a later
    one runs; SUCCESS when the last succeeds."""
    a, b, c = Dummy("a"), Dummy("b"), Dummy("c")
    ps = node("PipelineSequence", children=[a, b, c])
    a.change(R)
    assert tick(ps) == R
    a.change(S), b.change(R)
    assert tick(ps) == R
    a.change(R), b.change(S), c.change(R)
    assert tick(ps) == R
    a.change(R), b.change(S), c.change(S)
    assert tick(ps) == S
    assert R not in (a.status, b.status, c.status)


def test_recovery_node_running_and_retries():
    """test/plugins/control/test_recovery_node.cpp test_running, test_success_one_retry and
    test_failure_one_retry (number_of_retries 1)."""
    first, second = Dummy("first"), Dummy("second")
    rn = node("RecoveryNode", children=[first, second], number_of_retries=1)
    first.change(R)
    assert tick(rn) == R
    first.change(F), second.change(R)
    assert tick(rn) == R
    first, second = Scripted("first", [F, S]), Scripted("second", [S])
    rn = node("RecoveryNode", children=[first, second], number_of_retries=1)
    assert tick(rn) == S                            # fail, recover, retried in the same tick
    assert R not in (first.status, second.status)
    first, second = Scripted("first", [F]), Scripted("second", [F])
    rn = node("RecoveryNode", children=[first, second], number_of_retries=1)
    assert tick(rn) == F
    first, second = Scripted("first", [F, F]), Scripted("second", [S])
    rn = node("RecoveryNode", children=[first, second], number_of_retries=1)
    assert tick(rn) == F                            # one recovery only


def test_follow_path_writes_tracking_feedback_when_wired():
    """test/plugins/action/test_follow_path_action.cpp (main): tracking_feedback is an output
    of FollowPath; here it carries the cross-track and heading errors each tick."""
    w = ScriptedWorld()
    w.robot.teleport(Pose2D(0.5, 0.2, 0.1))
    n = node("FollowPath", world=w, path="{path}", tracking_feedback="{fb}")
    bb_set(n, "path", path_of([0.1 * i for i in range(31)]))
    assert tick(n) == R
    fb = bb_get(n, "fb")
    assert fb.current_path_index == 5
    assert fb.position_tracking_error == pytest.approx(0.2)
    assert fb.heading_tracking_error == pytest.approx(-0.1)
    assert fb.remaining_path_length == pytest.approx(2.5)
    plain = node("FollowPath", world=w, path="{path}")
    bb_set(plain, "path", path_of([0.1 * i for i in range(31)]))
    tick(plain)
    assert bb_get(plain, "tracking_feedback") is None    # not wired: not computed


def test_distance_controller():
    """test/plugins/decorator/test_distance_controller.cpp test_behavior (distance 1.0): the
    child at every metre, RUNNING in between."""
    w = ScriptedWorld()
    child = Dummy()
    d = node("DistanceController", world=w, child=child, distance=1.0)
    assert tick(d) == S
    for i in range(1, 21):
        w.robot.teleport(Pose2D(i * 0.51, 0.0, 0.0))
        assert tick(d) == (R if i % 2 else S), i


def test_goal_updated_controller():
    """test/plugins/decorator/test_goal_updated_controller.cpp test_behavior: the child on
    the first tick and for a new goal, RUNNING otherwise."""
    child = Dummy()
    g = node("GoalUpdatedController", child=child)
    bb_set(g, "goal", Pose2D(0.0, 0.0, 0.0))
    assert tick(g) == S and child.status == S
    bb_set(g, "goal", Pose2D(1.0, 0.0, 0.0))
    assert tick(g) == S
    assert tick(g) == R


def test_single_trigger():
    """test/plugins/decorator/test_single_trigger_node.cpp test_behavior: the child once per
    run, FAILURE afterwards; a halt re-arms it."""
    child = Dummy()
    n = node("SingleTrigger", child=child)
    assert tick(n) == S
    assert tick(n) == F
    n.stop(I)
    child.change(R)
    assert tick(n) == R
    child.change(S)
    assert tick(n) == S
    assert tick(n) == F


def test_goal_updated():
    """test/plugins/condition/test_goal_updated.cpp test_behavior."""
    n = node("GoalUpdated")
    bb_set(n, "goal", Pose2D(0.0, 0.0, 0.0))
    assert tick(n) == F
    bb_set(n, "goal", Pose2D(1.0, 0.0, 0.0))
    assert tick(n) == S
    assert tick(n) == F


def test_time_expired():
    """test/plugins/condition/test_time_expired.cpp test_behavior (seconds 1.0, sleeps of
    0.5 s -> clock)."""
    w = ScriptedWorld()
    n = node("TimeExpired", world=w, seconds=1.0)
    assert tick(n) == F
    for i in range(20):
        w.clock.advance(0.5)
        assert tick(n) == (S if i % 2 else F), i


def test_distance_traveled():
    """test/plugins/condition/test_distance_traveled.cpp test_behavior (distance 1.0)."""
    w = ScriptedWorld()
    n = node("DistanceTraveled", world=w, distance=1.0)
    assert tick(n) == F
    for i in range(1, 21):
        w.robot.teleport(Pose2D(i * 0.51, 0.0, 0.0))
        assert tick(n) == (F if i % 2 else S), i


def test_battery_conditions():
    """test/plugins/condition/test_is_battery_low.cpp (percentage and voltage) and
    test_is_battery_charging.cpp, with the robot's battery state instead of a topic."""
    from hw.interfaces import BatteryState
    w = ScriptedWorld()
    low = node("IsBatteryLow", world=w, min_battery=0.5)
    volts = node("IsBatteryLow", world=w, min_battery=5.0, is_voltage=True)
    charging = node("IsBatteryCharging", world=w)
    for pct, v, want_low, want_volts in [(1.0, 10.0, F, F), (0.49, 4.9, S, S),
                                         (0.51, 5.1, F, F), (0.0, 0.0, S, S)]:
        w.robot._battery = BatteryState(voltage=v, percentage=pct)
        assert (tick(low), tick(volts)) == (want_low, want_volts), pct
    assert tick(charging) == F
    w.robot._battery = BatteryState(voltage=12.0, percentage=0.3, charging=True)
    assert tick(charging) == S


@pytest.mark.parametrize("node_type, table", [
    ("WouldAPlannerRecoveryHelp", [(0, F), (200, S), (208, S), (207, S), (201, F), (206, F)]),
    ("WouldAControllerRecoveryHelp", [(0, F), (100, S), (101, F), (102, F), (103, F), (104, S),
                                      (105, S), (106, S)]),
    ("WouldASmootherRecoveryHelp", [(0, F), (500, S), (501, F), (502, S), (503, S), (504, S),
                                    (505, F)]),
])
def test_would_a_recovery_help(node_type, table):
    """test/plugins/condition/test_would_a_planner_recovery_help.cpp,
    test_would_a_controller_recovery_help.cpp and test_would_a_smoother_recovery_help.cpp:
    the codes a recovery may fix."""
    n = node(node_type, error_code="{code}")
    for code, want in table:
        bb_set(n, "code", code)
        assert tick(n) == want, code


def test_are_error_codes_present():
    """test/plugins/condition/test_are_error_codes_present.cpp."""
    n = node("AreErrorCodesPresent", error_code="{code}", error_codes_to_check=[100])
    for code, want in [(0, F), (100, S)]:
        bb_set(n, "code", code)
        assert tick(n) == want


def test_initial_pose_received_and_transform_available():
    """test/plugins/condition/test_initial_pose_received.cpp and test_transform_available.cpp
    (frames are the executive's: known frames succeed, others fail)."""
    n = node("InitialPoseReceived")
    assert tick(n) == F
    bb_set(n, "initial_pose_received", True)
    assert tick(n) == S
    known = node("TransformAvailable", port_values={"child": "base_link", "parent": "map"})
    assert tick(known) == S
    other = node("TransformAvailable", port_values={"child": "camera", "parent": "map"})
    assert tick(other) == F


def test_navigate_through_poses_subtree():
    """test/plugins/action/test_navigate_through_poses_action.cpp: the goals are passed in
    order and the node succeeds at the last (here the subtree runs with scripted components)."""
    w = ScriptedWorld()
    n = node("NavigateThroughPoses", world=w, replan_hz=1.0)
    bb_set(n, "goals", [Pose2D(1.0, 0.0, 0.0), Pose2D(1.5, 1.0, 0.0)])
    status = None
    for _ in range(2000):
        n.tick_once()
        status = n.status
        cmd = bb_get(n, "cmd_vel")
        w.step(cmd if cmd is not None else Twist.zero())
        if status is not R:
            break
    assert status == S
    assert w.robot.pose().distance_to(Pose2D(1.5, 1.0, 0.0)) <= 0.1
    plan = bb_get(n, "path")                  # planned through the first pose, in order
    first = min(range(len(plan)), key=lambda i: plan.pose(i).distance_to(Pose2D(1.0, 0.0)))
    assert plan.pose(first).distance_to(Pose2D(1.0, 0.0)) <= 0.05 and 0 < first < len(plan) - 1
