"""Footprint construction (costmap_2d semantics) and footprint cost vs brute-force rasterisation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navcore.costmap.footprint import (circumscribed_radius, footprint_cost, inscribed_radius,
                                       make_footprint, transform_footprint)

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


def _line(x0, y0, x1, y1):
    """The cells of base_local_planner's LineIterator, ends included."""
    dx, dy = abs(x1 - x0), abs(y1 - y0)
    sx, sy = (1 if x1 >= x0 else -1), (1 if y1 >= y0 else -1)
    major, minor = (dx, dy) if dx >= dy else (dy, dx)
    num = major // 2
    cells = []
    x, y = x0, y0
    for _ in range(major + 1):
        cells.append((x, y))
        num += minor
        step_minor = num >= major
        if step_minor:
            num -= major
        if dx >= dy:
            x += sx
            y += sy if step_minor else 0
        else:
            y += sy
            x += sx if step_minor else 0
    assert cells[-1] == (x1, y1)
    return cells


def _inside(px, py, poly):
    """Even-odd point-in-polygon test for arrays of points."""
    inside = np.zeros(px.shape, bool)
    for i in range(len(poly)):
        ax, ay = poly[i - 1]
        bx, by = poly[i]
        spans = ((ay <= py) & (py < by)) | ((by <= py) & (py < ay))
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = ax + (py - ay) * (bx - ax) / (by - ay)
        inside ^= spans & (xc > px)
    return inside


def _brute_force(costs, ox, oy, res, fp, x, y, th):
    poly = transform_footprint(fp, x, y, th)
    cells = [(math.floor((px - ox) / res), math.floor((py - oy) / res)) for px, py in poly]
    h, w = costs.shape
    if any(not (0 <= cx < w and 0 <= cy < h) for cx, cy in cells):
        return -1
    best = 0
    for i in range(len(cells)):
        for cx, cy in _line(*cells[i - 1], *cells[i]):
            best = max(best, int(costs[cy, cx]))
    my, mx = np.mgrid[0:h, 0:w]
    inside = _inside(ox + (mx + 0.5) * res, oy + (my + 0.5) * res, poly)
    if inside.any():
        best = max(best, int(costs[inside].max()))
    return best


@pytest.mark.parametrize("shape", ["rect", "radius", "ell"])
def test_footprint_cost_matches_brute_force_on_random_poses(shape):
    rng = np.random.default_rng(7)
    fp = {"rect": make_footprint(RECT), "radius": make_footprint(None, 0.3),
          "ell": make_footprint(ELL, footprint_padding=0.0)}[shape]
    res, ox, oy = 0.05, -1.0, 0.5
    h, w = 40, 48
    for trial in range(150):
        # sparse random costs so that the max comes from a specific cell, sometimes inside only
        costs = np.zeros((h, w), np.uint8)
        k = rng.integers(1, 6)
        costs[rng.integers(0, h, k), rng.integers(0, w, k)] = rng.integers(1, 256, k)
        x = ox + rng.uniform(-0.2, w * res + 0.2)
        y = oy + rng.uniform(-0.2, h * res + 0.2)
        th = rng.uniform(-math.pi, math.pi)
        expected = _brute_force(costs, ox, oy, res, fp, x, y, th)
        got = footprint_cost(costs, ox, oy, res, fp, x, y, th)
        assert got == expected, (trial, x, y, th)


def test_footprint_cost_sees_an_obstacle_strictly_inside():
    fp = make_footprint(RECT, footprint_padding=0.0)
    costs = np.zeros((100, 100), np.uint8)
    costs[50, 50] = 254  # world (2.525, 2.525) with res 0.05
    assert footprint_cost(costs, 0.0, 0.0, 0.05, fp, 2.5, 2.5, 0.0) == 254
    assert footprint_cost(costs, 0.0, 0.0, 0.05, fp, 2.5, 2.5, 1.0) == 254
    assert footprint_cost(costs, 0.0, 0.0, 0.05, fp, 3.5, 2.5, 0.0) == 0
    assert footprint_cost(costs, 0.0, 0.0, 0.05, fp, 0.1, 2.5, 0.0) == -1
