"""RemovePassedGoals, AppendGoalPoseToGoals, GetNextFewGoals, GetCurrentPose (Nav2 actions)
and ArePosesNear (Nav2 condition): goal lists are lists of Pose2D in map."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from behaviors.conditions.condition import Condition
from navcore.types import Pose2D


class _Plain(Leaf):
    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot", optional=True)


class RemovePassedGoals(_Plain):
    """Drop goals from the front of ``input_goals`` while the robot is within ``radius`` m of
    the first, always keeping the last one, and write the rest. With
    ``input_waypoint_statuses`` (a list of dicts with ``waypoint_pose`` and ``waypoint_status``)
    the removed goals are marked COMPLETED (1) in ``output_waypoint_statuses``. SUCCESS; an
    empty list is written as is. (Nav2 ``RemovePassedGoals``.)"""

    INPUT_PORTS = {
        "input_goals": PortInformation(list, True, "goals still to visit, Pose2D"),
        "radius": PortInformation(float, False, "distance that counts as passed, m", 0.5),
        "robot_base_frame": PortInformation(str, False, "Nav2's robot frame; unused",
                                            "base_link"),
        "input_waypoint_statuses": PortInformation(list, False, "status per waypoint"),
    }
    OUTPUT_PORTS = {
        "output_goals": PortInformation(list, True, "goals left"),
        "output_waypoint_statuses": PortInformation(list, False, "statuses, passed marked"),
    }

    def update(self) -> Status:
        goals = list(self.read("input_goals") or [])
        statuses = self.read("input_waypoint_statuses")
        statuses = None if statuses is None else [dict(s) for s in statuses]
        if goals:
            if self.robot is None:
                self.say("no robot pose")
                return FAILURE
            pose, radius = self.robot.pose(), self.get_input("radius")
            while len(goals) > 1 and pose.distance_to(goals[0]) <= radius:
                if statuses is not None:
                    match = next((s for s in statuses if s.get("waypoint_status", 0) == 0
                                  and s.get("waypoint_pose") == goals[0]), None)
                    if match is None:
                        self.say("a passed goal is not among the waypoint statuses")
                        return FAILURE
                    match["waypoint_status"] = WAYPOINT_COMPLETED
                goals.pop(0)
        self.write("output_goals", goals)
        if statuses is not None:
            self.write("output_waypoint_statuses", statuses)
        return SUCCESS


WAYPOINT_COMPLETED = 1  # nav2_msgs/WaypointStatus: PENDING 0, COMPLETED 1, SKIPPED 2, FAILED 3


class AppendGoalPoseToGoals(_Plain):
    """Write ``input_goals`` with ``goal_pose`` appended; SUCCESS (Nav2
    ``AppendGoalPoseToGoals``)."""

    INPUT_PORTS = {
        "goal_pose": PortInformation(Pose2D, True, "pose to append"),
        "input_goals": PortInformation(list, False, "goals, Pose2D"),
    }
    OUTPUT_PORTS = {"output_goals": PortInformation(list, True, "goals with the pose last")}

    def update(self) -> Status:
        pose = self.read("goal_pose")
        if pose is None:
            self.say("no goal_pose")
            return FAILURE
        self.write("output_goals", [*(self.read("input_goals") or []), pose])
        return SUCCESS


class GetNextFewGoals(_Plain):
    """Write the first ``num_goals`` of ``input_goals``; FAILURE when there are none (Nav2
    ``GetNextFewGoals``)."""

    INPUT_PORTS = {
        "input_goals": PortInformation(list, True, "goals, Pose2D"),
        "num_goals": PortInformation(int, True, "how many to keep"),
    }
    OUTPUT_PORTS = {"output_goals": PortInformation(list, True, "the first few goals")}

    def update(self) -> Status:
        goals, n = self.read("input_goals") or [], self.read("num_goals")
        if not goals or n is None:
            self.say("no goals" if not goals else "no num_goals")
            return FAILURE
        self.write("output_goals", list(goals[:max(0, n)]))
        return SUCCESS


class GetCurrentPose(_Plain):
    """Write the robot's pose in map to ``current_pose``; SUCCESS (Nav2 ``GetCurrentPose``;
    the frames are the executive's)."""

    INPUT_PORTS = {
        "global_frame": PortInformation(str, False, "Nav2's global frame; map here", "map"),
        "robot_base_frame": PortInformation(str, False, "Nav2's robot frame; unused",
                                            "base_link"),
    }
    OUTPUT_PORTS = {"current_pose": PortInformation(Pose2D, True, "robot pose in map")}

    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot")

    def update(self) -> Status:
        self.write("current_pose", self.robot.pose())
        return SUCCESS


class ArePosesNear(Condition):
    """SUCCESS when ``ref_pose`` and ``target_pose`` are within ``tolerance`` m (positions
    only; Nav2 ``ArePosesNear``)."""

    INPUT_PORTS = {
        "ref_pose": PortInformation(Pose2D, True, "first pose"),
        "target_pose": PortInformation(Pose2D, True, "second pose"),
        "global_frame": PortInformation(str, False, "Nav2's frame to compare in; map here",
                                        "map"),
        "tolerance": PortInformation(float, False, "distance, m", 0.5),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        a, b = self.read("ref_pose"), self.read("target_pose")
        if a is None or b is None:
            self.say("a pose is missing")
            return FAILURE
        tol = self.get_input("tolerance")
        dx, dy = a.x - b.x, a.y - b.y
        return SUCCESS if dx * dx + dy * dy <= tol * tol else FAILURE
