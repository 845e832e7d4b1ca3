"""Layered costmap: static/obstacle/voxel/inflation layers, rolling window, ROS params, clearing."""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest
import yaml

from navcore.clock import SimClock
from navcore.costmap.cost_values import (FREE_SPACE, INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE,
                                         NO_INFORMATION)
from navcore.costmap.inflation import compute_cost
from navcore.costmap.layered import LayeredCostmap
from navcore.costmap.obstacle_layer import ObstacleLayer, scan_to_points
from navcore.costmap.static_layer import interpret_map
from navcore.costmap.voxel_layer import VoxelLayer
from navcore.maps import OccupancyGrid, load_map
from navcore.params import ParameterError
from navcore.synthetic_maps import ascii_map as _ascii_map
from navcore.types import LaserScan, Pose2D
from tests.conftest import REAL_MAPS


def ascii_map(text: str, resolution: float) -> OccupancyGrid:
    return _ascii_map(textwrap.dedent(text).strip("\n"), resolution)


def _scan(ranges, n=360, range_max=10.0):
    """A full-circle scan; beam i points at -pi + i * 2 pi / n (beam n/2 along +x)."""
    inc = 2 * math.pi / n
    r = np.full(n, ranges, np.float32) if np.isscalar(ranges) else np.asarray(ranges, np.float32)
    return LaserScan(0.0, -math.pi, -math.pi + inc * (n - 1), inc, 0.0, 0.1, 0.05, range_max, r)


def _local(clock=None, **over):
    p = {"rolling_window": True, "width": 6.0, "height": 6.0, "resolution": 0.05,
         "robot_radius": 0.2, "footprint_padding": 0.0,
         "plugins": ["obstacle_layer", "inflation_layer"],
         "obstacle_layer": {"observation_sources": "scan",
                            "scan": {"data_type": "LaserScan", "marking": True, "clearing": True}},
         "inflation_layer": {"inflation_radius": 0.55}}
    p.update(over)
    for ns in ("obstacle_layer", "inflation_layer"):
        if ns not in p["plugins"]:
            p.pop(ns, None)
    return LayeredCostmap.from_params(p, name="local_costmap", clock=clock or SimClock())


def _cell_cost(cm, wx, wy):
    mx, my = cm.costmap.world_to_map(wx, wy)
    return int(cm.costmap.costs[my, mx])


def test_a_scan_marks_and_a_later_scan_that_sees_through_clears():
    cm = _local()
    robot = Pose2D(0.0, 0.0, 0.0)
    ranges = np.full(360, 2.0, np.float32)       # a round room of radius 2 m
    ranges[180] = 1.0                            # beam 180 points along +x: an obstacle at 1 m
    cm.add_scan(_scan(ranges), robot)
    cm.update_map(robot)
    assert _cell_cost(cm, 1.0, 0.0) == LETHAL_OBSTACLE
    # 0.4 m in front of it: the inflated cost of the distance between the two cells
    (hx, hy), (qx, qy) = cm.costmap.world_to_map(1.0, 0.0), cm.costmap.world_to_map(0.6, 0.0)
    d = math.hypot(hx - qx, hy - qy)
    assert _cell_cost(cm, 0.6, 0.0) == compute_cost(d, 0.05, cm.inscribed_radius, 10.0)
    assert 0 < _cell_cost(cm, 0.6, 0.0) < INSCRIBED_INFLATED_OBSTACLE
    # the obstacle went away: the next scan sees the wall at 2 m along +x, through the old hit
    ranges[180] = 2.0
    cm.add_scan(_scan(ranges), robot)
    cm.update_map(robot)
    assert _cell_cost(cm, 1.0, 0.0) == FREE_SPACE
    assert _cell_cost(cm, 0.6, 0.0) == FREE_SPACE
    assert _cell_cost(cm, 2.0, 0.0) == LETHAL_OBSTACLE


