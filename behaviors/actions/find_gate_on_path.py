"""FindGateOnPath: the narrow passage ahead on the path, to line up for."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, Port, PortInformation, Status
from behaviors.costmap_choice import MeasuresOnCostmap
from navcore.motion.gate import gate_on_path
from navcore.types import Path, Pose2D


class FindGateOnPath(MeasuresOnCostmap, Leaf):
    """Write ``gate``: where the robot drives straight to through the narrowest place of
    ``path`` within ``lookahead`` m ahead of it, when the room there is less than
    ``narrow_margin`` m per side beyond the footprint (a gap in a wall, a doorway): the pose on
    the straight line through that place along the path, farthest still in the narrow part,
    facing along the path. A tree lines up in front of it and drives through
    (``ComputePrePose`` and ``ApproachStraight`` with ``goal`` = the gate): the break-out for a
    robot swinging between two gaps (``IsDithering``). SUCCESS with it written; FAILURE without
    a path, a footprint, or a narrow place ahead.
    """

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "the plan being followed"),
        "lookahead": Port(float, False, "m of path ahead searched", 3.0, low=0.0),
        "narrow_margin": Port(float, False, "m of room per side beyond the footprint below "
                              "which a place counts as narrow", 0.15, low=0.0),
        "costmap": PortInformation(str, False, "costmap measured on", "global"),
    }
    OUTPUT_PORTS = {"gate": PortInformation(Pose2D, True, "where to drive straight to")}
    DEFAULT_KEYS = {"path": "path", "gate": "gate"}

    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot")
        self.take_costmaps(kwargs)

    def update(self) -> Status:
        path = self.read("path")
        handle, fp = self.costmap_and_footprint()
        if path is None or fp is None:
            self.say("no path" if path is None else "the costmap has no footprint polygon")
            return FAILURE
        gate = gate_on_path(handle.costmap, path, self.robot.pose(), fp,
                            self.get_input("lookahead"), self.get_input("narrow_margin"))
        if gate is None:
            self.say("nothing narrow ahead on the path")
            return FAILURE
        self.write("gate", gate)
        self.say("gate at ({:.2f}, {:.2f}) heading {:.2f}", gate.x, gate.y, gate.theta)
        return SUCCESS
