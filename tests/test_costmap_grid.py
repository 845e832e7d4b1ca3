"""Costmap2D operations: rolling origin, clearArea, polygon fill, bounds, combination methods."""

from __future__ import annotations

import numpy as np
import pytest

from navcore.costmap.cost_values import NO_INFORMATION
from navcore.costmap.costmap2d import (Costmap2D, combine_addition, combine_max, combine_overwrite,
                                       combine_true_overwrite)
from navcore.costmap.obstacle_layer import raytrace_line


def test_update_origin_moves_content_with_the_world():
    cm = Costmap2D(10, 8, 0.5, -1.0, 2.0, default_value=7)
    cm.costs[:] = np.arange(80).reshape(8, 10)
    world = {cm.map_to_world(mx, my): int(cm.costs[my, mx]) for my in range(8) for mx in range(10)}
    cm.update_origin(0.3, 0.9)       # whole cells from the old origin: +2 cells in x, -2 in y
    assert (cm.origin_x, cm.origin_y) == (0.0, 1.0)
    for (wx, wy), value in world.items():
        cell = cm.world_to_map(wx, wy)
        if cell is not None:
            assert cm.costs[cell[1], cell[0]] == value
    assert (cm.costs[:2] == 7).all() and (cm.costs[:, 8:] == 7).all()
    cm.update_origin(100.0, 100.0)   # no overlap at all
    assert (cm.costs == 7).all()


def test_clear_area_is_open_rectangle_and_invertible():
    cm = Costmap2D(6, 5, 1.0)
    cm.clear_area(1, 1, 4, 3)
    inside = np.zeros((5, 6), bool)
    inside[2, 2:4] = True            # open (1, 4) x (1, 3): x in {2, 3}, y = 2
    assert (cm.costs[inside] == 0).all() and (cm.costs[~inside] == NO_INFORMATION).all()
    cm2 = Costmap2D(6, 5, 1.0)
    cm2.clear_area(1, 1, 4, 3, invert=True)
    assert (cm2.costs[inside] == NO_INFORMATION).all() and (cm2.costs[~inside] == 0).all()


def test_convex_polygon_fill_covers_outline_and_inside():
    cm = Costmap2D(20, 20, 0.1)
    assert cm.set_convex_polygon_cost(np.array([[0.55, 0.55], [1.45, 0.55], [1.45, 1.25],
                                                [0.55, 1.25]]), 9)
    assert (cm.costs[5:13, 5:15] == 9).all()
    assert np.count_nonzero(cm.costs) == 8 * 10
    # a triangle: every column between its lowest and highest outline cell
    tri = Costmap2D(20, 20, 0.1)
    tri.set_convex_polygon_cost(np.array([[0.05, 0.05], [1.05, 0.05], [0.05, 1.05]]), 3)
    for mx in range(11):
        col = np.nonzero(tri.costs[:, mx])[0]
        assert col.min() == 0 and col.max() >= 9 - mx and (np.diff(col) == 1).all()
    assert not cm.set_convex_polygon_cost(np.array([[-0.5, 0.5], [1.0, 0.5], [1.0, 1.0]]), 1)


def test_world_to_map_enforce_bounds_clamps():
    cm = Costmap2D(10, 10, 0.5, 1.0, 1.0)
    assert cm.world_to_map_enforce_bounds(-5.0, 100.0) == (0, 9)
    assert cm.world_to_map_enforce_bounds(2.2, 3.9) == (2, 5)


def test_raytrace_line_stops_at_max_length_and_sets_the_last_cell():
    g = np.zeros((10, 20), np.uint8)
    raytrace_line(g, 1, 1, 15, 4, 1000, np.uint8(5))
    assert g[1, 1] == 5 and g[4, 15] == 5 and np.count_nonzero(g) == 15
    h = np.zeros((10, 20), np.uint8)
    raytrace_line(h, 1, 1, 15, 1, 4, np.uint8(5))
    assert list(np.nonzero(h[1])[0]) == [1, 2, 3, 4, 5]   # 4 steps, then the cell reached


@pytest.mark.parametrize("fn, expected", [
    (combine_true_overwrite, [255, 0, 100, 254, 200]),
    (combine_overwrite, [10, 0, 100, 254, 200]),      # the layer's unknown cells are skipped
    (combine_max, [10, 50, 100, 254, 252]),           # unknown master cells take the layer's
    (combine_addition, [10, 50, 150, 254, 252]),      # sums capped at 252
])
def test_combination_methods(fn, expected):
    master = np.array([[10, 50, 50, NO_INFORMATION, 252]], np.uint8)
    layer = np.array([[NO_INFORMATION, 0, 100, 254, 200]], np.uint8)
    fn(master, layer, 0, 0, 5, 1)
    assert list(master[0]) == expected
