"""NavigateThroughPoses: Nav2's plan-through-poses-and-follow pipeline as one node."""

from __future__ import annotations

from behaviors.actions.compute_path_through_poses import ComputePathThroughPoses
from behaviors.base import Port, PortInformation
from behaviors.controls.navigate_to_pose import NavigateToPose


class NavigateThroughPoses(NavigateToPose):
    """Plan through ``goals`` in order and follow the path, replanning at ``replan_hz`` (a
    subtree, as navbt's NavigateToPose; Nav2's node asks another navigator to do this).

    Inside: PipelineSequence[RateController(hz)[ComputePathThroughPoses], FollowPath].
    SUCCESS when FollowPath reaches the last pose; FAILURE with the failing child's error code
    on the blackboard (``compute_path_error_code`` / ``follow_path_error_code``).
    """

    INPUT_PORTS = {
        "goals": PortInformation(list, True, "poses to pass, Pose2D in map, in order"),
        "replan_hz": Port(float, False, "replanning rate, Hz; 0 = plan once", 1.0, low=0.0),
        "planner_id": PortInformation(str, False, "planner id", "GridBased"),
        "controller_id": PortInformation(str, False, "controller id", "FollowPath"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goals": "goals"}
    PLANNER = ComputePathThroughPoses
    GOAL_PORT = "goals"
