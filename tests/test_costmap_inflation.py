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


def _reference(costs, table, x0, y0, xn, yn, inflate_unknown):
    """Inflation of the window from the full-map exact EDT and the merge rule, written out."""
    r = math.isqrt(len(table) - 1)
    lethal = costs == LETHAL_OBSTACLE
    out = costs.copy()
    if not lethal.any():  # (the EDT's value without any site is finite)
        return out
    d2 = squared_distance_transform(lethal)[y0:yn, x0:xn].astype(np.int64)
    old = costs[y0:yn, x0:xn].astype(np.int64)
    near = d2 <= r * r
    c = np.where(near, table[np.minimum(d2, r * r)], 0).astype(np.int64)
    takes = (c > FREE_SPACE) if inflate_unknown else (c >= INSCRIBED_INFLATED_OBSTACLE)
    new = np.where(old == NO_INFORMATION, np.where(takes, c, NO_INFORMATION), np.maximum(old, c))
    out[y0:yn, x0:xn] = np.where(near, new, old)
    return out


# radii (cells) covering each row type and row pass: uint8 (r <= 11), uint16, the envelope (>= 182),
# int32 column distances (>= 254)
@pytest.mark.parametrize("radius_cells", [0, 1, 2, 7, 11, 12, 20, 39, 181, 182, 190, 260])
def test_truncated_transform_agrees_with_the_full_edt_on_random_maps_and_windows(radius_cells):
    rng = np.random.default_rng(100 + radius_cells)
    table = cost_table(RES, 0.6 * radius_cells * RES, (radius_cells - 0.25) * RES, 4.0)
    assert len(table) == radius_cells ** 2 + 1
    for trial in range(6):
        h, w = (int(v) for v in rng.integers(1, min(3 * radius_cells + 30, 230), 2))
        costs = np.zeros((h, w), np.uint8)
        costs[rng.random((h, w)) < rng.choice([0.002, 0.02, 0.2])] = LETHAL_OBSTACLE
        costs[rng.random((h, w)) < 0.15] = NO_INFORMATION
        costs[rng.random((h, w)) < 0.1] = rng.integers(1, 253)
        if trial == 0:  # windows at the map edges and the whole map
            x0, y0, xn, yn = 0, 0, w, h
        else:
            x0, xn = sorted(int(v) for v in rng.integers(0, w + 1, 2))
            y0, yn = sorted(int(v) for v in rng.integers(0, h + 1, 2))
        for inflate_unknown in (False, True):
            expected = _reference(costs, table, x0, y0, xn, yn, inflate_unknown)
            got = costs.copy()
            inflate(got, table, x0, y0, xn, yn, inflate_unknown=inflate_unknown)
            assert np.array_equal(got, expected), (trial, inflate_unknown, (x0, y0, xn, yn))


def test_reused_scratch_and_threads_give_the_same_costs_at_every_radius():
    rng = np.random.default_rng(21)
    base = np.zeros((400, 230), np.uint8)
    base[rng.random(base.shape) < 0.003] = LETHAL_OBSTACLE
    base[rng.random(base.shape) < 0.05] = NO_INFORMATION
    scratch: list = []
    for radius in (0.3, 1.0, 9.5, 0.55):  # uint8, uint16, envelope, uint8 again: buffers change
        table = cost_table(RES, INSCRIBED, radius, 3.0)
        one = base.copy()
        scratch = inflate(one, table, scratch=scratch)
        expected = _reference(base, table, 0, 0, 230, 400, False)
        assert np.array_equal(one, expected), radius
        two = base.copy()
        inflate(two, table, 5, 3, 220, 396, num_threads=2)
        assert np.array_equal(two[3:396, 5:220], expected[3:396, 5:220]), radius


