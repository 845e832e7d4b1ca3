"""ComputeRoute (Nav2 action): routes on the route graph handed to ``setup`` as
``route_graph`` (a navcore.route.RouteGraph from a Nav2 GeoJSON file; the robot config's
``route_server.graph_filepath``)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from navcore.error_codes import RouteErrorCode
from navcore.route import Route, RouteError, densify, find_route, route_between_poses
from navcore.types import Path, Pose2D


PATH_DENSITY = 0.05  # m between poses of the route's path (nav2_route's path_density default)


class ComputeRoute(Leaf):
    """Find the cheapest route on the route graph and write it with its dense ``path``.

    With ``use_poses`` the route runs between the graph nodes nearest ``start`` (the robot pose
    unless ``use_start``) and ``goal``; otherwise between ``start_id`` and ``goal_id``. SUCCESS
    with ``route`` (nodes, edges, cost) and ``path`` (the nodes joined by straight segments
    every ``route_server.path_density`` m, 5 cm by default). FAILURE with ``error_code_id``
    NO_VALID_GRAPH (no graph), INDETERMINANT_NODES_ON_GRAPH (an unknown id) or NO_VALID_ROUTE,
    and empty outputs. One tick: the search is synchronous. (Nav2 ``ComputeRoute``.)"""

    INPUT_PORTS = {
        "start_id": PortInformation(int, False, "route start node id"),
        "goal_id": PortInformation(int, False, "route goal node id"),
        "start": PortInformation(Pose2D, False, "start pose (used when use_start)"),
        "goal": PortInformation(Pose2D, False, "goal pose (used when use_poses)"),
        "use_start": PortInformation(bool, False, "route from 'start', not the robot pose",
                                     False),
        "use_poses": PortInformation(bool, False, "use the poses, not the node ids", False),
    }
    OUTPUT_PORTS = {
        "route": PortInformation(Route, False, "the route: nodes, edges, cost"),
        "path": PortInformation(Path, True, "the route as a dense path"),
        "planning_time": PortInformation(float, False, "search time, s (synchronous: 0)"),
        "error_code_id": PortInformation(int, False, "a RouteErrorCode; 0 on success"),
        "error_msg": PortInformation(str, False, "why routing failed"),
    }

    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot", optional=True)
        self.graph = kwargs.get("route_graph")
        self.density = float(kwargs.get("route_path_density") or PATH_DENSITY)

    def update(self) -> Status:
        if self.graph is None:
            return self._fail(RouteErrorCode.NO_VALID_GRAPH,
                              "no route graph (set route_server.graph_filepath)")
        try:
            if self.get_input("use_poses"):
                goal = self.read("goal")
                start = self.read("start") if self.get_input("use_start") else None
                if start is None and self.robot is not None:
                    start = self.robot.pose()
                if goal is None or start is None:
                    return self._fail(RouteErrorCode.TF_ERROR, "no start or goal pose")
                route = route_between_poses(self.graph, start, goal)
            else:
                a, b = self.read("start_id"), self.read("goal_id")
                if a is None or b is None or a not in self.graph.nodes \
                        or b not in self.graph.nodes:
                    return self._fail(RouteErrorCode.INDETERMINANT_NODES_ON_GRAPH,
                                      f"start {a} or goal {b} is not a node of the graph")
                route = find_route(self.graph, a, b)
        except RouteError as e:
            return self._fail(RouteErrorCode.NO_VALID_ROUTE, str(e))
        self.write("route", route)
        self.write("path", densify(route, self.density))
        self.write("planning_time", 0.0)
        self.write("error_code_id", int(RouteErrorCode.NONE))
        self.write("error_msg", "")
        self.say("route of {} nodes, cost {:.2f}", len(route.nodes), route.cost)
        return SUCCESS

    def _fail(self, code: RouteErrorCode, msg: str) -> Status:
        self.write("path", Path.from_poses([]))
        self.write("error_code_id", int(code))
        self.write("error_msg", msg)
        self.say(msg)
        return FAILURE