def test_marking_respects_obstacle_range_and_clearing_raytrace_range():
    cm = _local(obstacle_layer={"observation_sources": "scan", "scan": {
        "data_type": "LaserScan", "marking": True, "clearing": True, "obstacle_range": 1.5,
        "raytrace_range": 2.0}})
    robot = Pose2D(0.0, 0.0, 0.0)
    ranges = np.full(360, 2.8, np.float32)
    ranges[180] = 1.425
    ranges[0] = 1.625                    # along -x: beyond obstacle_range, not marked
    cm.add_scan(_scan(ranges), robot)
    cm.update_map(robot)
    assert _cell_cost(cm, 1.425, 0.0) == LETHAL_OBSTACLE
    assert _cell_cost(cm, -1.625, 0.0) == FREE_SPACE
    assert np.count_nonzero(cm.costmap.costs == LETHAL_OBSTACLE) == 1
    # a point put into the obstacle layer by hand 2.5 m away along +y is beyond raytrace_range
    layer = cm.layer("obstacle_layer")
    mx, my = layer.grid.world_to_map(0.025, 2.525)
    layer.grid.costs[my, mx] = LETHAL_OBSTACLE
    cm.add_scan(_scan(np.full(360, 2.8, np.float32)), robot)
    cm.update_map(robot)
    assert _cell_cost(cm, 0.025, 2.525) == LETHAL_OBSTACLE   # not reached by the 2 m rays
    assert _cell_cost(cm, 1.425, 0.0) == FREE_SPACE          # reached: cleared


def test_rolling_window_keeps_world_aligned_content_as_it_moves():
    clock = SimClock()
    cm = _local(clock, plugins=["obstacle_layer"])
    a, b = (1.025, 1.025), (-0.975, 0.525)           # cell centres of the first window
    cm.add_points(np.array([[*a, 0.5], [*b, 0.5]]), (0.0, 0.0, 0.5))
    cm.update_map(Pose2D(0.0, 0.0, 0.0))
    assert _cell_cost(cm, *a) == _cell_cost(cm, *b) == LETHAL_OBSTACLE
    assert np.count_nonzero(cm.costmap.costs) == 2
    o0 = (cm.costmap.origin_x, cm.costmap.origin_y)
    # the sensor stops seeing anything (no new observation) and the robot drives on
    for buf in cm.layer("obstacle_layer").buffers.values():
        buf.clear()
    for step in range(1, 26):
        pose = Pose2D(0.13 * step, 0.07 * step, 0.0)
        cm.update_map(pose)
        m = cm.costmap
        # the window stays centred on the robot, its corner on the original cell lattice
        assert abs(m.origin_x + 3.0 - pose.x) <= 0.05 + 1e-9
        assert abs(m.origin_y + 3.0 - pose.y) <= 0.05 + 1e-9
        assert (m.origin_x - o0[0]) / 0.05 == pytest.approx(round((m.origin_x - o0[0]) / 0.05))
        # the marked cells stay where they are in the world while they are in the window
        inside = [p for p in (a, b) if m.world_to_map(*p) is not None]
        assert all(_cell_cost(cm, *p) == LETHAL_OBSTACLE for p in inside)
        assert np.count_nonzero(m.costs) == len(inside)
    assert cm.costmap.world_to_map(*b) is None            # b left the window, a did not
    # back again: what left the window is forgotten (new cells get the default value)
    cm.update_map(Pose2D(0.0, 0.0, 0.0))
    assert _cell_cost(cm, *a) == LETHAL_OBSTACLE
    assert _cell_cost(cm, *b) == FREE_SPACE


def test_rolling_window_over_a_static_map_samples_the_map():
    grid = ascii_map("""
        ##########
        #........#
        #...##...#
        #........#
        ##########
    """, resolution=0.5)
    cm = LayeredCostmap.from_params({"rolling_window": True, "width": 2.0, "height": 2.0,
                                     "resolution": 0.1, "plugins": ["static_layer"]},
                                    static_map=grid, name="local_costmap")
    for pose in (Pose2D(2.0, 1.25, 0.0), Pose2D(3.1, 1.4, 0.0)):
        cm.update_map(pose)
        for my in range(cm.costmap.size_y):
            for mx in range(cm.costmap.size_x):
                wx, wy = cm.costmap.map_to_world(mx, my)
                cell = grid.world_to_map(wx, wy)
                expected = LETHAL_OBSTACLE if grid.data[cell[1], cell[0]] == 100 else FREE_SPACE
                assert cm.costmap.costs[my, mx] == expected


