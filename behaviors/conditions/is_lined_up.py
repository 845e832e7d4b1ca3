"""IsLinedUp: does the robot stand on the straight way into the goal?"""

from __future__ import annotations

from behaviors.base import FAILURE, Port, PortInformation, Status
from behaviors.conditions.condition import Condition, yes
from navcore.motion.line_up import line_offsets
from navcore.types import Pose2D


class IsLinedUp(Condition):
    """SUCCESS when the robot stands behind ``goal`` on its heading line, facing along it: at
    most ``max_distance`` m to go along the line, at most ``lateral_tolerance`` m beside it and
    ``yaw_tolerance`` rad off its heading. FAILURE otherwise, or with no goal yet. (What a
    straight entry, ``ApproachStraight``, needs to start from.)
    """

    INPUT_PORTS = {
        "goal": PortInformation(Pose2D, True, "goal pose in map"),
        "lateral_tolerance": Port(float, False, "m beside the line", 0.1, low=0.0),
        "yaw_tolerance": Port(float, False, "rad off the goal's heading", 0.2, low=0.0),
        "max_distance": Port(float, False, "m to go along the line at most", 2.0, low=0.0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    def update(self) -> Status:
        goal = self.read("goal")
        if goal is None:
            self.say("no goal")
            return FAILURE
        to_go, lateral, heading = line_offsets(goal, self.pose())
        ok = (0.0 <= to_go <= self.get_input("max_distance")
              and abs(lateral) <= self.get_input("lateral_tolerance")
              and abs(heading) <= self.get_input("yaw_tolerance"))
        self.say("{:.2f} m to go, {:.2f} m beside, {:.2f} rad off", to_go, lateral, heading)
        return yes(ok)
