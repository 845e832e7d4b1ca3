"""navcore.route: Nav2 GeoJSON route graphs, the shortest route (against a plain reference)
and the dense path; the office map's shipped graph stays in free space; navcore.path_ops."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest

from navcore import path_ops
from navcore.maps import load_map
from navcore.route import RouteError, densify, find_route, load_route_graph
from navcore.route.graph import parse_route_graph
from navcore.types import Path as NavPath, Pose2D

DATA = Path(__file__).resolve().parent.parent / "executive" / "data" / "maps"


def graph_doc(nodes, edges):
    feats = [{"type": "Feature", "properties": {"id": i, "frame": "map"},
              "geometry": {"type": "Point", "coordinates": [x, y]}} for i, (x, y) in nodes.items()]
    feats += [{"type": "Feature", "properties": {"id": 100 + k, "startid": a, "endid": b,
                                                 **({"cost": c} if c is not None else {})},
               "geometry": {"type": "MultiLineString", "coordinates": [[nodes[a], nodes[b]]]}}
              for k, (a, b, c) in enumerate(edges)]
    return {"type": "FeatureCollection", "features": feats}


def reference_cost(graph, a, b):
    """Bellman-Ford: the obviously correct cheapest cost."""
    best = {n: math.inf for n in graph.nodes}
    best[a] = 0.0
    for _ in range(len(graph.nodes)):
        for e in graph.edges.values():
            if best[e.start] + e.cost < best[e.end]:
                best[e.end] = best[e.start] + e.cost
    return best[b]


def test_shortest_route_matches_reference_on_random_graphs():
    rng = np.random.default_rng(7)
    for trial in range(20):
        n = 12
        nodes = {i: [float(x), float(y)] for i, (x, y) in enumerate(rng.uniform(0, 10, (n, 2)))}
        edges = [(int(a), int(b), None if rng.random() < 0.5 else float(rng.uniform(0.5, 20)))
                 for a, b in rng.integers(0, n, (30, 2)) if a != b]
        g = parse_route_graph(graph_doc(nodes, edges), f"random{trial}")
        for a, b in itertools.product(range(n), repeat=2):
            ref = reference_cost(g, a, b)
            if math.isinf(ref):
                with pytest.raises(RouteError, match=f"no route from node {a} to node {b}"):
                    find_route(g, a, b)
                continue
            r = find_route(g, a, b)
            assert r.cost == pytest.approx(ref, abs=1e-9)
            assert sum(e.cost for e in r.edges) == pytest.approx(r.cost, abs=1e-9)
            assert [x.id for x in r.nodes][0] == a and r.nodes[-1].id == b


def test_edges_are_directed_and_costs_override_length():
    nodes = {0: [0.0, 0.0], 1: [1.0, 0.0], 2: [0.0, 1.0]}
    g = parse_route_graph(graph_doc(nodes, [(0, 1, 10.0), (0, 2, None), (2, 1, None)]))
    r = find_route(g, 0, 1)
    assert [n.id for n in r.nodes] == [0, 2, 1] and r.cost == pytest.approx(1 + math.sqrt(2))
    with pytest.raises(RouteError):
        find_route(g, 1, 0)


@pytest.mark.parametrize("mutate, message", [
    (lambda d: d.update(type="Feature"), "not a GeoJSON FeatureCollection"),
    (lambda d: d["features"].append(d["features"][0]), "node id 0 appears twice"),
    (lambda d: d["features"][-1]["properties"].update(endid=7), "refers to node 7"),
    (lambda d: d["features"][0]["properties"].update(id="a"), "properties.id must be an integer"),
    (lambda d: d["features"][0]["geometry"].update(type="Polygon"), "neither a node"),
    (lambda d: d["features"][-1]["properties"].update(cost=-1), "negative cost"),
])
def test_bad_graphs_say_which_feature(mutate, message):
    doc = graph_doc({0: [0.0, 0.0], 1: [1.0, 0.0]}, [(0, 1, None)])
    mutate(doc)
    with pytest.raises(RouteError, match=message):
        parse_route_graph(doc, "g.geojson")


def test_densify_spacing_and_headings():
    g = parse_route_graph(graph_doc({0: [0.0, 0.0], 1: [1.0, 0.0], 2: [1.0, 2.0]},
                                    [(0, 1, None), (1, 2, None)]))
    p = densify(find_route(g, 0, 2), 0.1)
    steps = np.hypot(np.diff(p.poses[:, 0]), np.diff(p.poses[:, 1]))
    assert steps.max() <= 0.1 + 1e-12 and p.length() == pytest.approx(3.0)
    assert p.poses[0, 2] == 0.0 and p.poses[-1, 2] == pytest.approx(math.pi / 2)
    assert tuple(p.poses[-1, :2]) == (1.0, 2.0)


def test_office_graph_is_connected_and_in_free_space():
    """Every edge of the shipped graph keeps 0.2 m from occupied and unknown cells of the
    office map, and every room centre reaches every other."""
    grid = load_map(DATA / "office.yaml")
    g = load_route_graph(DATA / "office_route_graph.geojson")
    data, res = grid.data, grid.resolution
    r = int(round(0.2 / res))
    for e in g.edges.values():
        a, b = g.nodes[e.start], g.nodes[e.end]
        for t in np.linspace(0.0, 1.0, int(math.hypot(b.x - a.x, b.y - a.y) / 0.05) + 2):
            col = int(round((a.x + t * (b.x - a.x)) / res))
            row = int(round((a.y + t * (b.y - a.y)) / res))
            block = data[row - r:row + r + 1, col - r:col + r + 1]
            assert (block >= 0).all() and (block <= 50).all(), (e.id, a, b)
    for a, b in itertools.product(range(16), repeat=2):
        find_route(g, a, b)


def test_truncate_and_window_and_smooth():
    p = NavPath.from_poses([Pose2D(0.1 * i, 0.0, 0.0) for i in range(21)])   # 2 m
    t = path_ops.truncate_end(p, 0.55)
    assert t.poses[-1, 0] == pytest.approx(1.4) and len(t) == 15
    w = path_ops.window_around(p, 10, forward=0.35, backward=0.25)
    assert list(np.round(w.poses[:, 0], 6)) == [0.8, 0.9, 1.0, 1.1, 1.2, 1.3]
    zig = NavPath.from_poses([Pose2D(0.5 * i, 0.3 * (i % 2), 0.0) for i in range(9)])
    s, done = path_ops.smooth(zig)
    assert done and tuple(s.poses[0, :2]) == tuple(zig.poses[0, :2])
    assert tuple(s.poses[-1, :2]) == tuple(zig.poses[-1, :2])
    wiggle = lambda q: float(np.sum(np.abs(np.diff(q.poses[:, 1], 2))))  # noqa: E731
    assert wiggle(s) < 0.5 * wiggle(zig)
    fb = path_ops.tracking_feedback(p, Pose2D(0.52, 0.1, 0.2), speed=0.3)
    assert fb.position_tracking_error == pytest.approx(0.1)       # left of the path
    assert fb.heading_tracking_error == pytest.approx(-0.2)       # turned left of it
    assert fb.current_path_index == 5 and fb.remaining_path_length == pytest.approx(1.5)
