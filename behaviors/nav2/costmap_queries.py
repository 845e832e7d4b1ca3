"""CheckPoseOccupancy and RemoveInCollisionGoals (Nav2 actions on the global costmap's
GetCosts service)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, Port, PortInformation, Status
from navcore.costmap.cost_values import NO_INFORMATION
from navcore.types import Pose2D


WAYPOINT_SKIPPED = 2  # nav2_msgs/WaypointStatus


class _CostQuery(Leaf):
    """Costs of poses on the global costmap: the footprint's cost (``use_footprint``) or the
    cell's; a pose off the map counts as unknown (255)."""

    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def setup(self, **kwargs: Any) -> None:
        self.costmap = self.component(kwargs, "global_costmap")

    def cost(self, pose: Pose2D) -> int:
        if self.get_input("use_footprint"):
            return int(self.costmap.footprint_cost(pose.x, pose.y, pose.theta))
        grid = self.costmap.costmap
        cell = grid.world_to_map(pose.x, pose.y)
        return NO_INFORMATION if cell is None else int(grid.costs[cell[1], cell[0]])

    def blocked(self, pose: Pose2D) -> bool:
        """Nav2's rule: unknown is free unless ``consider_unknown_as_obstacle``; otherwise a
        cost at or above ``cost_threshold`` blocks."""
        c = self.cost(pose)
        if c == NO_INFORMATION and not self.get_input("consider_unknown_as_obstacle"):
            return False
        return c >= self.get_input("cost_threshold")


_QUERY_PORTS = {
    "cost_threshold": Port(float, False, "cost at which a pose counts as occupied", 254.0,
                           low=0.0, high=255.0),
    "use_footprint": PortInformation(bool, False, "check the footprint, not the cell", True),
    "consider_unknown_as_obstacle": PortInformation(bool, False, "unknown cells block", False),
}


class CheckPoseOccupancy(_CostQuery):
    """SUCCESS when ``pose`` is occupied on the global costmap (see ``cost_threshold``),
    FAILURE when it is free (Nav2 main ``CheckPoseOccupancy``)."""

    INPUT_PORTS = {"pose": PortInformation(Pose2D, True, "pose to check"), **_QUERY_PORTS}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        pose = self.read("pose")
        if pose is None:
            self.say("no pose")
            return FAILURE
        return SUCCESS if self.blocked(pose) else FAILURE


class RemoveInCollisionGoals(_CostQuery):
    """Write ``input_goals`` without the goals that are occupied on the global costmap; with
    ``input_waypoint_statuses`` the removed ones are marked SKIPPED. SUCCESS (also when every
    goal was removed). (Nav2 Kilted+ ``RemoveInCollisionGoals``.)"""

    INPUT_PORTS = {
        "input_goals": PortInformation(list, True, "goals, Pose2D"),
        "input_waypoint_statuses": PortInformation(list, False, "status per waypoint"),
        **_QUERY_PORTS,
    }
    OUTPUT_PORTS = {
        "output_goals": PortInformation(list, True, "goals that are free"),
        "output_waypoint_statuses": PortInformation(list, False, "statuses, removed skipped"),
    }

    def update(self) -> Status:
        goals = list(self.read("input_goals") or [])
        statuses = self.read("input_waypoint_statuses")
        statuses = None if statuses is None else [dict(s) for s in statuses]
        kept = []
        for g in goals:
            if not self.blocked(g):
                kept.append(g)
            elif statuses is not None:
                match = next((s for s in statuses if s.get("waypoint_status", 0) == 0
                              and s.get("waypoint_pose") == g), None)
                if match is None:
                    self.say("a removed goal is not among the waypoint statuses")
                    return FAILURE
                match["waypoint_status"] = WAYPOINT_SKIPPED
        self.write("output_goals", kept)
        if statuses is not None:
            self.write("output_waypoint_statuses", statuses)
        self.say(f"{len(goals) - len(kept)} of {len(goals)} goals in collision")
        return SUCCESS