def test_rolling_static_sampling_equals_the_per_cell_centre_lookup_on_random_windows():
    # the kernel against the plain numpy statement of "the map cell under each cell centre",
    # for windows partly or wholly off the map, at finer and coarser resolutions than the map
    from navcore.costmap.static_layer import sample_map
    rng = np.random.default_rng(7)
    map_costs = rng.integers(0, 256, size=(37, 53)).astype(np.uint8)
    map_ox, map_oy, map_res = -1.3, 0.7, 0.1
    for _ in range(200):
        res = float(rng.choice([0.03, 0.05, 0.1, 0.25]))
        h, w = (int(v) for v in rng.integers(1, 40, size=2))
        # anywhere from just left of / below the map to just past its far edges
        ox = float(rng.uniform(map_ox - w * res, map_ox + 53 * map_res))
        oy = float(rng.uniform(map_oy - h * res, map_oy + 37 * map_res))
        x0, y0 = int(rng.integers(0, w)), int(rng.integers(0, h))
        xn, yn = int(rng.integers(x0, w + 1)), int(rng.integers(y0, h + 1))
        start = rng.integers(0, 256, size=(h, w)).astype(np.uint8)
        got = start.copy()
        sample_map(got, x0, y0, xn, yn, ox, oy, res, map_costs, map_ox, map_oy, map_res)
        want = start.copy()
        mx = np.floor((ox + (np.arange(x0, xn) + 0.5) * res - map_ox) / map_res).astype(np.int64)
        my = np.floor((oy + (np.arange(y0, yn) + 0.5) * res - map_oy) / map_res).astype(np.int64)
        xs = np.nonzero((mx >= 0) & (mx < map_costs.shape[1]))[0]
        ys = np.nonzero((my >= 0) & (my < map_costs.shape[0]))[0]
        want[np.ix_(y0 + ys, x0 + xs)] = map_costs[np.ix_(my[ys], mx[xs])]
        np.testing.assert_array_equal(got, want)


def test_footprint_clearing_frees_the_robot_cells():
    cm = _local(plugins=["obstacle_layer"])
    cm.add_points(np.array([[0.05, 0.0, 0.3], [1.0, 0.0, 0.3]]), (0.0, 0.0, 0.3))
    cm.update_map(Pose2D(0.0, 0.0, 0.0))
    assert _cell_cost(cm, 0.05, 0.0) == FREE_SPACE         # under the 0.2 m robot
    assert _cell_cost(cm, 1.0, 0.0) == LETHAL_OBSTACLE
    off = _local(plugins=["obstacle_layer"],
                 obstacle_layer={"footprint_clearing_enabled": False})
    off.add_points(np.array([[0.05, 0.0, 0.3]]), (0.0, 0.0, 0.3))
    off.update_map(Pose2D(0.0, 0.0, 0.0))
    assert _cell_cost(off, 0.05, 0.0) == LETHAL_OBSTACLE


def test_points_above_max_obstacle_height_are_not_marked():
    cm = _local(plugins=["obstacle_layer"], obstacle_layer={"max_obstacle_height": 1.0})
    cm.add_points(np.array([[1.0, 0.0, 0.5], [0.0, 1.0, 1.5]]), (0.0, 0.0, 0.5))
    cm.update_map(Pose2D(0.0, 0.0, 0.0))
    assert _cell_cost(cm, 1.0, 0.0) == LETHAL_OBSTACLE
    assert _cell_cost(cm, 0.0, 1.0) == FREE_SPACE


def test_observation_persistence_and_expected_update_rate_follow_the_clock():
    clock = SimClock()
    cm = _local(clock, plugins=["obstacle_layer"], obstacle_layer={
        "observation_sources": "scan",
        "scan": {"data_type": "LaserScan", "marking": True, "clearing": False,
                 "observation_persistence": 1.0, "expected_update_rate": 0.5}})
    layer = cm.layer("obstacle_layer")
    assert layer.is_current()                              # the first deadline is 0.5 s away
    clock.advance(0.6)
    assert not layer.is_current()                          # nothing received in time
    ranges = np.full(360, np.inf, np.float32)
    ranges[180] = 1.0
    cm.add_scan(_scan(ranges), Pose2D())
    clock.advance(0.6)
    ranges[180], ranges[90] = np.inf, 1.0                  # beam 90 points along -y
    cm.add_scan(_scan(ranges), Pose2D())
    assert len(layer.buffers["scan"].observations()) == 2  # both within 1 s
    clock.advance(0.6)
    # no new reading: ages count from the newest one, so both stay, but the source is late
    assert len(layer.buffers["scan"].observations()) == 2
    assert not layer.is_current()
    cm.update_map(Pose2D())
    assert not cm.is_current()
    assert _cell_cost(cm, 0.0, -1.0) == _cell_cost(cm, 1.0, 0.0) == LETHAL_OBSTACLE
    cm.add_scan(_scan(ranges), Pose2D())                 # now the first is 1.2 s older
    assert len(layer.buffers["scan"].observations()) == 2
    cm.update_map(Pose2D())
    assert cm.is_current()