@pytest.mark.parametrize("r", [1, 3, 11, 25])
def test_window_and_envelope_row_passes_agree_within_the_radius(r):
    # the two row passes the kernel chooses between by radius, on the same random rows
    from navcore.costmap.inflation import _row_pass_envelope, _row_pass_window, _row_type
    rng = np.random.default_rng(r)
    t = _row_type(r)
    for trial in range(50):
        w = int(rng.integers(1, 120))
        g = np.minimum(rng.integers(0, r + 2, w), r + 1)
        g[rng.random(w) < 0.5] = r + 1  # many cells out of reach
        pad = np.full(w + 2 * r, r * r + 1, t)
        pad[r:r + w] = np.minimum(g * g, r * r + 1)
        ox, nx = sorted(int(v) for v in rng.integers(0, w + 1, 2))
        nx -= ox
        a = np.zeros(max(nx, 1), t)
        b = np.zeros(max(nx, 1), np.int32)
        _row_pass_window(pad, ox, nx, r, a)
        _row_pass_envelope(pad, ox, nx, r, np.empty(w, np.int64), np.empty(w, np.int64),
                           np.empty(w + 1, np.float64), b)
        q = np.arange(w)
        brute = np.array([min([int(g[i]) ** 2 + (x - i) ** 2 for i in q if g[i] <= r],
                              default=r * r + 1) for x in range(ox, ox + nx)], dtype=np.int64)
        inside = brute <= r * r
        assert np.array_equal(a[:nx][inside], brute[inside]), trial
        assert np.array_equal(b[:nx][inside], brute[inside]), trial
        assert (a[:nx][~inside] > r * r).all() and (b[:nx][~inside] > r * r).all(), trial


@pytest.mark.parametrize("r", [2, 11, 30])
def test_both_row_passes_give_the_same_costs(r):
    # the kernel's two row passes (chosen by radius in ``inflate``) on the same maps and windows
    from navcore.costmap.inflation import _buffers, _inflate_kernel, _kernel_table
    rng = np.random.default_rng(40 + r)
    table = cost_table(RES, 0.3 * r * RES, (r - 0.25) * RES, 2.0)
    changed = 0
    for trial in range(8):
        h, w = (int(v) for v in rng.integers(1, 4 * r + 40, 2))
        costs = np.zeros((h, w), np.uint8)
        costs[rng.random((h, w)) < rng.choice([0.005, 0.05])] = LETHAL_OBSTACLE
        costs[rng.random((h, w)) < 0.1] = NO_INFORMATION
        x0, xn = sorted(int(v) for v in rng.integers(0, w + 1, 2))
        y0, yn = sorted(int(v) for v in rng.integers(0, h + 1, 2))
        sx0, sy0, sxn, syn = max(0, x0 - r), max(0, y0 - r), min(w, xn + r), min(h, yn + r)
        out = []
        for envelope in (False, True):
            c = costs.copy()
            bufs = _buffers(r, (syn - sy0, sxn - sx0), xn - x0, None)
            _inflate_kernel(c, x0, y0, xn, yn, sx0, sy0, sxn, syn, _kernel_table(table),
                            1 if trial % 2 else INSCRIBED_INFLATED_OBSTACLE, r, envelope,
                            int(rng.integers(1, 40)), *bufs)
            out.append(c)
        assert np.array_equal(out[0], out[1]), trial
        changed += int((out[0] != costs).sum())
    assert changed > 0  # the maps were really inflated


def test_wide_maps_inflate_in_blocks_of_rows_with_the_same_costs():
    # wide enough that inflate() cuts the rows into several blocks (column distances in cache)
    from navcore.costmap.inflation import _block_rows
    rng = np.random.default_rng(8)
    h, w = 300, 6000
    assert _block_rows(11, w + 22) * 2 < h
    base = np.zeros((h, w), np.uint8)
    base[rng.random(base.shape) < 0.002] = LETHAL_OBSTACLE
    base[rng.random(base.shape) < 0.05] = NO_INFORMATION
    table = cost_table(RES, INSCRIBED, RADIUS, CSF)
    for window in [(0, 0, w, h), (17, 5, 5000, 290)]:
        for inflate_unknown in (False, True):
            got = base.copy()
            inflate(got, table, *window, inflate_unknown=inflate_unknown)
            assert np.array_equal(got, _reference(base, table, *window, inflate_unknown))
