"""Error codes written by the navigation actions, so that recoveries are chosen by cause.

Values follow Nav2's action definitions (ComputePathToPose 2xx, FollowPath 1xx, the behaviour
servers 7xx) so a Nav2 user's ``error_codes_to_check`` lists mean the same here. 0 is success.
"""

from __future__ import annotations

from enum import IntEnum


class PlannerError(IntEnum):
    """ComputePathToPose / ComputePathThroughPoses (nav2_msgs/action/ComputePathToPose)."""

    NONE = 0
    UNKNOWN = 200
    INVALID_PLANNER = 201
    TF_ERROR = 202
    START_OUTSIDE_MAP = 203
    GOAL_OUTSIDE_MAP = 204
    START_OCCUPIED = 205
    GOAL_OCCUPIED = 206
    TIMEOUT = 207
    NO_VALID_PATH = 208
    NO_VIAPOINTS_GIVEN = 209
    INVALID_GOAL = 210


class ControllerError(IntEnum):
    """FollowPath (nav2_msgs/action/FollowPath)."""

    NONE = 0
    UNKNOWN = 100
    INVALID_CONTROLLER = 101
    TF_ERROR = 102
    INVALID_PATH = 103
    PATIENCE_EXCEEDED = 104
    FAILED_TO_MAKE_PROGRESS = 105
    NO_VALID_CONTROL = 106
    CONTROLLER_TIMED_OUT = 107


class BehaviorError(IntEnum):
    """Spin, BackUp, DriveOnHeading, Wait and the navbt recoveries."""

    NONE = 0
    UNKNOWN = 700
    TIMEOUT = 701
    TF_ERROR = 702
    COLLISION_AHEAD = 703
    INVALID_INPUT = 704
    NO_FREE_POSE = 710       # TemporaryGoal: nothing reachable and free nearby
    NO_POSE_HISTORY = 711    # BackOffToPreviousPose: the robot has not moved yet
    PARAMETER_REJECTED = 720  # SetParameters: unknown namespace or value out of range


# Planner reason strings (PlanResultLike.reason) -> code.
PLANNER_REASONS: dict[str, PlannerError] = {
    "": PlannerError.NONE,
    "start_outside_map": PlannerError.START_OUTSIDE_MAP,
    "goal_outside_map": PlannerError.GOAL_OUTSIDE_MAP,
    "start_occupied": PlannerError.START_OCCUPIED,
    "goal_occupied": PlannerError.GOAL_OCCUPIED,
    "timeout": PlannerError.TIMEOUT,
    "no_path": PlannerError.NO_VALID_PATH,
    "no_valid_path": PlannerError.NO_VALID_PATH,
    "invalid_planner": PlannerError.INVALID_PLANNER,
    "invalid_goal": PlannerError.INVALID_GOAL,
}

# Nav2's default lists for WouldA...RecoveryHelp.
PLANNER_RECOVERABLE = [int(PlannerError.UNKNOWN), int(PlannerError.NO_VALID_PATH),
                       int(PlannerError.TIMEOUT)]
CONTROLLER_RECOVERABLE = [int(ControllerError.UNKNOWN), int(ControllerError.PATIENCE_EXCEEDED),
                          int(ControllerError.FAILED_TO_MAKE_PROGRESS),
                          int(ControllerError.NO_VALID_CONTROL)]


def planner_code(reason: str) -> PlannerError:
    """Map a planner's reason string to its code (UNKNOWN for anything unrecognised)."""
    return PLANNER_REASONS.get(reason, PlannerError.UNKNOWN)