def test_inf_is_valid_clears_without_marking():
    cm = _local(plugins=["obstacle_layer"], obstacle_layer={
        "observation_sources": "scan",
        "scan": {"data_type": "LaserScan", "marking": True, "clearing": True,
                 "inf_is_valid": True}})
    layer = cm.layer("obstacle_layer")
    mx, my = layer.grid.world_to_map(1.5, 0.0)
    layer.grid.costs[my, mx] = LETHAL_OBSTACLE
    cm.add_scan(_scan(np.full(360, np.inf, np.float32)), Pose2D())
    cm.update_map(Pose2D())
    assert _cell_cost(cm, 1.5, 0.0) == FREE_SPACE
    assert np.count_nonzero(cm.costmap.costs == LETHAL_OBSTACLE) == 0


def test_voxel_layer_marks_in_3d_and_clears_along_3d_rays():
    cm = _local(plugins=[{"name": "obstacles", "type": "costmap_2d::VoxelLayer"}],
                obstacles={"observation_sources": "cloud", "z_voxels": 10, "z_resolution": 0.2,
                           "origin_z": 0.0, "mark_threshold": 1,
                           "cloud": {"data_type": "PointCloud2", "marking": True,
                                     "clearing": True}})
    layer = cm.layer("obstacles")
    assert isinstance(layer, VoxelLayer) and layer.effective_unknown_threshold == 21
    sensor = (0.0, 0.0, 0.5)
    # one marked voxel is not enough with mark_threshold 1; two in the same column are
    cm.add_points(np.array([[1.0, 0.0, 0.3], [0.0, 1.0, 0.3], [0.0, 1.0, 0.7]]), sensor)
    cm.update_map(Pose2D())
    assert _cell_cost(cm, 1.0, 0.0) == FREE_SPACE
    assert _cell_cost(cm, 0.0, 1.0) == LETHAL_OBSTACLE
    # a ray passing above the column's lower voxel but through the upper one clears only that
    # voxel: one marked voxel stays, below the threshold, so the cell becomes free
    cm.add_points(np.array([[0.0, 2.0, 0.9]]), sensor)
    cm.update_map(Pose2D())
    assert _cell_cost(cm, 0.0, 1.0) == FREE_SPACE
    col = layer.voxels[layer.grid.world_to_map(0.0, 1.0)[::-1]]
    assert (int(col) >> 16) & 0b110 == 0b010            # voxel 1 (0.2-0.4 m) still marked


def test_clear_outside_and_inside_follow_clear_costmap_recovery():
    cm = _local(plugins=["obstacle_layer", "inflation_layer"])
    pts = np.array([[0.525, 0.025, 0.3], [1.525, 1.525, 0.3], [-1.975, 0.025, 0.3]])
    cm.add_points(pts, (0.0, 0.0, 0.3))
    cm.update_map(Pose2D())
    assert all(_cell_cost(cm, x, y) == LETHAL_OBSTACLE for x, y, _ in pts)
    layer = cm.layer("obstacle_layer")
    for b in layer.buffers.values():
        b.clear()
    cm.clear_outside(0.0, 0.0, 2.0)                  # keep the 2 m square around the robot
    assert _cell_cost(cm, 0.525, 0.025) == LETHAL_OBSTACLE
    assert _cell_cost(cm, 1.525, 1.525) == FREE_SPACE   # unknown in the layer: master default
    assert _cell_cost(cm, -1.975, 0.025) == FREE_SPACE
    assert layer.grid.costs[layer.grid.world_to_map(1.525, 1.525)[::-1]] == NO_INFORMATION
    cm.clear_inside(0.0, 0.0, 2.0)
    assert np.count_nonzero(cm.costmap.costs) == 0


