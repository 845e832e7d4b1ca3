"""The parameter tables of the namespaces the executive owns: ``robot`` (body and devices),
``move_base``, ``safety`` and ``behavior_server``.

They sit below executive.config so that the ROS readers config uses (ros_params, nav2_params)
can name them without importing config back.
"""
from __future__ import annotations

from navcore.params import Param

ROBOT_PARAMS: tuple[Param, ...] = (
    Param("footprint", [[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]], list,
          "robot outline in base_link, counter- or clockwise [[x, y], ...] (m); [] to use "
          "robot_radius"),
    Param("robot_radius", 0.0, float, "circular robot radius (m), used when footprint is []",
          min=0.0, max=5.0),
    Param("devices", "sim", str, "'sim' for the simulator (real devices: see 'base'/'laser' URLs)"),
    Param("base", "", str, "URL of the base driver (from devices: {base: ...})"),
    Param("laser", "", str, "URL of the laser driver (from devices: {laser: ...})"),
)

MOVE_BASE_PARAMS: tuple[Param, ...] = (
    Param("base_global_planner", "navfn/NavfnROS", str, "global planner plugin",
          choices=("navfn/NavfnROS", "global_planner/GlobalPlanner",
                   "carrot_planner/CarrotPlanner")),
    Param("base_local_planner", "base_local_planner/TrajectoryPlannerROS", str,
          "local planner plugin",
          choices=("base_local_planner/TrajectoryPlannerROS", "dwa_local_planner/DWAPlannerROS")),
    Param("controller_frequency", 20.0, float, "control loop rate (Hz)", min=0.1, max=1000.0),
    Param("planner_frequency", 0.0, float, "replanning rate (Hz); 0 plans on new goals/failures",
          min=0.0, max=100.0),
    Param("planner_patience", 5.0, float, "time to find a valid plan before recovery (s)",
          min=0.0),
    Param("controller_patience", 15.0, float, "time without a valid command before recovery (s)",
          min=0.0),
    Param("max_planning_retries", -1, int, "planning retries before recovery; -1 = unlimited",
          min=-1),
    Param("oscillation_timeout", 0.0, float, "time allowed to oscillate before recovery; 0 off",
          min=0.0),
    Param("oscillation_distance", 0.5, float, "distance that resets the oscillation timer (m)",
          min=0.0),
    Param("conservative_reset_dist", 3.0, float, "conservative clear_costmap reset distance (m)",
          min=0.0),
    Param("clearing_radius", -1.0, float, "clearing radius; -1 = circumscribed radius"),
    Param("recovery_behavior_enabled", True, bool, "run recovery behaviours"),
    Param("clearing_rotation_allowed", True, bool, "allow rotate_recovery"),
    Param("shutdown_costmaps", False, bool, "stop costmaps when inactive (kept for parity)"),
    Param("make_plan_clear_costmap", True, bool, "kept for parity"),
    Param("make_plan_add_unreachable_goal", True, bool, "kept for parity"),
)

SAFETY_PARAMS: tuple[Param, ...] = (
    Param("max_vel_x", 0.55, float, "hard forward speed limit (m/s)", min=0.0, max=10.0),
    Param("min_vel_x", -0.3, float, "hard reverse speed limit (m/s, <= 0)", min=-10.0, max=0.0),
    Param("max_vel_y", 0.0, float, "hard lateral speed limit (m/s)", min=0.0, max=10.0),
    Param("max_vel_theta", 1.5, float, "hard yaw rate limit (rad/s)", min=0.0, max=20.0),
    Param("sensor_timeout", 0.5, float, "laser/odometry older than this stops the robot (s)",
          min=0.001, max=10.0),
    Param("stall_timeout", 2.0, float, "commanded motion without measured motion for this long "
          "is a stall (s); 0 = no stall check", min=0.0, max=60.0),
    Param("stall_speed", 0.02, float, "measured speed below which a commanded robot counts as "
          "stalled (m/s or rad/s)", min=0.0, max=1.0),
    Param("stop_on_bumper", True, bool, "a pressed bumper blocks forward motion"),
    Param("stamp_tolerance", 0.02, float, "a sensor stamp further than this in the future is "
          "invalid (s)", min=0.0, max=1.0),
    Param("frozen_scans", 2, int, "this many consecutive fresh scans with identical ranges while "
          "odometry reports motion mean a frozen laser", min=2, max=1000),
    Param("watchdog_periods", 1.5, float, "a control cycle taking longer than this many periods "
          "of wall time stops the robot (wall clock only)", min=1.0, max=100.0),
)

# Nav2's behavior_server parameters: the recovery nodes' ports of those names take these values
# unless the tree sets them (see RobotConfig.port_defaults); defaults are Nav2's.
BEHAVIOR_SERVER_PARAMS: tuple[Param, ...] = (
    Param("simulate_ahead_time", 2.0, float, "collision look-ahead of Spin, BackUp, "
          "DriveOnHeading (s)", min=0.0),
    Param("max_rotational_vel", 1.0, float, "Spin's top yaw rate (rad/s)", min=0.0),
    Param("min_rotational_vel", 0.4, float, "Spin's lowest yaw rate (rad/s)", min=0.0),
    Param("rotational_acc_lim", 3.2, float, "Spin's yaw acceleration (rad/s^2)", min=0.0),
)
# the behavior_server's plugins, by their node names
BEHAVIOR_SERVER_NODES = ("Spin", "BackUp", "DriveOnHeading", "Wait", "AssistedTeleop")

OWN_NAMESPACES: dict[str, tuple[Param, ...]] = {
    "robot": ROBOT_PARAMS,
    "move_base": MOVE_BASE_PARAMS,
    "safety": SAFETY_PARAMS,
    "behavior_server": BEHAVIOR_SERVER_PARAMS,
}


# move_base parameters that a tree decides in navbt (trees/move_base.yaml writes move_base's
# defaults as its nodes' ports): where each one lives.
MOVE_BASE_IN_TREE = {
    "planner_frequency": "GoalUpdatedController (0) or RateController hz around "
                         "ComputePathToPose",
    "planner_patience": "Timeout msec around ComputePathToPose (PlannerPatience)",
    "controller_patience": "FollowPath failure_tolerance",
    "max_planning_retries": "RetryUntilSuccessful num_attempts (MaxPlanningRetries)",
    "oscillation_timeout": "IsOscillating oscillation_timeout",
    "oscillation_distance": "IsOscillating oscillation_distance",
    "conservative_reset_dist": "ClearCostmapExceptRegion reset_distance (conservative_reset)",
    "clearing_radius": "the recovery nodes' clearing ports",
    "recovery_behavior_enabled": "the recovery subtree (MoveBaseRecoveries)",
    "clearing_rotation_allowed": "the Spin nodes of the recovery subtree",
    "shutdown_costmaps": "nothing (costmaps run while the executive runs)",
    "make_plan_clear_costmap": "nothing (no make_plan service)",
    "make_plan_add_unreachable_goal": "nothing (no make_plan service)",
}
