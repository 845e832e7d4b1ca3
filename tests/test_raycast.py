"""navcore.raycast: exact grid traversal against analytic distances and a brute-force march."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navcore.raycast import (cast_dir_clear, cast_fan_clear, cast_ray, cast_rays,
                             cast_rays_clear, cast_rays_shapes,
                             clearance_field, distance_field, ray_circle, ray_segment,
                             segment_blocked)

RES = 0.05


def box_world(n: int = 100, wall: int = 2) -> np.ndarray:
    """n x n cells with a ``wall``-cell border: inner faces at wall*RES and (n-wall)*RES."""
    occ = np.zeros((n, n), np.uint8)
    occ[:wall, :] = 1
    occ[-wall:, :] = 1
    occ[:, :wall] = 1
    occ[:, -wall:] = 1
    return occ


def analytic_box_range(x: float, y: float, a: float, lo: float, hi: float) -> float:
    """Distance from (x, y) inside the square [lo, hi]^2 to its boundary along angle a."""
    dx, dy = math.cos(a), math.sin(a)
    ts = []
    if dx > 1e-12:
        ts.append((hi - x) / dx)
    if dx < -1e-12:
        ts.append((lo - x) / dx)
    if dy > 1e-12:
        ts.append((hi - y) / dy)
    if dy < -1e-12:
        ts.append((lo - y) / dy)
    return min(ts)


def test_box_world_ranges_are_exact_to_the_cell_faces():
    occ = box_world()
    rng = np.random.default_rng(1)
    lo, hi = 2 * RES, 98 * RES
    for _ in range(50):
        x, y = rng.uniform(lo + 0.01, hi - 0.01, size=2)
        angles = rng.uniform(-math.pi, math.pi, size=30)
        got = cast_rays(occ, 0.0, 0.0, RES, x, y, angles, 20.0)
        want = [analytic_box_range(x, y, a, lo, hi) for a in angles]
        np.testing.assert_allclose(got, want, atol=1e-9)


def test_origin_offset_and_axis_aligned_rays():
    occ = box_world()
    ox, oy = -2.5, -2.5  # the box spans [-2.4, 2.4] inside
    for a, want in [(0.0, 2.4), (math.pi / 2, 2.4), (math.pi, 2.4), (-math.pi / 2, 2.4)]:
        assert cast_ray(occ, ox, oy, RES, 0.0, 0.0, a, 10.0) == pytest.approx(want, abs=1e-9)
    # from (1, 0): east 1.4, west 3.4
    assert cast_ray(occ, ox, oy, RES, 1.0, 0.0, 0.0, 10.0) == pytest.approx(1.4, abs=1e-9)
    assert cast_ray(occ, ox, oy, RES, 1.0, 0.0, math.pi, 10.0) == pytest.approx(3.4, abs=1e-9)


def test_max_range_and_leaving_the_grid():
    occ = box_world()
    x = y = 2.5
    assert cast_ray(occ, 0.0, 0.0, RES, x, y, 0.3, 1.0) == 1.0  # wall is 2.4+ m away
    free = np.zeros((40, 40), np.uint8)
    assert cast_ray(free, 0.0, 0.0, RES, 1.0, 1.0, 0.7, 30.0) == 30.0
    # a ray from outside the grid that crosses a blocked cell finds it
    free[20, 20] = 1
    d = cast_ray(free, 0.0, 0.0, RES, -1.0, 20.5 * RES, 0.0, 30.0)
    assert d == pytest.approx(1.0 + 20 * RES, abs=1e-9)
    # ... and one that points away from the grid does not
    assert cast_ray(free, 0.0, 0.0, RES, -1.0, 1.0, math.pi, 30.0) == 30.0


def test_start_inside_blocked_cell_is_zero():
    occ = box_world()
    assert cast_ray(occ, 0.0, 0.0, RES, 0.01, 2.0, 0.0, 10.0) == 0.0


def test_matches_a_fine_brute_force_march_in_clutter():
    rng = np.random.default_rng(7)
    occ = (rng.random((60, 80)) < 0.08).astype(np.uint8)
    occ[30, 40] = 0
    x, y = 40.5 * RES, 30.5 * RES
    angles = np.linspace(-math.pi, math.pi, 181)
    got = cast_rays(occ, 0.0, 0.0, RES, x, y, angles, 5.0)
    step = 1e-4
    ts = np.arange(0.0, 5.0, step)
    for a, g in zip(angles, got):
        mx = np.floor((x + ts * math.cos(a)) / RES).astype(int)
        my = np.floor((y + ts * math.sin(a)) / RES).astype(int)
        inside = (mx >= 0) & (mx < 80) & (my >= 0) & (my < 60)
        hit = np.zeros(len(ts), bool)
        hit[inside] = occ[my[inside], mx[inside]] != 0
        # a ray that leaves the grid hits nothing beyond it
        stop = np.argmax(hit | ~inside) if np.any(hit | ~inside) else len(ts)
        want = ts[stop] if stop < len(ts) and hit[stop] else 5.0
        # the march overshoots the face by less than one step
        assert g <= want + 1e-9
        assert want - g < step + 1e-9


def test_segment_blocked():
    occ = np.zeros((20, 20), np.uint8)
    occ[10, 5] = 1  # cell spans x [0.25, 0.30), y [0.5, 0.55)
    assert segment_blocked(occ, 0.0, 0.0, RES, 0.0, 0.52, 0.5, 0.52)
    assert not segment_blocked(occ, 0.0, 0.0, RES, 0.0, 0.45, 0.5, 0.45)
    assert not segment_blocked(occ, 0.0, 0.0, RES, 0.0, 0.52, 0.2, 0.52)  # stops short
    assert segment_blocked(occ, 0.0, 0.0, RES, 0.27, 0.52, 0.27, 0.52)  # a point in the cell


def test_circle_and_segment_shapes():
    # circle of radius 1 at (5, 0): from the origin along +x the rim is at 4
    assert ray_circle(0.0, 0.0, 1.0, 0.0, 5.0, 0.0, 1.0) == pytest.approx(4.0)
    assert ray_circle(0.0, 0.0, -1.0, 0.0, 5.0, 0.0, 1.0) == math.inf
    a = math.atan2(0.5, 5.0)
    want = 5.0 * math.cos(a) - math.sqrt(1.0 - (5.0 * math.sin(a)) ** 2)
    assert ray_circle(0.0, 0.0, math.cos(a), math.sin(a), 5.0, 0.0, 1.0) == pytest.approx(want)
    assert ray_segment(0.0, 0.0, 1.0, 0.0, 3.0, -1.0, 3.0, 1.0) == pytest.approx(3.0)
    assert ray_segment(0.0, 0.0, 1.0, 0.0, 3.0, 0.5, 3.0, 1.0) == math.inf
    angles = np.array([0.0, math.pi / 2, math.pi])
    ranges = np.full(3, 10.0)
    cast_rays_shapes(0.0, 0.0, angles, ranges, np.array([[5.0, 0.0, 1.0]]),
                     np.array([[-1.0, 2.0, 1.0, 2.0]]))
    np.testing.assert_allclose(ranges, [4.0, 2.0, 10.0])


def test_distance_field_matches_brute_force():
    rng = np.random.default_rng(3)
    occ = (rng.random((30, 40)) < 0.05).astype(np.uint8)
    d = distance_field(occ)
    bys, bxs = np.nonzero(occ)
    yy, xx = np.mgrid[0:30, 0:40]
    want = np.sqrt(((yy[..., None] - bys) ** 2 + (xx[..., None] - bxs) ** 2).min(-1))
    np.testing.assert_allclose(d, want, atol=1e-5)
    assert distance_field(np.zeros((3, 4), np.uint8)).min() >= 1e8  # nothing blocked


@pytest.mark.parametrize("density", [0.002, 0.02, 0.1])
def test_clearance_leaping_gives_the_exact_same_ranges(density):
    rng = np.random.default_rng(11)
    occ = (rng.random((150, 200)) < density).astype(np.uint8)
    occ[40:42, 20:180] = 1  # a long wall to graze along
    clear = clearance_field(occ)
    assert np.all((clear == 0) == (occ != 0))
    angles = rng.uniform(-math.pi, math.pi, 400)
    for _ in range(20):
        x, y = rng.uniform(-1.0, 11.0), rng.uniform(-1.0, 8.5)  # some start off the grid
        want = cast_rays(occ, -0.2, 0.3, RES, x, y, angles, 8.0)
        got = cast_rays_clear(clear, -0.2, 0.3, RES, x, y, angles, 8.0)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)


def _fan_dirs(a0: float, n: int, span: float) -> np.ndarray:
    a = a0 + np.linspace(0.0, span, n)
    return np.stack([np.cos(a), np.sin(a)], axis=1)


def _check_fan_against_exact(occ: np.ndarray, rng: np.random.Generator, starts: int,
                             t_end: float) -> None:
    """cast_fan_clear (beams sliding on their predecessor's clear disks) against the exact cell
    walk per beam: equal to rounding in float64 and identical once scaled to float32 metres,
    which is what the laser publishes."""
    clear = clearance_field(occ)
    h, w = occ.shape
    for k in range(starts):
        gx, gy = rng.uniform(-3.0, w + 3.0), rng.uniform(-3.0, h + 3.0)  # a few off the grid
        n = int(rng.choice([3, 181, 720, 1440]))
        dirs = _fan_dirs(rng.uniform(-math.pi, math.pi), n, rng.choice([0.3, 4.71, 2 * math.pi]))
        got = np.empty(n)
        cast_fan_clear(clear, gx, gy, dirs, t_end, got)
        want = np.array([cast_ray(occ, 0.0, 0.0, 1.0, gx, gy, math.atan2(d[1], d[0]), t_end)
                         for d in dirs])
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)
        single = np.array([cast_dir_clear(clear, gx, gy, d[0], d[1], t_end) for d in dirs])
        assert np.array_equal((got * RES).astype(np.float32), (single * RES).astype(np.float32))


@pytest.mark.parametrize("density", [0.0, 0.002, 0.02, 0.1])
def test_fan_casting_gives_the_exact_ranges_in_clutter(density):
    rng = np.random.default_rng(5)
    occ = (rng.random((150, 200)) < density).astype(np.uint8)
    occ[40:42, 20:180] = 1  # a long wall to graze along
    occ[60:140, 100] = 1  # a thin one
    _check_fan_against_exact(occ, rng, 25, 160.0)


def test_fan_casting_gives_the_exact_ranges_in_a_box_and_around_a_disc():
    rng = np.random.default_rng(6)
    occ = box_world(160)
    yy, xx = np.mgrid[0:160, 0:160]
    occ[(xx - 100.5) ** 2 + (yy - 70.5) ** 2 <= 15.0 ** 2] = 1
    _check_fan_against_exact(occ, rng, 25, 400.0)


@pytest.mark.parametrize("name", ["willow_garage", "intel_lab"])
def test_fan_casting_gives_the_exact_ranges_on_real_maps(shared_data, name):
    from navcore.maps import load_map
    from tests.conftest import REAL_MAPS
    grid = load_map(shared_data / "maps" / REAL_MAPS[name])
    occ = np.ascontiguousarray((grid.data >= 65) | (grid.data < 0), dtype=np.uint8)
    rng = np.random.default_rng(7)
    clear = clearance_field(occ)
    free = np.argwhere(occ == 0)
    for r, c in free[rng.integers(0, len(free), 30)]:
        gx, gy = c + rng.random(), r + rng.random()
        dirs = _fan_dirs(rng.uniform(-math.pi, math.pi), 720, 4.71238898)
        got = np.empty(720)
        cast_fan_clear(clear, gx, gy, dirs, 600.0, got)
        single = np.array([cast_dir_clear(clear, gx, gy, d[0], d[1], 600.0) for d in dirs])
        np.testing.assert_allclose(got, single, rtol=0, atol=1e-9)
        assert np.array_equal((got * 0.05).astype(np.float32),
                              (single * 0.05).astype(np.float32))
        want = np.array([cast_ray(occ, 0.0, 0.0, 1.0, gx, gy, math.atan2(d[1], d[0]), 600.0)
                         for d in dirs[::9]])
        np.testing.assert_allclose(got[::9], want, rtol=0, atol=1e-9)


def test_fan_casting_from_cell_faces_and_corners_along_the_axes():
    """Starts exactly on cell faces, corners and the grid's own edges, beams exactly along the
    axes (a zero direction component, faces met head-on), some leaving the grid at once: the
    clearance casts still give the exact walk's ranges. (Diagonals only from half-cell offsets:
    a ray through a lattice corner touches the two side cells in one point, which the exact
    walk's tie rule counts as a hit and a clear disk may not.)"""
    rng = np.random.default_rng(8)
    occ = (rng.random((60, 80)) < 0.03).astype(np.uint8)
    occ[20, 10:70] = 1
    # near the right edge, so that a beam leaving there walks cell by cell; one cell past the
    # end of row 30 in memory is the start of row 31: blocked, to catch a missed bounds test
    occ[32, 76] = 1
    occ[31, 0] = 1
    clear = clearance_field(occ)
    h, w = occ.shape
    s = math.sqrt(0.5)
    axes = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 0.0]]
    diagonals = [[s, s], [-s, s], [-s, -s], [s, -s]]
    starts = [(0.0, 0.0), (float(w) - 1e-9, 5.0), (0.0, 30.0), (40.0, 21.0), (40.0, 19.0),
              (12.0, 45.0), (79.0, 59.0), (7.0, 0.0), (33.5, 50.0), (60.0, 7.5), (20.5, 0.0),
              (70.0, 30.5), (74.5, 30.0)]
    checked = 0
    for gx, gy in starts:
        if occ[min(int(gy), h - 1), min(int(gx), w - 1)]:
            continue
        half = (gx - gy) % 1.0 == 0.5
        dirs = np.array(axes + diagonals if half else axes)
        got = np.empty(len(dirs))
        cast_fan_clear(clear, gx, gy, dirs, 200.0, got)
        want = [cast_ray(occ, 0.0, 0.0, 1.0, gx, gy, math.atan2(d[1], d[0]), 200.0)
                for d in dirs]
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)
        single = [cast_dir_clear(clear, gx, gy, d[0], d[1], 200.0) for d in dirs]
        np.testing.assert_allclose(single, want, rtol=0, atol=1e-9)
        checked += len(dirs)
    assert checked >= 50
