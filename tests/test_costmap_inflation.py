"""Inflation: the costmap_2d formula, an exact distance transform, windowed re-inflation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navcore.costmap.cost_values import (FREE_SPACE, INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE,
                                         NO_INFORMATION)
from navcore.costmap.inflation import (InflationLayer, cell_inflation_radius, compute_cost,
                                       cost_table, inflate)
from navcore.distance_transform import squared_distance_transform
from navcore.params import ParameterError

RES, INSCRIBED, RADIUS, CSF = 0.05, 0.2, 0.55, 10.0


def _brute_force(costs, res, inscribed, radius, csf, inflate_unknown=False):
    """Inflate by measuring every cell's distance to every lethal cell (no shared code)."""
    out = costs.copy()
    ys, xs = np.nonzero(costs == LETHAL_OBSTACLE)
    if len(ys) == 0:
        return out
    r = math.ceil(radius / res)
    h, w = costs.shape
    for y in range(h):
        for x in range(w):
            d = math.sqrt(float(((ys - y) ** 2 + (xs - x) ** 2).min()))
            if d > r:
                continue
            if d == 0:
                c = 254
            elif d * res <= inscribed:
                c = 253
            else:
                c = int(252 * math.exp(-csf * (d * res - inscribed)))
            old = int(out[y, x])
            if old == 255:
                if (c > 0) if inflate_unknown else (c >= 253):
                    out[y, x] = c
            else:
                out[y, x] = max(old, c)
    return out


def test_cost_formula_at_sampled_distances():
    # d = 0 lethal; within the inscribed radius 253; beyond, 252 exp(-csf (d - inscribed)) floored
    assert compute_cost(0, RES, INSCRIBED, CSF) == 254
    assert compute_cost(4, RES, INSCRIBED, CSF) == 253            # 0.20 m == inscribed
    assert compute_cost(5, RES, INSCRIBED, CSF) == int(252 * math.exp(-0.5))   # 152
    assert compute_cost(5, RES, INSCRIBED, CSF) == 152
    assert compute_cost(11, RES, INSCRIBED, CSF) == 7             # 252 e^-3.5 = 7.6
    assert compute_cost(math.sqrt(50), RES, INSCRIBED, CSF) == int(
        252 * math.exp(-CSF * (math.sqrt(50) * RES - INSCRIBED)))
    table = cost_table(RES, INSCRIBED, RADIUS, CSF)
    assert cell_inflation_radius(RADIUS, RES) == 11 and len(table) == 122
    for d2 in range(len(table)):
        assert table[d2] == compute_cost(math.sqrt(d2), RES, INSCRIBED, CSF)


def test_inflated_costs_equal_the_formula_around_one_obstacle():
    costs = np.zeros((41, 41), np.uint8)
    costs[20, 20] = LETHAL_OBSTACLE
    inflate(costs, cost_table(RES, INSCRIBED, RADIUS, CSF))
    for dx, dy in [(0, 0), (1, 0), (3, 2), (4, 0), (5, 0), (6, 6), (11, 0), (7, 8), (8, 8),
                   (12, 0)]:
        d = math.hypot(dx, dy)
        expected = compute_cost(d, RES, INSCRIBED, CSF) if d <= 11 else 0
        assert costs[20 + dy, 20 + dx] == expected, (dx, dy)
        assert costs[20 - dx, 20 - dy] == expected, (dx, dy)


@pytest.mark.parametrize("inflate_unknown", [False, True])
def test_inflation_agrees_with_brute_force_on_random_small_maps(inflate_unknown):
    rng = np.random.default_rng(3)
    table = cost_table(RES, INSCRIBED, RADIUS, CSF)
    for trial in range(12):
        h, w = rng.integers(3, 36, 2)
        costs = np.zeros((h, w), np.uint8)
        costs[rng.random((h, w)) < 0.04] = LETHAL_OBSTACLE
        costs[rng.random((h, w)) < 0.08] = NO_INFORMATION
        costs[rng.random((h, w)) < 0.05] = 100
        expected = _brute_force(costs, RES, INSCRIBED, RADIUS, CSF, inflate_unknown)
        got = costs.copy()
        inflate(got, table, inflate_unknown=inflate_unknown)
        assert np.array_equal(got, expected), trial


