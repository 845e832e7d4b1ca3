"""A route graph as Nav2's route server reads it (nav2_route's GeoJSON graph files).

The file is a GeoJSON ``FeatureCollection``. A ``Point`` feature is a node: ``properties.id``
(an integer) and ``properties.frame`` (``map``), coordinates ``[x, y]`` in metres. A
``MultiLineString`` (or ``LineString``) feature is a directed edge: ``properties.id``,
``startid`` and ``endid`` (node ids) and optionally ``cost`` (else its length, m). Other
properties (``metadata``, ``operations``, ``overridable``) are kept but not interpreted. A
two-way corridor is two edges, as in Nav2's own graphs.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from navcore.errors import NavcoreError
from navcore.params import Param

# nav2_route's route_server parameters that navbt reads (robot config namespace route_server).
ROUTE_SERVER_PARAMS = (
    Param("graph_filepath", "", str, "Nav2 GeoJSON route graph file; relative to the robot "
          "config's folder, or a bundled graph name such as office_route_graph.geojson"),
    Param("path_density", 0.05, float, "distance between poses of a route's path, m",
          min=1e-3),
)


class RouteError(NavcoreError, ValueError):
    """A route graph file that cannot be used; the message names the file and the feature."""


@dataclass(frozen=True)
class RouteNode:
    id: int
    x: float
    y: float
    frame: str = "map"


@dataclass(frozen=True)
class RouteEdge:
    id: int
    start: int
    end: int
    cost: float  # the file's ``cost``, else the straight length, m


@dataclass
class RouteGraph:
    """Nodes by id and outgoing edges by start node; ``source`` is the file it came from."""

    nodes: dict[int, RouteNode]
    edges: dict[int, RouteEdge]
    source: str = ""
    outgoing: dict[int, list[RouteEdge]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.outgoing = {n: [] for n in self.nodes}
        for e in sorted(self.edges.values(), key=lambda e: e.id):
            self.outgoing[e.start].append(e)
        ids = sorted(self.nodes)
        self._ids = np.array(ids, dtype=np.int64)
        self._xy = np.array([[self.nodes[i].x, self.nodes[i].y] for i in ids],
                            dtype=np.float64).reshape(-1, 2)

    def nearest_node(self, x: float, y: float) -> int:
        """Id of the node closest to (x, y) (Nav2's default start/goal node finder, less its
        costmap check); ties go to the lower id."""
        if len(self._ids) == 0:
            raise RouteError(f"{self.source}: the route graph has no nodes")
        d2 = (self._xy[:, 0] - x) ** 2 + (self._xy[:, 1] - y) ** 2
        return int(self._ids[int(np.argmin(d2))])


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise RouteError(f"{where}: expected a finite number, got {value!r}")
    return float(value)


def _int_id(props: dict[str, Any], key: str, where: str) -> int:
    value = props.get(key)
    if isinstance(value, bool) or not isinstance(value, int):
        raise RouteError(f"{where}: properties.{key} must be an integer, got {value!r}")
    return value


def parse_route_graph(data: Any, source: str = "<graph>") -> RouteGraph:
    """A RouteGraph from parsed GeoJSON; every problem names the feature (index and id)."""
    if not isinstance(data, dict) or data.get("type") != "FeatureCollection" \
            or not isinstance(data.get("features"), list):
        raise RouteError(f"{source}: not a GeoJSON FeatureCollection with 'features'")
    nodes: dict[int, RouteNode] = {}
    raw_edges: list[tuple[int, int, int, Any, list, str]] = []
    for i, feature in enumerate(data["features"]):
        where = f"{source}: feature {i}"
        if not isinstance(feature, dict) or not isinstance(feature.get("geometry"), dict):
            raise RouteError(f"{where}: a feature needs a 'geometry'")
        props = feature.get("properties") or {}
        geom = feature["geometry"]
        kind, coords = geom.get("type"), geom.get("coordinates")
        if kind == "Point":
            nid = _int_id(props, "id", where)
            if nid in nodes:
                raise RouteError(f"{where}: node id {nid} appears twice")
            if not isinstance(coords, list) or len(coords) < 2:
                raise RouteError(f"{where}: a Point needs coordinates [x, y]")
            nodes[nid] = RouteNode(nid, _number(coords[0], where), _number(coords[1], where),
                                   str(props.get("frame", "map")))
        elif kind in ("MultiLineString", "LineString"):
            eid = _int_id(props, "id", where)
            raw_edges.append((eid, _int_id(props, "startid", where),
                              _int_id(props, "endid", where), props.get("cost"), coords, where))
        else:
            raise RouteError(f"{where}: geometry type {kind!r} is neither a node (Point) nor an "
                             f"edge (MultiLineString)")
    edges: dict[int, RouteEdge] = {}
    for eid, start, end, cost, _coords, where in raw_edges:
        if eid in edges:
            raise RouteError(f"{where}: edge id {eid} appears twice")
        for nid in (start, end):
            if nid not in nodes:
                raise RouteError(f"{where}: edge {eid} refers to node {nid}, which the graph "
                                 f"does not have")
        a, b = nodes[start], nodes[end]
        length = math.hypot(b.x - a.x, b.y - a.y)
        value = length if cost is None else _number(cost, where)
        if value < 0.0:
            raise RouteError(f"{where}: edge {eid} has a negative cost {value}")
        edges[eid] = RouteEdge(eid, start, end, value)
    return RouteGraph(nodes, edges, source)


def load_route_graph(path: str | os.PathLike) -> RouteGraph:
    """Read a Nav2 GeoJSON route graph file."""
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except OSError as e:
        raise RouteError(f"{path}: cannot read route graph ({e.strerror or e})") from None
    except json.JSONDecodeError as e:
        raise RouteError(f"{path}:{e.lineno}: not valid JSON: {e.msg}") from None
    return parse_route_graph(data, str(path))