def test_reset_layers_keeps_the_static_map_and_forgets_obstacles():
    grid = ascii_map("""
        ########
        #......#
        #......#
        ########
    """, resolution=0.25)
    cm = LayeredCostmap.from_params({"plugins": ["static_layer", "obstacle_layer"],
                                     "robot_radius": 0.1}, static_map=grid)
    assert (cm.costmap.size_x, cm.costmap.size_y) == (8, 4)
    cm.add_points(np.array([[1.1, 0.6, 0.2]]), (0.6, 0.6, 0.2))
    cm.update_map(Pose2D(0.6, 0.6, 0.0))
    assert _cell_cost(cm, 1.1, 0.6) == LETHAL_OBSTACLE
    walls = np.count_nonzero(cm.costmap.costs == LETHAL_OBSTACLE)
    cm.layer("obstacle_layer").buffers["default"].clear()
    cm.reset_layers()
    assert _cell_cost(cm, 1.1, 0.6) == FREE_SPACE
    assert np.count_nonzero(cm.costmap.costs == LETHAL_OBSTACLE) == walls - 1


def test_static_layer_interprets_values_as_costmap_2d():
    data = np.array([[-1, 0, 50, 99, 100]])
    assert list(interpret_map(data)[0]) == [NO_INFORMATION, 0, 0, 0, LETHAL_OBSTACLE]
    assert list(interpret_map(data, track_unknown_space=False)[0]) == [0, 0, 0, 0, 254]
    assert list(interpret_map(data, lethal_cost_threshold=50)[0]) == [255, 0, 254, 254, 254]
    scaled = interpret_map(data, trinary_costmap=False)[0]
    assert list(scaled) == [255, 0, int(0.5 * 254), int(0.99 * 254), 254]



def _interpret_value(v: int, lethal: int, unknown: int, track_unknown: bool, trinary: bool) -> int:
    """StaticLayer::interpretValue for one byte, written out as in costmap_2d."""
    if track_unknown and v == unknown:
        return NO_INFORMATION
    if not track_unknown and v == unknown:
        return 0
    if v >= lethal:
        return LETHAL_OBSTACLE
    if trinary:
        return 0
    return int(v / lethal * LETHAL_OBSTACLE)


@pytest.mark.parametrize("dtype", [np.int8, np.int16, np.uint8])
def test_static_layer_interpretation_matches_the_per_value_rule(dtype):
    rng = np.random.default_rng(3)
    info = np.iinfo(dtype)
    data = rng.integers(info.min, info.max, (40, 30), endpoint=True).astype(dtype)
    for lethal, unknown in ((100, -1), (65, 255), (30, 0)):
        for track in (True, False):
            for trinary in (True, False):
                got = interpret_map(data, lethal, unknown, track, trinary)
                want = [[_interpret_value(int(v) & 0xFF, lethal, unknown & 0xFF, track, trinary)
                         for v in row] for row in data]
                assert got.dtype == np.uint8
                np.testing.assert_array_equal(got, np.array(want, np.uint8))

def test_combination_methods_overwrite_and_maximum():
    grid = ascii_map("""
        ######
        #....#
        ######
    """, resolution=0.5)
    for method, expected in ((1, LETHAL_OBSTACLE), (0, FREE_SPACE), (99, LETHAL_OBSTACLE)):
        cm = LayeredCostmap.from_params(
            {"plugins": ["static_layer", "obstacle_layer"], "robot_radius": 0.1,
             "obstacle_layer": {"combination_method": method}}, static_map=grid)
        # a ray from (1.4, 0.74) to a hit in the left wall: clears the row, marks the hit
        cm.add_points(np.array([[0.25, 0.74, 0.1]]), (1.4, 0.74, 0.1))
        cm.update_map(Pose2D(1.4, 0.74, 0.0))
        assert _cell_cost(cm, 0.25, 0.74) == LETHAL_OBSTACLE  # the hit itself is marked
        assert _cell_cost(cm, 0.75, 0.74) == FREE_SPACE
        # a cleared cell on top of a static wall: overwrite lets the layer's FREE win
        layer = cm.layer("obstacle_layer")
        layer.grid.costs[0, 1] = FREE_SPACE               # static wall cell (row 0)
        layer.add_extra_bounds(0.0, 0.0, 3.0, 1.5)
        cm.update_map(Pose2D(1.4, 0.74, 0.0))
        assert cm.costmap.costs[0, 1] == expected, method


ROS_COMMON = """
footprint: [[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]]
footprint_padding: 0.0
obstacle_range: 2.0
raytrace_range: 2.5
max_obstacle_height: 1.0
inflation_radius: 0.8
cost_scaling_factor: 4.0
observation_sources: laser_scan_sensor
laser_scan_sensor: {sensor_frame: base_laser, data_type: LaserScan, topic: scan, marking: true, clearing: true}
"""

