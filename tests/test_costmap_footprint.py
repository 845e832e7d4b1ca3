"""Footprint construction (costmap_2d semantics) and footprint cost vs brute-force rasterisation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navcore.costmap import footprint as footprint_module
from navcore.costmap.footprint import (bound_reach, circumscribed_radius, footprint_cost,
                                       footprint_cost_plain, inscribed_radius, make_footprint,
                                       square_max, transform_footprint)

# Both compiled variants on every host; the vector row max is LLVM IR, which only the JIT runs
# (without it footprint_cost is the plain variant, tested as such)
VARIANTS = {"plain": footprint_cost_plain}
if footprint_module.VECTOR_ROWS:
    VARIANTS["vector"] = footprint_module.footprint_cost_vector

RECT = [[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]]
# a non-convex "L" footprint, to exercise the even-odd fill
ELL = [[0.3, 0.3], [0.3, -0.1], [0.0, -0.1], [0.0, -0.3], [-0.3, -0.3], [-0.3, 0.3]]


def test_radius_footprint_is_a_padded_16gon():
    fp = make_footprint(None, robot_radius=0.46, footprint_padding=0.0)
    assert fp.shape == (16, 2) and fp.dtype == np.float64
    assert np.allclose(np.hypot(fp[:, 0], fp[:, 1]), 0.46)
    assert circumscribed_radius(fp) == pytest.approx(0.46)
    assert inscribed_radius(fp) == pytest.approx(0.46 * math.cos(math.pi / 16))
    padded = make_footprint(None, 0.46, 0.01)
    # vertex (0.46, 0) moves along x only (sin 0 is exactly 0); diagonal ones along both
    assert padded[0] == pytest.approx([0.47, 0.0])
    assert padded[4][1] == pytest.approx(0.47)
    assert padded[2] == pytest.approx(fp[2] + 0.01)


def test_polygon_footprint_padding_and_radii():
    fp = make_footprint(RECT, footprint_padding=0.05)
    assert fp[0] == pytest.approx([0.30, 0.27])
    assert fp[2] == pytest.approx([-0.30, -0.27])
    assert inscribed_radius(fp) == pytest.approx(0.27)
    assert circumscribed_radius(fp) == pytest.approx(math.hypot(0.30, 0.27))
    # the ROS string form means the same; an empty footprint falls back to robot_radius
    assert np.allclose(make_footprint(str(RECT), footprint_padding=0.05), fp)
    assert make_footprint("[]", robot_radius=0.3).shape == (16, 2)


@pytest.mark.parametrize("bad", [[[0, 0], [1, 1]], [[0, 0, 0], [1, 1, 1], [2, 2, 2]], "[[0,",
                                 "abc"])
def test_bad_footprints_are_clear_errors(bad):
    with pytest.raises(ValueError, match="footprint"):
        make_footprint(bad)


def _clip(poly, inside, cut):
    """One Sutherland-Hodgman step: keep the part of ``poly`` where ``inside`` holds."""
    out = []
    for i in range(len(poly)):
        p, q = poly[i - 1], poly[i]
        if inside(q):
            if not inside(p):
                out.append(cut(p, q))
            out.append(q)
        elif inside(p):
            out.append(cut(p, q))
    return out


def _meets_square(poly, x0, y0, x1, y1):
    """Whether a polygon meets the closed rectangle: clip it to the rectangle, see if anything
    is left."""
    def at_x(p, q, x):
        t = (x - p[0]) / (q[0] - p[0])
        return (x, p[1] + t * (q[1] - p[1]))

    def at_y(p, q, y):
        t = (y - p[1]) / (q[1] - p[1])
        return (p[0] + t * (q[0] - p[0]), y)
    poly = [tuple(p) for p in poly]
    for inside, cut in ((lambda p: p[0] >= x0, lambda p, q: at_x(p, q, x0)),
                        (lambda p: p[0] <= x1, lambda p, q: at_x(p, q, x1)),
                        (lambda p: p[1] >= y0, lambda p, q: at_y(p, q, y0)),
                        (lambda p: p[1] <= y1, lambda p, q: at_y(p, q, y1))):
        poly = _clip(poly, inside, cut)
        if not poly:
            return False
    return True


def _brute_force(costs, ox, oy, res, fp, x, y, th):
    """Max cost over every cell the placed polygon overlaps (no code shared with the kernel)."""
    poly = transform_footprint(fp, x, y, th)
    h, w = costs.shape
    u, v = (poly[:, 0] - ox) / res, (poly[:, 1] - oy) / res
    if (u < 0).any() or (v < 0).any() or (u >= w).any() or (v >= h).any():
        return -1
    best = 0
    for my in range(int(v.min()), int(v.max()) + 1):
        for mx in range(int(u.min()), int(u.max()) + 1):
            if costs[my, mx] > best and _meets_square(
                    poly, ox + mx * res, oy + my * res, ox + (mx + 1) * res, oy + (my + 1) * res):
                best = int(costs[my, mx])
    return best


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("shape", ["rect", "radius", "ell"])
def test_footprint_cost_matches_brute_force_on_random_poses(shape, variant):
    footprint_cost = VARIANTS[variant]
    rng = np.random.default_rng(7)
    fp = {"rect": make_footprint(RECT), "radius": make_footprint(None, 0.3),
          "ell": make_footprint(ELL, footprint_padding=0.0)}[shape]
    res, ox, oy = 0.05, -1.0, 0.5
    h, w = 40, 48
    for trial in range(150):
        # sparse random costs so that the max comes from one cell: on the rim or inside
        costs = np.zeros((h, w), np.uint8)
        k = rng.integers(1, 8) if trial % 3 else h * w // 4   # every third map is dense
        costs[rng.integers(0, h, k), rng.integers(0, w, k)] = rng.integers(1, 255, k)
        x = ox + rng.uniform(-0.2, w * res + 0.2)
        y = oy + rng.uniform(-0.2, h * res + 0.2)
        th = rng.uniform(-math.pi, math.pi)
        expected = _brute_force(costs, ox, oy, res, fp, x, y, th)
        got = footprint_cost(costs, ox, oy, res, fp, x, y, th)
        assert got == expected, (trial, x, y, th)


def test_footprint_cost_counts_cells_the_rim_only_grazes():
    square = np.array([[0.1, 0.1], [0.1, -0.1], [-0.1, -0.1], [-0.1, 0.1]])
    costs = np.zeros((20, 20), np.uint8)
    costs[10, 12] = 200          # cell [0.60, 0.65) x [0.50, 0.55): its centre is outside
    # the square around (0.5, 0.5) reaches x = 0.6 + 0.001: it overlaps that cell by 1 mm
    assert footprint_cost(costs, 0.0, 0.0, 0.05, square, 0.501, 0.52, 0.0) == 200
    assert footprint_cost(costs, 0.0, 0.0, 0.05, square, 0.499, 0.52, 0.0) == 0


def test_the_costmaps_call_the_vector_variant_unless_told_otherwise():
    # NAVBT_PLAIN_KERNELS=1 (and NUMBA_DISABLE_JIT=1) select the plain kernel
    import os
    plain = (os.environ.get("NAVBT_PLAIN_KERNELS") == "1"
             or os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"))
    assert footprint_module.VECTOR_ROWS is not plain
    assert footprint_cost is (footprint_cost_plain if plain
                              else footprint_module.footprint_cost_vector)


def test_footprint_cost_sees_an_obstacle_strictly_inside():
    fp = make_footprint(RECT, footprint_padding=0.0)
    costs = np.zeros((100, 100), np.uint8)
    costs[50, 50] = 254  # world (2.525, 2.525) with res 0.05
    assert footprint_cost(costs, 0.0, 0.0, 0.05, fp, 2.5, 2.5, 0.0) == 254
    assert footprint_cost(costs, 0.0, 0.0, 0.05, fp, 2.5, 2.5, 1.0) == 254
    assert footprint_cost(costs, 0.0, 0.0, 0.05, fp, 3.5, 2.5, 0.0) == 0
    assert footprint_cost(costs, 0.0, 0.0, 0.05, fp, 0.1, 2.5, 0.0) == -1


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("case", ["wide_rows", "heap_rows", "many_vertices", "narrow_map",
                                  "strided_costs"])
def test_footprint_cost_matches_brute_force_beyond_the_common_sizes(case, variant):
    """The kernel's other paths: row spans longer than one vector load, many rows or vertices,
    maps narrower than a vector load, non-contiguous rows."""
    footprint_cost = VARIANTS[variant]
    rng = np.random.default_rng(11)
    res, ox, oy = 0.05, 0.0, 0.0
    h, w = 60, 60
    fp = make_footprint(RECT, footprint_padding=0.0)
    if case == "wide_rows":          # 1.2 m x 0.6 m at 0.01 m: spans of up to ~130 cells
        fp = np.array([[0.6, 0.3], [0.6, -0.3], [-0.6, -0.3], [-0.6, 0.3]])
        res, h, w = 0.01, 200, 200
    elif case == "heap_rows":        # 3.2 m across at 0.01 m: ~320 rows
        fp = make_footprint(None, 1.6, 0.0)
        res, h, w = 0.01, 400, 400
    elif case == "many_vertices":    # a 100-gon
        a = np.arange(100) * (2 * math.pi / 100)
        fp = np.stack([0.4 * np.cos(a), 0.3 * np.sin(a)], axis=1)
    elif case == "narrow_map":
        h, w = 60, 14
    for trial in range(25):
        costs = np.zeros((h, w), np.uint8)
        k = rng.integers(1, 6) * max(1, h * w // 3600)  # a few cells under the footprint
        costs[rng.integers(0, h, k), rng.integers(0, w, k)] = rng.integers(1, 255, k)
        if case == "strided_costs":
            wide = np.zeros((h, 2 * w), np.uint8)
            wide[:, ::2] = costs
            wide[:, 1::2] = 255          # must never be read
            costs = wide[:, ::2]
        half = circumscribed_radius(fp) + 1e-6  # on the map at any heading
        x = ox + rng.uniform(half, w * res - half)
        y = oy + rng.uniform(half, h * res - half)
        th = rng.uniform(-math.pi, math.pi)
        expected = _brute_force(costs, ox, oy, res, fp, x, y, th)
        assert footprint_cost(costs, ox, oy, res, fp, x, y, th) == expected, (trial, x, y, th)


def test_square_max_is_the_max_over_the_clipped_square_and_bounds_footprint_costs():
    rng = np.random.default_rng(5)
    for shape, reach in (((30, 41), 3), ((5, 7), 4), ((3, 3), 0), ((4, 9), 20)):
        costs = ((rng.random(shape) < 0.05) * rng.integers(1, 255, shape)).astype(np.uint8)
        expected = np.array([[costs[max(0, i - reach):i + reach + 1,
                                    max(0, j - reach):j + reach + 1].max()
                              for j in range(shape[1])] for i in range(shape[0])])
        assert np.array_equal(square_max(costs, reach), expected)
    # the bound at a pose's cell is never below its footprint cost, at any heading
    fp = make_footprint(RECT, footprint_padding=0.0)
    reach = bound_reach(fp, 0.05)
    costs = ((rng.random((60, 60)) < 0.02) * rng.integers(1, 255, (60, 60))).astype(np.uint8)
    bound = square_max(costs, reach)
    for _ in range(300):
        x, y, th = rng.uniform(0.5, 2.5), rng.uniform(0.5, 2.5), rng.uniform(-math.pi, math.pi)
        assert footprint_cost(costs, 0.0, 0.0, 0.05, fp, x, y, th) <= bound[int(y / 0.05),
                                                                             int(x / 0.05)]


@pytest.mark.parametrize("res", [0.05, 0.03, 0.1])
def test_reach_square_holds_every_cell_the_footprint_covers(res):
    """Everything outside the reach square around the pose's cell is lethal: the footprint
    never sees it, at any position within the cell and any heading, grown or not."""
    rng = np.random.default_rng(3)
    fp = make_footprint(RECT, footprint_padding=0.0)
    for scale in (1.0, 1.2):
        reach = bound_reach(fp, res, scale)
        for _ in range(300):
            mx, my = 20, 20
            x = (mx + rng.choice([0.0, 1e-12, 0.5, 1.0 - 1e-12, rng.random()])) * res
            y = (my + rng.choice([0.0, 1e-12, 0.5, 1.0 - 1e-12, rng.random()])) * res
            if int(x / res) != mx or int(y / res) != my:
                continue
            costs = np.full((41, 41), 254, np.uint8)
            costs[my - reach:my + reach + 1, mx - reach:mx + reach + 1] = 0
            th = rng.uniform(-math.pi, math.pi)
            assert footprint_cost(costs, 0.0, 0.0, res, fp * scale, x, y, th) == 0
    assert bound_reach(fp, 0.05) == int(math.hypot(0.25, 0.22) / 0.05) + 1


def test_transform_footprint_is_the_rotation_then_translation_of_each_vertex():
    rng = np.random.default_rng(3)
    for n in (1, 4, 16):
        fp = rng.uniform(-0.6, 0.6, size=(n, 2))
        for _ in range(50):
            x, y, th = rng.uniform(-40.0, 40.0), rng.uniform(-40.0, 40.0), rng.uniform(-7.0, 7.0)
            c, s = np.cos(th), np.sin(th)
            want = np.stack([x + c * fp[:, 0] - s * fp[:, 1], y + s * fp[:, 0] + c * fp[:, 1]],
                            axis=1)
            np.testing.assert_array_equal(transform_footprint(fp, x, y, th), want)
