"""AppendGoalPoseToGoals and GetNextFewGoals (Nav2 actions on goal lists: lists of Pose2D
in map)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from navcore.types import Pose2D


class _Plain(Leaf):
    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot", optional=True)


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
