"""Shortest routes on a RouteGraph (Dijkstra, as Nav2's route planner) and the dense path
along a route (Nav2's path converter interpolates each edge at ``path_density``)."""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass

import numpy as np

from navcore.route.graph import RouteEdge, RouteError, RouteGraph, RouteNode
from navcore.types import Path, Pose2D


@dataclass(frozen=True)
class Route:
    """An ordered list of nodes and the edges joining them; ``cost`` is the sum of edge costs."""

    nodes: tuple[RouteNode, ...]
    edges: tuple[RouteEdge, ...]
    cost: float


def find_route(graph: RouteGraph, start_id: int, goal_id: int) -> Route:
    """The cheapest route from ``start_id`` to ``goal_id``; RouteError when there is none
    (Nav2's NO_VALID_ROUTE). Ties between equal costs go to lower edge ids (deterministic)."""
    for nid in (start_id, goal_id):
        if nid not in graph.nodes:
            raise RouteError(f"{graph.source}: no node {nid} in the route graph")
    best = {start_id: 0.0}
    came: dict[int, RouteEdge] = {}
    heap = [(0.0, start_id)]
    done: set[int] = set()
    while heap:
        cost, nid = heapq.heappop(heap)
        if nid in done:
            continue
        done.add(nid)
        if nid == goal_id:
            break
        for edge in graph.outgoing[nid]:
            c = cost + edge.cost
            if c < best.get(edge.end, math.inf):
                best[edge.end] = c
                came[edge.end] = edge
                heapq.heappush(heap, (c, edge.end))
    if goal_id not in done:
        raise RouteError(f"no route from node {start_id} to node {goal_id} on the route graph")
    edges: list[RouteEdge] = []
    nid = goal_id
    while nid != start_id:
        edges.append(came[nid])
        nid = came[nid].start
    edges.reverse()
    nodes = [graph.nodes[start_id]] + [graph.nodes[e.end] for e in edges]
    return Route(tuple(nodes), tuple(edges), best[goal_id])


def route_between_poses(graph: RouteGraph, start: Pose2D, goal: Pose2D) -> Route:
    """The route between the nodes nearest ``start`` and ``goal`` (Nav2's ``use_poses``)."""
    return find_route(graph, graph.nearest_node(start.x, start.y),
                      graph.nearest_node(goal.x, goal.y))


def densify(route: Route, density: float = 0.05, frame_id: str = "map") -> Path:
    """The route's nodes joined by straight segments sampled every ``density`` metres; each
    pose faces along its segment, the last one along the last edge (a one-node route gives
    that node with heading 0)."""
    if density <= 0.0:
        raise ValueError(f"density must be > 0 m, got {density}")
    pts = np.array([[n.x, n.y] for n in route.nodes], dtype=np.float64).reshape(-1, 2)
    if len(pts) == 1:
        return Path(np.array([[pts[0, 0], pts[0, 1], 0.0]]), frame_id)
    out = []
    heading = 0.0
    for (x0, y0), (x1, y1) in zip(pts[:-1], pts[1:]):
        length = math.hypot(x1 - x0, y1 - y0)
        if length == 0.0:
            continue
        heading = math.atan2(y1 - y0, x1 - x0)
        n = max(1, int(math.ceil(length / density)))
        for k in range(n):
            f = k / n
            out.append((x0 + f * (x1 - x0), y0 + f * (y1 - y0), heading))
    out.append((pts[-1, 0], pts[-1, 1], heading))
    return Path(np.array(out, dtype=np.float64), frame_id)