ROS_PLUGINS = """
footprint: "[[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]]"
footprint_padding: 0.0
obstacle_range: 2.0
raytrace_range: 2.5
plugins:
  - {name: obstacle_layer, type: "costmap_2d::ObstacleLayer"}
  - {name: inflation_layer, type: "costmap_2d::InflationLayer"}
obstacle_layer:
  max_obstacle_height: 1.0
  observation_sources: laser_scan_sensor
  laser_scan_sensor: {sensor_frame: base_laser, data_type: LaserScan, topic: scan, marking: true, clearing: true}
inflation_layer: {inflation_radius: 0.8, cost_scaling_factor: 4.0}
"""


def test_ros_parameter_yaml_means_the_same_pre_hydro_and_with_plugins():
    local = {"rolling_window": True, "width": 6.0, "height": 6.0, "resolution": 0.05}
    maps = []
    for text in (ROS_COMMON, ROS_PLUGINS):
        cm = LayeredCostmap.from_params({**yaml.safe_load(text), **local}, name="local_costmap")
        assert [type(l).__name__ for l in cm.layers] == ["ObstacleLayer", "InflationLayer"]
        ol = cm.layer("obstacle_layer")
        src = ol.buffers["laser_scan_sensor"].params
        assert (src.obstacle_range, src.raytrace_range) == (2.0, 2.5)   # found up the namespace
        assert ol.params.max_obstacle_height == 1.0
        assert cm.layer("inflation_layer").params.inflation_radius == 0.8
        assert cm.inscribed_radius == pytest.approx(0.22)
        assert cm.circumscribed_radius == pytest.approx(math.hypot(0.25, 0.22))
        ranges = np.full(360, 1.8, np.float32)
        ranges[100:120] = 2.2                      # beyond obstacle_range: cleared, not marked
        cm.add_scan(_scan(ranges), Pose2D(0.3, -0.2, 0.4))
        cm.update_map(Pose2D(0.3, -0.2, 0.4))
        maps.append(cm.costmap.costs.copy())
    assert np.array_equal(maps[0], maps[1])
    assert np.count_nonzero(maps[0] == LETHAL_OBSTACLE) > 100
    assert INSCRIBED_INFLATED_OBSTACLE in maps[0]


@pytest.mark.parametrize("params, match", [
    ({"plugins": ["obstacle_layer"], "widht": 5.0}, "widht.*did you mean 'width'"),
    ({"plugins": ["inflation_layer"], "inflation_layer": {"inflation_radis": 1}},
     "inflation_radis"),
    ({"plugins": ["obstacle_layer"], "obstacle_layer": {"observation_sources": "scan"}},
     "observation source 'scan'"),
    ({"plugins": ["obstacle_layer"], "obstacle_layer": {
        "observation_sources": "scan", "scan": {"data_type": "Laser"}}}, "data_type"),
    ({"plugins": ["fancy_layer"]}, "fancy_layer"),
    ({"plugins": ["static_layer"]}, "static layer needs a map"),
    ({"plugins": ["obstacle_layer"], "footprint": [[0, 0], [1, 1]]}, "at least 3 points"),
    ({"plugins": "obstacle_layer"}, "'plugins' must be a list"),
    ({"plugins": ["obstacle_layer"], "observation_sources": "scan"}, "belongs in an obstacle"),
])
def test_bad_parameters_are_errors_naming_them(params, match):
    with pytest.raises(ParameterError, match=match):
        LayeredCostmap.from_params(params, name="local_costmap")


def test_footprint_cost_of_the_handle_uses_the_master_grid():
    grid = ascii_map("""
        ##########
        #........#
        #........#
        #........#
        ##########
    """, resolution=0.25)
    cm = LayeredCostmap.from_params({"plugins": ["static_layer", "inflation_layer"],
                                     "footprint": [[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2],
                                                   [-0.2, 0.2]], "footprint_padding": 0.0,
                                     "inflation_layer": {"inflation_radius": 0.3}},
                                    static_map=grid)
    cm.update_map(Pose2D(1.25, 0.6, 0.0))
    # rows 1..3 are free, one cell (0.25 m, beyond the 0.2 m inscribed radius) from the walls
    assert cm.footprint_cost(1.25, 0.62, 0.0) == compute_cost(1.0, 0.25, 0.2, 10.0) == 152
    assert cm.footprint_cost(1.25, 0.3, 0.0) == LETHAL_OBSTACLE
    assert cm.footprint_cost(-1.0, 0.6, 0.0) == -1
    poses = np.array([[1.25, 0.62, 0.0], [1.25, 0.3, 0.0], [-1.0, 0.6, 0.0], [1.0, 0.7, 0.5]])
    assert list(cm.footprint_costs(poses)) == [cm.footprint_cost(*p) for p in poses]


