"""Goal tolerance, "stopped" and the stop-then-rotate-to-goal-yaw commands (base_local_planner's
goal_functions and LatchedStopRotateController), as plain functions of numbers."""

from __future__ import annotations

import math

from navcore.types import Pose2D, Twist, angle_diff


def stopped(vel: Twist, theta_stopped_vel: float, trans_stopped_vel: float) -> bool:
    """True when every body velocity component is within its "stopped" threshold."""
    return (abs(vel.wz) <= theta_stopped_vel and abs(vel.vx) <= trans_stopped_vel
            and abs(vel.vy) <= trans_stopped_vel)


def xy_reached(pose: Pose2D, goal: Pose2D, xy_goal_tolerance: float) -> bool:
    return math.hypot(goal.x - pose.x, goal.y - pose.y) <= xy_goal_tolerance


def yaw_reached(pose: Pose2D, goal: Pose2D, yaw_goal_tolerance: float) -> bool:
    return abs(angle_diff(goal.theta, pose.theta)) <= yaw_goal_tolerance


def _sign(v: float) -> float:
    return 1.0 if v >= 0.0 else -1.0  # ROS's sign(): zero counts as positive


def stop_with_acc_limits(vel: Twist, acc_lim: tuple[float, float, float],
                         sim_period: float) -> Twist:
    """Brake every axis as hard as the acceleration limits allow within one period."""
    return Twist(_sign(vel.vx) * max(0.0, abs(vel.vx) - acc_lim[0] * sim_period),
                 _sign(vel.vy) * max(0.0, abs(vel.vy) - acc_lim[1] * sim_period),
                 _sign(vel.wz) * max(0.0, abs(vel.wz) - acc_lim[2] * sim_period))


def rotate_to_goal_velocity(yaw: float, goal_yaw: float, current_wz: float, acc_lim_theta: float,
                            sim_period: float, min_rot: float, max_rot: float) -> float:
    """The in-place yaw rate toward ``goal_yaw``: at least ``min_rot`` (bases stall on tiny
    rotations), at most ``max_rot``, within one period's acceleration of the current rate, and
    slow enough to stop at the goal yaw (sqrt(2 a |error|))."""
    err = angle_diff(goal_yaw, yaw)
    w = min(max_rot, max(min_rot, abs(err)))
    w = min(max(w, abs(current_wz) - acc_lim_theta * sim_period),
            abs(current_wz) + acc_lim_theta * sim_period)
    w = min(w, math.sqrt(2.0 * acc_lim_theta * abs(err)))
    w = min(max_rot, max(min_rot, w))  # the minimum wins over the acceleration limit
    return -w if err < 0 else w
