"""ComputePrePose: where to line up before driving straight into a tight goal."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, Port, PortInformation, Status
from behaviors.costmap_choice import MeasuresOnCostmap
from navcore.motion.line_up import pre_pose
from navcore.types import Pose2D


class ComputePrePose(MeasuresOnCostmap, Leaf):
    """Write ``pre_pose``: a pose on ``goal``'s heading line, facing the goal, at least
    ``prepose_distance`` m back from it and far enough out that the robot can turn on the spot
    there without entering the narrow part (less than ``narrow_margin`` m per side beyond the
    footprint); the first such pose, a cell at a time up to ``max_extra`` m farther, whose
    footprint is free on the ``costmap`` (below the inscribed cost) and from which the straight
    way to the goal is passable (``navcore.motion.line_up``). SUCCESS with it written; FAILURE
    when there is none (or no goal). (Nav2's docking server lines up the same way on a staging
    pose, ``staging_x_offset`` behind the dock; here the offset follows from the space.)
    """

    INPUT_PORTS = {
        "goal": PortInformation(Pose2D, True, "goal pose in map"),
        "prepose_distance": Port(float, False, "m back from the goal, at least", 1.0, low=0.0),
        "narrow_margin": Port(float, False, "m of room per side beyond the footprint below "
                              "which the space counts as narrow", 0.15, low=0.0),
        "max_extra": Port(float, False, "m farther out searched for a free pre-pose", 1.0,
                          low=0.0),
        "costmap": PortInformation(str, False, "costmap checked on", "global"),
    }
    OUTPUT_PORTS = {"pre_pose": PortInformation(Pose2D, True, "where to line up")}
    DEFAULT_KEYS = {"goal": "goal", "pre_pose": "pre_pose"}

    def setup(self, **kwargs: Any) -> None:
        self.take_costmaps(kwargs)

    def update(self) -> Status:
        goal = self.read("goal")
        handle, fp = self.costmap_and_footprint()
        if goal is None or fp is None:
            self.say("no goal" if goal is None else "the costmap has no footprint polygon")
            return FAILURE
        p = pre_pose(handle, goal, fp,
                     self.get_input("prepose_distance"), self.get_input("narrow_margin"),
                     self.get_input("max_extra"))
        if p is None:
            self.say("no free pre-pose with a clear straight way in")
            return FAILURE
        self.write("pre_pose", p)
        self.say("line up at ({:.2f}, {:.2f}), {:.2f} m out", p.x, p.y, p.distance_to(goal))
        return SUCCESS