@pytest.mark.parametrize("name", sorted(REAL_MAPS))
def test_each_real_map_builds_a_global_costmap(shared_data, name):
    grid = load_map(shared_data / "maps" / REAL_MAPS[name])
    cm = LayeredCostmap.from_params({"plugins": ["static_layer", "inflation_layer"],
                                     "robot_radius": 0.2, "footprint_padding": 0.0}, grid)
    cm.update_map(Pose2D(grid.origin.x, grid.origin.y, 0.0))
    costs = cm.costmap.costs
    counts = grid.counts()
    assert costs.shape == grid.data.shape
    assert np.count_nonzero(costs == LETHAL_OBSTACLE) == np.count_nonzero(
        (grid.data >= 100) & (grid.data != -1))
    assert np.count_nonzero(costs == LETHAL_OBSTACLE) >= counts["occupied"]
    # unknown cells stay unknown unless inscribed-inflated over
    unknown = grid.data == -1
    assert set(np.unique(costs[unknown])) <= {NO_INFORMATION, INSCRIBED_INFLATED_OBSTACLE,
                                               LETHAL_OBSTACLE}


def test_bad_sensor_data_and_poses_do_not_corrupt_the_map():
    cm = _local(plugins=["obstacle_layer"])
    cm.add_points(np.array([[np.nan, 1.0, 0.3], [1.025, np.inf, 0.3], [1.025, 0.025, 0.3]]),
                  (0.0, 0.0, 0.3))
    assert cm.update_map(Pose2D()) is not None
    assert np.count_nonzero(cm.costmap.costs) == 1
    with pytest.raises(ValueError, match="not finite"):
        cm.add_points(np.array([[1.0, 1.0, 0.3]]), (np.nan, 0.0, 0.3))
    before = cm.costmap.costs.copy()
    assert cm.update_map(Pose2D(np.nan, 0.0, 0.0)) is None
    assert "not finite" in cm.last_error and not cm.is_current()
    assert np.array_equal(cm.costmap.costs, before)
    assert cm.footprint_cost(np.nan, 0.0, 0.0) == -1


def test_a_parameter_change_reinflates_everything_at_the_next_update():
    grid = ascii_map("""
        ############
        #..........#
        #..........#
        #..........#
        #..........#
        #..........#
        ############
    """, resolution=0.1)
    cm = LayeredCostmap.from_params({"plugins": ["static_layer", "inflation_layer"],
                                     "robot_radius": 0.05, "footprint_padding": 0.0,
                                     "inflation_layer": {"inflation_radius": 0.2}},
                                    static_map=grid)
    cm.update_map(Pose2D(0.6, 0.35, 0.0))
    assert _cell_cost(cm, 0.55, 0.35) == FREE_SPACE            # 3 cells from the wall cells
    namespaces = cm.parameter_namespaces()
    assert set(namespaces) == {"global_costmap", "global_costmap/static_layer",
                               "global_costmap/inflation_layer"}
    previous = namespaces["global_costmap/inflation_layer"].set({"inflation_radius": 0.5})
    assert previous == {"inflation_radius": 0.2}
    cm.update_map(Pose2D(0.6, 0.35, 0.0))
    assert _cell_cost(cm, 0.55, 0.35) == compute_cost(3, 0.1, cm.inscribed_radius, 10.0) > 0


def test_nav2_style_plugin_types_inside_the_namespaces():
    cm = LayeredCostmap.from_params({
        "use_sim_time": True, "rolling_window": True, "width": 3.0, "height": 3.0,
        "plugins": ["voxel", "inflater"],
        "voxel": {"plugin": "nav2_costmap_2d::VoxelLayer", "z_voxels": 16},
        "inflater": {"plugin": "nav2_costmap_2d::InflationLayer", "cost_scaling_factor": 3.0}},
        name="local_costmap")
    assert [type(l).__name__ for l in cm.layers] == ["VoxelLayer", "InflationLayer"]
    assert cm.layer("voxel").params.z_voxels == 16


