"""Kilted's and main's navigate_w_routing_global_planning_and_control_w_recovery.xml,
unchanged, on the bundled office map with its route graph: ComputeRoute finds the route
between rooms, ExtractRouteNodesAsGoals / GetNextFewGoals / AppendGoalPoseToGoals turn it into
goals for ComputePathThroughPoses, and the robot reaches the goal through the route's doors."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from tests.conftest import data_root

ROOT = Path(__file__).resolve().parent.parent
TREE = "navigate_w_routing_global_planning_and_control_w_recovery.xml"


@pytest.mark.parametrize("distro", ["kilted", "main"])
def test_routing_tree_drives_through_the_route(distro):
    data = data_root()
    if data is None:
        pytest.skip("../shared/data not found (set NAVBT_DATA): Nav2's trees are not here")
    from executive.api import open_mission
    from executive.config import DEFAULT_CONFIG, config_from_mapping, read_config_doc
    from executive.tree_loader import load_tree_file
    from navcore.route import load_route_graph
    from navcore.types import Pose2D
    doc = dict(read_config_doc(DEFAULT_CONFIG))
    doc["route_server"] = {"graph_filepath": "office_route_graph.geojson"}
    config = config_from_mapping(doc, str(DEFAULT_CONFIG))
    tree = load_tree_file(data / "nav2_trees" / distro / TREE, namespace=f"/route_{distro}")
    nav = open_mission(tree, config, ROOT / "executive/data/maps/office.yaml",
                       Pose2D(2.0, 2.2, 0.0))
    visited: list[tuple[float, float]] = []
    routes: list = []

    def watch(*_: object) -> None:
        pose = nav.executive.robot.pose()
        visited.append((pose.x, pose.y))
        routes.append(tree.get("route"))

    nav.follow_waypoints([Pose2D(15.5, 9.5, 0.0)])
    result = nav.run(120.0, on_tick=watch)
    nav.close()
    assert result.outcome == "succeeded" and result.collisions == 0
    route = next((r for r in routes if r is not None), None)
    graph = load_route_graph(ROOT / "executive/data/maps/office_route_graph.geojson")
    assert route is not None and len(route.nodes) >= 4
    assert all(graph.nodes[n.id] == n for n in route.nodes)
    doors = [n for n in route.nodes if n.x % 6.0 == 0.0 or n.y % 6.0 == 0.0]
    assert len(doors) >= 2                       # two rooms crossed on the way
    for door in doors:                           # and the robot went through those doors
        assert min(math.hypot(x - door.x, y - door.y) for x, y in visited) < 0.5, door
