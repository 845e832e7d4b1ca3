"""navcore.motion: the geometry, collision checks, pure pursuit, escape search and path-progress
kernels the recoveries use (each against a plain reference or a hand-computed case)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from navcore.motion.collision import first_collision, is_collision
from navcore.motion.escape import arc_goal, rank_candidates
from navcore.motion.geometry import arc_poses, heading_to, ring_candidates
from navcore.motion.path_progress import length_to_go, remaining_length
from navcore.motion.pursuit import pure_pursuit, swept_poses
from navcore.types import Path, Pose2D


class WallAt:
    """A costmap handle: lethal footprint cost from x >= ``x``, inscribed 0.1 m before it."""

    def __init__(self, x: float) -> None:
        self.x = x
        self.costmap = Costmap2D(10, 10, 0.5, -2.5, -2.5)

    def footprint_cost(self, x: float, y: float, theta: float) -> int:
        if x >= self.x:
            return LETHAL_OBSTACLE
        return INSCRIBED_INFLATED_OBSTACLE if x >= self.x - 0.1 else 0


def test_is_collision_lets_a_robot_out_of_inscribed_cost_but_never_into_lethal():
    assert is_collision(-1) and is_collision(LETHAL_OBSTACLE, INSCRIBED_INFLATED_OBSTACLE)
    assert is_collision(INSCRIBED_INFLATED_OBSTACLE, 0)
    assert not is_collision(INSCRIBED_INFLATED_OBSTACLE, INSCRIBED_INFLATED_OBSTACLE)
    assert not is_collision(100, 0)


def test_first_collision_finds_the_first_blocked_pose():
    poses = [Pose2D(0.1 * k, 0.0, 0.0) for k in range(1, 20)]
    hit = first_collision(WallAt(1.0), poses, Pose2D())
    assert hit is not None and hit[0].x == pytest.approx(0.9) and hit[1] == INSCRIBED_INFLATED_OBSTACLE
    assert first_collision(WallAt(5.0), poses, Pose2D()) is None


def test_pure_pursuit_drives_forwards_or_backwards_on_the_arc_through_the_aim():
    trail = [Pose2D(1.0, 0.0), Pose2D(2.0, 1.0)]
    cmd, i = pure_pursuit(Pose2D(), trail, 0, trail[-1], 0.2, 0.5, 1.0, 0.1)
    assert (cmd.vx, cmd.wz, i) == (0.2, 0.0, 0)           # aim straight ahead
    cmd, i = pure_pursuit(Pose2D(0.8, 0.0), trail, 0, trail[-1], 0.2, 0.5, 1.0, 0.1)
    aim = trail[1].relative_to(Pose2D(0.8, 0.0))
    assert i == 1 and cmd.vx == 0.2
    assert cmd.wz == pytest.approx(0.2 * 2.0 * aim.y / (aim.x ** 2 + aim.y ** 2))
    back = [Pose2D(-1.0, 0.5)]
    cmd, _ = pure_pursuit(Pose2D(), back, 0, back[0], 0.2, 0.1, 0.05, 0.1)
    assert cmd.vx == -0.2 and cmd.wz == -0.05              # behind and left: reverse, clamped
    near = [Pose2D(0.01, 0.0)]
    cmd, _ = pure_pursuit(Pose2D(), near, 0, near[0], 0.2, 0.1, 1.0, 0.1)
    assert cmd.vx == pytest.approx(0.1)                    # no faster than reaches it in a period


def test_swept_poses_integrate_the_command():
    poses = swept_poses(Pose2D(), 0.2, 0.0, 1.0)
    assert len(poses) == 4 and poses[-1].x == pytest.approx(0.2)
    turn = swept_poses(Pose2D(), 0.0, 1.0, 0.5)
    assert len(turn) == 1 and turn[0].theta == pytest.approx(0.5)


def test_ring_candidates_face_away_on_each_ring():
    c = ring_candidates(Pose2D(1.0, 2.0, 0.3), 0.4, 0.8, 0.2, 8)
    assert len(c) == 3 * 8
    for p in c:
        r = math.hypot(p.x - 1.0, p.y - 2.0)
        assert min(abs(r - x) for x in (0.4, 0.6, 0.8)) < 1e-9
        assert abs(math.remainder(heading_to(Pose2D(1.0, 2.0), p) - p.theta, 2 * math.pi)) < 1e-9


def test_arc_poses_end_at_the_point_tangent_to_the_arc():
    start = Pose2D(0.0, 0.0, 0.0)
    arc = arc_poses(start, 1.0, 1.0, 0.03)
    assert arc is not None and arc[-1].x == pytest.approx(1.0) and arc[-1].y == pytest.approx(1.0)
    assert arc[-1].theta == pytest.approx(math.pi / 2)      # a quarter circle of radius 1
    steps = [a.distance_to(b) for a, b in zip([start] + arc, arc)]
    assert max(steps) <= 0.03 + 1e-9
    back = arc_poses(start, -1.0, 0.0, 0.1)
    assert back is not None and back[-1].x == pytest.approx(-1.0) and back[-1].theta == 0.0
    assert arc_poses(start, 0.0, 1.0, 0.03) is None          # abeam: a half turn
    assert arc_poses(start, 1.0, 1.0, 0.03, end_only=True) == [arc[-1]]


def test_escape_ranks_open_poses_ahead_first_and_finds_a_clear_arc():
    wall = WallAt(0.5)                                       # the way ahead is blocked
    pose = Pose2D()
    cands = ring_candidates(pose, 0.6, 0.6, 0.2, 8)
    ranked = rank_candidates(wall, pose, cands)
    assert all(p.x < 0.4 for p in ranked)                    # none at or past the wall
    assert ranked[0].x == pytest.approx(-0.6)                # straight behind: no turn
    goal = arc_goal(wall, wall, pose, cands, None)
    assert goal is not None and goal.x < 0.0                 # backwards, away from the wall
    arc = arc_poses(pose, goal.x, goal.y, 0.03)
    assert first_collision(wall, arc, pose) is None


def test_remaining_length_matches_numpy_argmin_on_random_paths():
    """The kernel picks the same pose as np.argmin (first of ties) and gives the same sum."""
    rng = np.random.default_rng(7)
    for k in range(400):
        n = int(rng.integers(1, 40))
        poses = rng.normal(0.0, 3.0, (n, 3))
        if k % 3 == 0:
            poses[:, :2] = np.round(poses[:, :2])          # ties between poses
        if k % 5 == 0:
            poses = np.asfortranarray(poses)               # any memory layout
        path = Path(poses)
        pose = Pose2D(*rng.normal(0.0, 3.0, 3))
        d = np.hypot(path.poses[:, 0] - pose.x, path.poses[:, 1] - pose.y)
        i = int(np.argmin(d))
        to_go = length_to_go(path.poses)
        assert remaining_length(path, pose) == float(d[i] + to_go[i])
    assert remaining_length(Path(np.zeros((0, 3))), Pose2D()) == 0.0
    line = Path(np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]]))
    assert remaining_length(line, Pose2D(1.2, 0.5, 0.0)) == np.hypot(0.2, 0.5) + 2.0


def test_length_to_go_matches_the_reversed_cumulative_sum():
    rng = np.random.default_rng(8)
    for k in range(300):
        poses = rng.normal(0.0, 5.0, (int(rng.integers(0, 120)), 3))
        if k % 4 == 0:
            poses = np.asfortranarray(poses)
        steps = np.hypot(np.diff(poses[:, 0]), np.diff(poses[:, 1]))
        want = (np.concatenate([np.cumsum(steps[::-1])[::-1], [0.0]]) if len(steps)
                else np.zeros(1))
        np.testing.assert_array_equal(length_to_go(poses), want)


def test_first_blocked_path_pose_on_the_grid():
    from navcore.costmap.cost_values import NO_INFORMATION
    from navcore.costmap.path_check import first_blocked
    cm = Costmap2D(20, 10, 0.1, 0.0, 0.0)
    cm.costs[5, 12] = INSCRIBED_INFLATED_OBSTACLE
    cm.costs[5, 8] = NO_INFORMATION
    poses = np.array([[0.05 + 0.1 * i, 0.55, 0.0] for i in range(-3, 20)])  # three off the map
    assert first_blocked(cm, poses, INSCRIBED_INFLATED_OBSTACLE - 1) == (15, 253)
    assert first_blocked(cm, poses, INSCRIBED_INFLATED_OBSTACLE - 1, True) == (11, 255)
    assert first_blocked(cm, poses, INSCRIBED_INFLATED_OBSTACLE) is None


def test_blocked_poses_all_of_them_and_within_a_lookahead():
    """ValidatePath's check: every blocked pose, or those within a path length."""
    from navcore.costmap.cost_values import NO_INFORMATION
    from navcore.costmap.path_check import blocked_poses
    cm = Costmap2D(20, 10, 0.1, 0.0, 0.0)
    cm.costs[5, 8] = NO_INFORMATION
    cm.costs[5, 12] = INSCRIBED_INFLATED_OBSTACLE
    cm.costs[5, 16] = INSCRIBED_INFLATED_OBSTACLE
    poses = np.array([[0.05 + 0.1 * i, 0.55, 0.0] for i in range(20)])
    assert blocked_poses(cm, poses, 252, first_only=False) == [(12, 253), (16, 253)]
    assert blocked_poses(cm, poses, 252, True, first_only=False) == [(8, 255), (12, 253),
                                                                      (16, 253)]
    # 1.25 m along the path reaches pose 12 (1.2 m from pose 0), not pose 16 (1.6 m)
    assert blocked_poses(cm, poses, 252, max_length=1.25, first_only=False) == [(12, 253)]
    assert blocked_poses(cm, poses, 252, max_length=1.1) == []
    # an unknown cell blocks whenever unknown cells block, whatever max_cost says
    assert blocked_poses(cm, poses, 255, True) == [(8, 255)]


