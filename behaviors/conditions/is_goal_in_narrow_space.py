"""IsGoalInNarrowSpace: is the goal in a space only a little wider than the robot?"""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, Port, PortInformation, Status
from behaviors.conditions.condition import Condition, yes
from behaviors.costmap_choice import MeasuresOnCostmap
from navcore.motion.line_up import goal_room
from navcore.types import Pose2D


class IsGoalInNarrowSpace(MeasuresOnCostmap, Condition):
    """SUCCESS when the free width across ``goal`` (between the walls either side of the
    robot's body standing there, narrowest over its length, measured on the ``costmap``'s
    lethal cells) leaves less than ``narrow_margin`` metres per side beyond the footprint: a
    bay or a slot to be entered straight. FAILURE when there is more room, or no goal yet.
    ``free_width`` gets the width measured (m).
    """

    INPUT_PORTS = {
        "goal": PortInformation(Pose2D, True, "goal pose in map"),
        "narrow_margin": Port(float, False, "m of room per side beyond the footprint below "
                              "which the goal counts as narrow", 0.15, low=0.0),
        "costmap": PortInformation(str, False, "costmap measured on", "global"),
    }
    OUTPUT_PORTS = {"free_width": PortInformation(float, False, "free width across the goal, m")}
    DEFAULT_KEYS = {"goal": "goal"}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self.take_costmaps(kwargs)

    def update(self) -> Status:
        goal = self.read("goal")
        handle, fp = self.costmap_and_footprint()
        if goal is None or fp is None:
            self.say("no goal" if goal is None else "the costmap has no footprint polygon")
            return FAILURE
        room = goal_room(handle.costmap, goal, fp)
        self.write("free_width", room.width)
        narrow = room.margin < self.get_input("narrow_margin")
        self.say("{:.2f} m across the goal, {:.2f} m per side: {}", room.width, room.margin,
                 "narrow" if narrow else "open")
        return yes(narrow)
