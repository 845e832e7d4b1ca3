"""Error codes of the navigation actions, so that recoveries are chosen by cause, and the one
table from the planners' and controllers' results to them.

Values follow Nav2's action definitions (nav2_msgs/action: ComputePathToPose 2xx, FollowPath 1xx,
ComputeRoute 4xx, SmoothPath 5xx, Spin 70x, BackUp 71x, DriveOnHeading 72x, Wait 74x), so a Nav2 user's ``error_codes_to_check``
lists mean the same here; 0 is success. navbt's own recoveries (TemporaryGoal,
BackOffToPreviousPose) use 80x. ``UNOBSERVED_SPACE`` (x9 of each motion recovery's range, 812 for
navbt's own) is navbt's, not Nav2's: the motion would enter space the sensors have not seen free
recently (navcore.costmap.observed_space). A bug is none of these: it raises, and the
executive ends the mission with INTERNAL_ERROR (no recovery branch ever sees it).
"""

from __future__ import annotations

from enum import IntEnum

from navcore.controllers.result import ControlStatus
from navcore.planners.result import PlanReason


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


class SmootherError(IntEnum):
    """nav2_msgs/action/SmoothPath error codes."""

    NONE = 0
    UNKNOWN = 500
    INVALID_SMOOTHER = 501
    TIMEOUT = 502
    SMOOTHED_PATH_IN_COLLISION = 503
    FAILED_TO_SMOOTH_PATH = 504
    INVALID_PATH = 505


class RouteErrorCode(IntEnum):
    """nav2_msgs/action/ComputeRoute (and ComputeAndTrackRoute) error codes."""

    NONE = 0
    UNKNOWN = 400
    TF_ERROR = 401
    NO_VALID_GRAPH = 402
    INDETERMINANT_NODES_ON_GRAPH = 403
    TIMEOUT = 404
    NO_VALID_ROUTE = 405
    INVALID_EDGE_SCORER_USE = 407


class SpinError(IntEnum):
    """Spin (nav2_msgs/action/Spin)."""

    NONE = 0
    UNKNOWN = 700
    TIMEOUT = 701
    TF_ERROR = 702
    COLLISION_AHEAD = 703
    UNOBSERVED_SPACE = 709    # navbt: the sweep reaches space not observed free recently


class BackUpError(IntEnum):
    """BackUp (nav2_msgs/action/BackUp)."""

    NONE = 0
    UNKNOWN = 710
    TIMEOUT = 711
    TF_ERROR = 712
    INVALID_INPUT = 713
    COLLISION_AHEAD = 714
    UNOBSERVED_SPACE = 719    # navbt: the way back was not observed free recently


class DriveOnHeadingError(IntEnum):
    """DriveOnHeading (nav2_msgs/action/DriveOnHeading)."""

    NONE = 0
    UNKNOWN = 720
    TIMEOUT = 721
    TF_ERROR = 722
    COLLISION_AHEAD = 723
    INVALID_INPUT = 724
    UNOBSERVED_SPACE = 729    # navbt: the way was not observed free recently


class WaitError(IntEnum):
    """Wait (nav2_msgs/action/Wait)."""

    NONE = 0
    UNKNOWN = 740
    TIMEOUT = 741


class RecoveryError(IntEnum):
    """navbt's own recoveries: TemporaryGoal, BackOffToPreviousPose."""

    NONE = 0
    UNKNOWN = 800
    TIMEOUT = 801
    COLLISION_AHEAD = 803
    INVALID_INPUT = 804
    NO_FREE_POSE = 810        # TemporaryGoal: nothing reachable and free nearby
    NO_POSE_HISTORY = 811     # BackOffToPreviousPose: the robot has not moved yet
    UNOBSERVED_SPACE = 812    # the way was not observed free recently


# The one table: a planner's reason -> the code ComputePathToPose writes.
PLAN_CODES: dict[PlanReason, PlannerError] = {
    PlanReason.NONE: PlannerError.NONE,
    PlanReason.INVALID_POSE: PlannerError.UNKNOWN,  # a non-finite start (localisation) or goal
    PlanReason.START_OUTSIDE_MAP: PlannerError.START_OUTSIDE_MAP,
    PlanReason.GOAL_OUTSIDE_MAP: PlannerError.GOAL_OUTSIDE_MAP,
    PlanReason.START_OCCUPIED: PlannerError.START_OCCUPIED,
    PlanReason.GOAL_OCCUPIED: PlannerError.GOAL_OCCUPIED,
    PlanReason.NO_PATH: PlannerError.NO_VALID_PATH,
}

# ... and a controller's failing status -> the code FollowPath writes (NO_VALID_CONTROL becomes
# PATIENCE_EXCEEDED once FollowPath's failure_tolerance has run out).
CONTROL_CODES: dict[ControlStatus, ControllerError] = {
    ControlStatus.NO_VALID_TRAJECTORY: ControllerError.NO_VALID_CONTROL,
    ControlStatus.NO_PLAN: ControllerError.INVALID_PATH,
}

# Nav2's default lists for WouldA...RecoveryHelp.
PLANNER_RECOVERABLE = [int(PlannerError.UNKNOWN), int(PlannerError.NO_VALID_PATH),
                       int(PlannerError.TIMEOUT)]
CONTROLLER_RECOVERABLE = [int(ControllerError.UNKNOWN), int(ControllerError.PATIENCE_EXCEEDED),
                          int(ControllerError.FAILED_TO_MAKE_PROGRESS),
                          int(ControllerError.NO_VALID_CONTROL)]
ROUTE_RECOVERABLE = [int(RouteErrorCode.UNKNOWN), int(RouteErrorCode.NO_VALID_ROUTE),
                     int(RouteErrorCode.TIMEOUT)]
SMOOTHER_RECOVERABLE = [int(SmootherError.UNKNOWN), int(SmootherError.TIMEOUT),
                        int(SmootherError.FAILED_TO_SMOOTH_PATH),
                        int(SmootherError.SMOOTHED_PATH_IN_COLLISION)]