def test_back_off_trail_goes_back_from_the_nearest_pose_to_a_free_one():
    from navcore.motion.trail import back_off_trail
    history = [Pose2D(0.1 * i, 0.0, 0.0) for i in range(21)]          # 0 .. 2 m along x
    trail = back_off_trail(history, Pose2D(1.52, 0.03, 0.0), 0.5, 2.0)
    assert trail[0].x == pytest.approx(1.5) and trail[-1].x == pytest.approx(1.0)
    assert [p.x for p in trail] == sorted((p.x for p in trail), reverse=True)
    class Tight:                                                        # inscribed before 0.75
        def footprint_cost(self, x, y, t):
            return INSCRIBED_INFLATED_OBSTACLE if x >= 0.75 else 0
    longer = back_off_trail(history, Pose2D(1.5, 0.0, 0.0), 0.5, 2.0, Tight())
    assert longer[-1].x == pytest.approx(0.7)                          # on to the first free pose
    capped = back_off_trail(history, Pose2D(1.5, 0.0, 0.0), 0.5, 0.6, Tight())
    assert capped[-1].x == pytest.approx(0.9)                          # no further than 0.6 m
    assert back_off_trail([], Pose2D(), 0.5, 2.0) == []
    assert back_off_trail(history[:1], Pose2D(), 0.5, 2.0, Tight()) == []  # nowhere to go