def test_exact_distance_transform_matches_brute_force():
    rng = np.random.default_rng(11)
    mask = rng.random((23, 31)) < 0.03
    mask[0, 0] = True
    ys, xs = np.nonzero(mask)
    yy, xx = np.mgrid[0:23, 0:31]
    brute = ((yy[..., None] - ys) ** 2 + (xx[..., None] - xs) ** 2).min(-1)
    assert np.array_equal(squared_distance_transform(mask), brute)


def test_window_reinflation_equals_full_inflation_inside_the_window():
    rng = np.random.default_rng(5)
    table = cost_table(RES, INSCRIBED, RADIUS, CSF)
    base = np.zeros((80, 90), np.uint8)
    base[rng.random(base.shape) < 0.02] = LETHAL_OBSTACLE
    full = base.copy()
    inflate(full, table)
    part = base.copy()
    inflate(part, table, 20, 15, 60, 50)
    # inside the window exactly as a full inflation (obstacles outside it count), outside untouched
    assert np.array_equal(part[15:50, 20:60], full[15:50, 20:60])
    outside = np.ones(base.shape, bool)
    outside[15:50, 20:60] = False
    assert np.array_equal(part[outside], base[outside])


def test_inflation_layer_bounds_and_parameters():
    layer = InflationLayer("inflation_layer", {"inflation_radius": 1.0, "cost_scaling_factor": 3.0},
                           inscribed_radius=0.3)
    b = [0.0, 0.0, 1.0, 1.0]
    layer.update_bounds(0, 0, 0, b)      # first update: everything
    assert b == [-1e30, -1e30, 1e30, 1e30]
    b = [2.0, 2.0, 3.0, 3.0]
    layer.update_bounds(0, 0, 0, b)      # union with the previous window, grown by the radius
    assert b == pytest.approx([-1.0, -1.0, 4.0, 4.0])
    assert layer.table()[0] == LETHAL_OBSTACLE and layer.table()[25] == INSCRIBED_INFLATED_OBSTACLE
    with pytest.raises(ParameterError, match="inflation_radiuss"):
        InflationLayer("inflation_layer", {"inflation_radiuss": 1.0})


def test_unknown_cells_keep_no_information_unless_lethal_nearby():
    costs = np.full((30, 30), NO_INFORMATION, np.uint8)
    costs[15, 15] = LETHAL_OBSTACLE
    inflate(costs, cost_table(RES, INSCRIBED, RADIUS, CSF))
    assert costs[15, 19] == INSCRIBED_INFLATED_OBSTACLE   # 4 cells: inscribed, written
    assert costs[15, 21] == NO_INFORMATION                # 6 cells: 91 < 253, unknown kept
    assert costs[15, 15] == LETHAL_OBSTACLE
    assert FREE_SPACE not in costs


def test_threaded_bands_give_the_same_costs():
    rng = np.random.default_rng(9)
    base = np.zeros((600, 300), np.uint8)
    base[rng.random(base.shape) < 0.01] = LETHAL_OBSTACLE
    base[rng.random(base.shape) < 0.05] = NO_INFORMATION
    table = cost_table(RES, INSCRIBED, 1.0, 3.0)
    one, three = base.copy(), base.copy()
    inflate(one, table)
    scratch = inflate(three, table, 0, 10, 300, 590, num_threads=3)
    assert len(scratch) == 3
    assert np.array_equal(three[10:590], one[10:590])
    assert np.array_equal(three[:10], base[:10]) and np.array_equal(three[590:], base[590:])