def test_a_costmap_is_freed_as_soon_as_it_is_dropped():
    # Its parameters call back into it before a change (the lazily added scan); held strongly,
    # that hook made a cycle and every dropped costmap's grids waited for the garbage collector
    # (a map-sized costmap built per call cost +35 % in allocation).
    import gc
    import weakref

    cm = _local()
    cm.update_map(Pose2D(0.0, 0.0, 0.0))
    ref = weakref.ref(cm)
    gc.disable()
    try:
        del cm
        assert ref() is None
    finally:
        gc.enable()


def _numpy_scan_points(scan, pose, z, inf_is_valid):
    # the plain statement: drop NaN and out-of-range readings, inf -> just short of range_max
    r = np.asarray(scan.ranges, dtype=np.float64).copy()
    if inf_is_valid:
        r[np.isinf(r) & (r > 0)] = scan.range_max - 0.0001
    ok = np.isfinite(r) & (r >= scan.range_min) & (r < scan.range_max)
    a = scan.angles()[ok] + pose.theta
    r = r[ok]
    return np.stack([pose.x + r * np.cos(a), pose.y + r * np.sin(a), np.full(len(r), z)], axis=1)


@pytest.mark.parametrize("inf_is_valid", [False, True])
def test_scan_points_are_the_valid_beam_ends_in_beam_order(inf_is_valid):
    rng = np.random.default_rng(11)
    for _ in range(40):
        n = int(rng.integers(1, 400))
        ranges = rng.uniform(-1.0, 12.0, n)
        odd = rng.random(n)
        ranges[odd < 0.1] = np.nan
        ranges[(odd >= 0.1) & (odd < 0.2)] = np.inf
        ranges[(odd >= 0.2) & (odd < 0.25)] = -np.inf
        a0 = float(rng.uniform(-3.2, 0.0))
        inc = float(rng.uniform(0.001, 0.05))
        scan = LaserScan(0.0, a0, a0 + inc * (n - 1), inc, 0.0, 0.1, 0.05, 10.0, ranges)
        pose = Pose2D(*rng.uniform(-20.0, 20.0, 2), float(rng.uniform(-7.0, 7.0)))
        got = scan_to_points(scan, pose, 0.3, inf_is_valid)
        np.testing.assert_array_equal(got, _numpy_scan_points(scan, pose, 0.3, inf_is_valid))


def test_observations_keep_the_finite_points_within_the_source_heights():
    from navcore.costmap.obstacle_layer import _kept_points
    rng = np.random.default_rng(5)
    pts = rng.uniform(-1.0, 3.0, size=(500, 3))
    pts[rng.random(pts.shape) < 0.05] = np.nan
    pts[rng.random(pts.shape) < 0.02] = np.inf
    pts[:4] = [[0.0, 0.0, 0.2], [0.0, 0.0, 1.5], [0.0, 0.0, 0.2 - 1e-12], [0.0, 0.0, 1.5 + 1e-12]]
    got = _kept_points(pts, 0.2, 1.5)
    keep = np.isfinite(pts).all(axis=1) & (pts[:, 2] >= 0.2) & (pts[:, 2] <= 1.5)
    np.testing.assert_array_equal(got, pts[keep])
    np.testing.assert_array_equal(got[:2, 2], [0.2, 1.5])  # the limits are kept, beyond them not
    assert got.flags.c_contiguous and 0 < len(got) < len(pts)


def test_scan_and_observation_filters_give_empty_arrays_when_nothing_is_valid():
    from navcore.costmap.obstacle_layer import _kept_points
    scan = LaserScan(0.0, -0.5, 0.5, 0.25, 0.0, 0.1, 0.05, 10.0,
                     np.array([np.nan, 0.01, 10.0, np.inf, -np.inf]))
    pts = scan_to_points(scan, Pose2D(1.0, 2.0, 0.3), 0.2)
    assert pts.shape == (0, 3)
    kept = _kept_points(np.empty((0, 3)), 0.0, 2.0)
    assert kept.shape == (0, 3) and kept.flags.c_contiguous
    # inf_is_valid turns only the +inf reading into a point just short of range_max
    np.testing.assert_array_equal(scan_to_points(scan, Pose2D(0.0, 0.0, 0.0), 0.2, True),
                                  [[(10.0 - 0.0001) * math.cos(0.25),
                                    (10.0 - 0.0001) * math.sin(0.25), 0.2]])
