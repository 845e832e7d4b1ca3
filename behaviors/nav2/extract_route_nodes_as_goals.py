"""ExtractRouteNodesAsGoals (Nav2 action)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from navcore.route import Route
from navcore.types import Pose2D


class ExtractRouteNodesAsGoals(Leaf):
    """Write the positions of ``route``'s nodes as ``goals`` (heading 0); FAILURE for a route
    without nodes (Nav2 ``ExtractRouteNodesAsGoals``)."""

    INPUT_PORTS = {"route": PortInformation(Route, True, "a route from ComputeRoute")}
    OUTPUT_PORTS = {"goals": PortInformation(list, True, "node positions, Pose2D")}

    def setup(self, **kwargs: Any) -> None:
        pass

    def update(self) -> Status:
        route = self.read("route")
        if route is None or not route.nodes:
            self.say("the route has no nodes")
            return FAILURE
        self.write("goals", [Pose2D(n.x, n.y, 0.0) for n in route.nodes])
        return SUCCESS
