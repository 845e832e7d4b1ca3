"""RemovePassedGoals (Nav2 action)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status


WAYPOINT_COMPLETED = 1  # nav2_msgs/WaypointStatus: PENDING 0, COMPLETED 1, SKIPPED 2, FAILED 3


class RemovePassedGoals(Leaf):
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

    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot", optional=True)

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
