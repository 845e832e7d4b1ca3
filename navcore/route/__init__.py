"""Route graphs in Nav2's GeoJSON format: loading, shortest routes, dense paths along them."""

from navcore.route.graph import RouteEdge, RouteError, RouteGraph, RouteNode, load_route_graph
from navcore.route.search import Route, densify, find_route, route_between_poses

__all__ = ["RouteEdge", "RouteError", "RouteGraph", "RouteNode", "load_route_graph", "Route",
           "densify", "find_route", "route_between_poses"]
