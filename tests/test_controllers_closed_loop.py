"""Both local planners drive a whole corridor to a goal pose through a rolling local window."""

from __future__ import annotations

import numpy as np
import pytest

from navcore.controllers import make_controller
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.footprint import footprint_cost
from navcore.costmap.inflation import cost_table, inflate
from navcore.maps import OCCUPIED
from navcore.synthetic_maps import corridor_map
from navcore.types import Path, Pose2D, Twist
from tests.test_controllers_support import DT, RECT


def corridor_costmap(width: float) -> Costmap2D:
    grid = corridor_map(length=12.0, width=width)
    cm = Costmap2D(grid.width, grid.height, grid.resolution, grid.origin.x, grid.origin.y)
    cm.costs[grid.data == OCCUPIED] = 254
    inflate(cm.costs, cost_table(cm.resolution, 0.22, 0.55, 10.0))
    return cm


def window(world: Costmap2D, local: Costmap2D, x: float, y: float) -> None:
    """What a rolling-window costmap holds around (x, y): the world's cells, unknown outside as
    free (track_unknown_space false), with the origin snapped to the world grid."""
    res = world.resolution
    ox = world.origin_x + np.floor((x - local.size_x * res / 2 - world.origin_x) / res) * res
    oy = world.origin_y + np.floor((y - local.size_y * res / 2 - world.origin_y) / res) * res
    local.origin_x, local.origin_y = ox, oy
    mx0 = int(round((ox - world.origin_x) / res))
    my0 = int(round((oy - world.origin_y) / res))
    local.costs[:] = 0
    sx0, sy0 = max(0, mx0), max(0, my0)
    sx1, sy1 = min(world.size_x, mx0 + local.size_x), min(world.size_y, my0 + local.size_y)
    if sx1 > sx0 and sy1 > sy0:
        local.costs[sy0 - my0:sy1 - my0, sx0 - mx0:sx1 - mx0] = world.costs[sy0:sy1, sx0:sx1]


@pytest.mark.parametrize("kind, params", [
    ("dwa_local_planner/DWAPlannerROS", {"max_vel_y": 0.0, "min_vel_y": 0.0,
                                         "vth_samples": 30, "sim_time": 2.0}),
    ("base_local_planner/TrajectoryPlannerROS", {"holonomic_robot": False,
                                                 "meter_scoring": True,
                                                 "path_distance_bias": 32.0,
                                                 "goal_distance_bias": 24.0}),
])
def test_corridor_run_reaches_the_goal_pose_without_touching_a_wall(kind, params):
    world = corridor_costmap(1.6)
    local = Costmap2D(80, 80, world.resolution)
    xs = np.arange(1.0, 10.0 + 1e-9, 0.05)
    path = Path(np.column_stack([xs, np.zeros_like(xs), np.zeros_like(xs)]))
    path.poses[-1, 2] = 0.8                                    # arrive, then turn to 0.8 rad
    ctl = make_controller(kind, local, RECT, params)
    pose, vel = Pose2D(1.0, 0.2, 0.4), Twist()
    statuses = []
    for _ in range(900):
        window(world, local, pose.x, pose.y)
        r = ctl.compute_velocity(pose, vel, path)
        statuses.append(r.status)
        assert footprint_cost(world.costs, world.origin_x, world.origin_y, world.resolution,
                              RECT, pose.x, pose.y, pose.theta) < 254
        if r.status == "goal_reached":
            break
        vel = r.cmd
        pose = pose.compose(Pose2D(vel.vx * DT, vel.vy * DT, vel.wz * DT))
    assert statuses[-1] == "goal_reached" and ctl.is_goal_reached()
    assert np.hypot(pose.x - 10.0, pose.y) <= 0.1 + 1e-9
    assert abs(pose.theta - 0.8) <= ctl.params.yaw_goal_tolerance + 1e-9
    assert "rotating_to_goal" in statuses
    assert statuses.count("no_valid_trajectory") == 0
