"""The observed-space memory (navcore.costmap.observed_space): the kernels against plain
references, and the motion recoveries that rely on it, tick by tick in scripted worlds (a grid
world, a 240-degree laser cast on it, a costmap that a clear empties)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from py_trees.blackboard import Client
from py_trees.common import Access, Status

from behaviors.base import make
from behaviors.testing import FakeCostmap, ScriptedWorld
from navcore.costmap.cost_values import LETHAL_OBSTACLE
from navcore.costmap.costmap2d import _fill_convex_cells, shift_grid
from navcore.costmap.footprint import make_footprint
from navcore.costmap.obstacle_layer import raytrace_line
from navcore.costmap.observed_space import (NEVER, ObservedSpace, fan_angles, first_unobserved,
                                            free_body, stamp_scan)
from navcore.error_codes import BackUpError, DriveOnHeadingError, RecoveryError, SpinError
from navcore.raycast import _clip_to_grid, cast_rays
from navcore.types import LaserScan, Pose2D, Twist

RES = 0.05
RECT = [[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]]
ROUND = [[0.2 * math.cos(a), 0.2 * math.sin(a)] for a in np.linspace(0, 2 * math.pi, 16,
                                                                         endpoint=False)]
MOUNT = Pose2D(0.15, 0.0, 0.0)
S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING
_ns = itertools.count()


# --- plain references -------------------------------------------------------------------------
def ref_line(x0, y0, x1, y1):
    """Bresenham from (x0, y0) to (x1, y1), both ends included (costmap_2d raytraceLine)."""
    dx, dy = x1 - x0, y1 - y0
    sx, sy = (dx > 0) - (dx < 0), (dy > 0) - (dy < 0)
    adx, ady = abs(dx), abs(dy)
    cells, x, y = [], x0, y0
    major, minor = (adx, ady) if adx >= ady else (ady, adx)
    err = major // 2
    for _ in range(major):
        cells.append((x, y))
        err += minor
        if adx >= ady:
            x += sx
            if err >= major:
                y += sy
                err -= major
        else:
            y += sy
            if err >= major:
                x += sx
                err -= major
    cells.append((x, y))
    return cells


def ref_stamp(shape, ox, oy, angles, ranges, rmin, rmax, now):
    """Walk each beam in small steps to find where it leaves the grid, then stamp as
    ``stamp_scan`` specifies."""
    h, w = shape
    free, occ = np.full(shape, NEVER), np.full(shape, NEVER)
    gx, gy = ox / RES, oy / RES
    hits = []
    for a, r in zip(angles, ranges):
        if math.isnan(r) or r < rmin:
            continue
        hit = r < rmax
        t_end = (r if hit else rmax) / RES
        dx, dy = math.cos(a), math.sin(a)
        # exit parameter of the grid rectangle
        t1 = t_end
        for g, d, n in ((gx, dx, w), (gy, dy, h)):
            if d > 0:
                t1 = min(t1, (n - g) / d)
            elif d < 0:
                t1 = min(t1, -g / d)
        inside = hit and t1 >= t_end
        t = t_end + 1e-6 if inside else t1 - 1e-9
        x1 = min(max(math.floor(gx + t * dx), 0), w - 1)
        y1 = min(max(math.floor(gy + t * dy), 0), h - 1)
        for cx, cy in ref_line(int(gx), int(gy), x1, y1):
            free[cy, cx] = now
        if inside:
            hits.append((x1, y1))
    for cx, cy in hits:
        occ[cy, cx] = now
    return free, occ


def ref_needed(poly, start_poly, i, j, n=40):
    """Whether the footprint ``poly`` covers part of cell (i, j) outside ``start_poly`` (both in
    cell units), by sampling the cell on an n x n grid of points (exact away from edges)."""
    def inside(p, x, y):
        k = len(p)
        return all((p[e][0] - p[e - 1][0]) * (y - p[e - 1][1])
                   - (p[e][1] - p[e - 1][1]) * (x - p[e - 1][0]) > 1e-9 for e in range(k))
    for a in range(n):
        for b in range(n):
            x, y = i + (a + 0.5) / n, j + (b + 0.5) / n
            if inside(poly, x, y) and not inside(start_poly, x, y):
                return True
    return False


def placed(fp, x, y, t):
    c, s = math.cos(t), math.sin(t)
    return [((x + c * a - s * b) / RES, (y + s * a + c * b) / RES) for a, b in fp]


# --- the kernels ---------------------------------------------------------------------------
def test_stamp_scan_matches_the_plain_reference():
    rng = np.random.default_rng(3)
    shape = (60, 80)
    ranges = rng.uniform(0.0, 3.0, 300)
    ranges[::7] = np.inf
    ranges[::11] = np.nan
    angles = rng.uniform(-math.pi, math.pi, 300)
    free, occ = np.full(shape, NEVER), np.full(shape, NEVER)
    used = stamp_scan(free, occ, 0.0, 0.0, RES, 1.83, 1.41, angles, ranges, 0.05, 2.5, 4.0)
    ref_free, ref_occ = ref_stamp(shape, 1.83, 1.41, angles, ranges, 0.05, 2.5, 4.0)
    assert used == int(np.sum(~np.isnan(ranges) & (ranges >= 0.05)))
    np.testing.assert_array_equal(free, ref_free)
    np.testing.assert_array_equal(occ, ref_occ)
    assert 0 < np.sum(np.isfinite(occ)) < np.sum(np.isfinite(free))
    # a laser off the grid stamps nothing
    assert stamp_scan(free, occ, 0.0, 0.0, RES, -1.0, 1.0, angles, ranges, 0.05, 2.5, 5.0) == 0


def raytrace_stamp(free, occupied, origin_x, origin_y, resolution, ox, oy, angles, ranges,
                   range_min, range_max, now):
    """``stamp_scan`` as it was before the flat two-beam walk: per beam the same clip and end
    cell, then the obstacle layer's ``raytrace_line`` on the 2-D grid (plain Python around it)."""
    h, w = free.shape
    gx = (ox - origin_x) / resolution
    gy = (oy - origin_y) / resolution
    if not (0.0 <= gx < w and 0.0 <= gy < h):
        return 0
    x0, y0 = int(gx), int(gy)
    n = 0
    for a, r in zip(angles, ranges):
        r = float(r)
        if not r >= range_min:
            continue
        hit = r < range_max
        length = r if hit else range_max
        dx, dy = math.cos(a), math.sin(a)
        t_end = length / resolution
        t0, t1 = _clip_to_grid(gx, gy, dx, dy, w, h, t_end)
        if t0 > t1:
            continue
        inside = hit and t1 >= t_end
        t = t_end + 1e-6 if inside else t1 - 1e-9
        x1 = min(max(int(math.floor(gx + t * dx)), 0), w - 1)
        y1 = min(max(int(math.floor(gy + t * dy)), 0), h - 1)
        raytrace_line(free, x0, y0, x1, y1, w + h, now)
        if inside:
            occupied[y1, x1] = now
        n += 1
    return n


def test_stamp_scan_stamps_the_cells_the_per_beam_raytrace_stamped():
    # grids down to one cell, lasers on cell corners, on the grid's edges and off it, beams
    # along the axes and diagonals, readings NaN / inf / negative / at the limits
    rng = np.random.default_rng(17)
    compass = np.arange(-8, 9) * (math.pi / 4)
    for case in range(40):
        h, w = [(1, 1), (1, 9), (9, 1), (2, 3), (23, 31), (40, 64)][case % 6]
        res = float(rng.choice([RES, 0.1, 0.031]))
        ox0, oy0 = rng.uniform(-2.0, 2.0, 2)
        where = case % 4
        if where == 0:      # anywhere near the grid, on it or not
            gx, gy = rng.uniform(-0.2, 1.2) * w, rng.uniform(-0.2, 1.2) * h
        elif where == 1:    # a cell corner
            gx, gy = float(rng.integers(0, w)), float(rng.integers(0, h))
        elif where == 2:    # the low and high edges
            gx, gy = float(rng.choice([0.0, w - 1e-9])), float(rng.choice([0.0, h - 1e-9]))
        else:
            gx, gy = rng.uniform(0, w), rng.uniform(0, h)
        lx, ly = ox0 + gx * res, oy0 + gy * res
        n = int(rng.integers(0, 90))
        angles = np.where(rng.random(n) < 0.3, rng.choice(compass, n), rng.uniform(-7, 7, n))
        ranges = rng.uniform(-0.1, 1.5 * max(h, w) * res, n)
        pick = rng.random(n)
        ranges[pick < 0.1] = np.nan
        ranges[(pick >= 0.1) & (pick < 0.2)] = np.inf
        ranges[(pick >= 0.2) & (pick < 0.25)] = 2.5
        ranges[(pick >= 0.25) & (pick < 0.3)] = 0.0
        rmin = float(rng.choice([0.0, 0.05, -1.0]))
        free = np.where(rng.random((h, w)) < 0.5, rng.uniform(0, 3, (h, w)), NEVER)
        occ = np.where(rng.random((h, w)) < 0.2, rng.uniform(0, 3, (h, w)), NEVER)
        ref_f, ref_o = free.copy(), occ.copy()
        want = raytrace_stamp(ref_f, ref_o, ox0, oy0, res, lx, ly, angles, ranges, rmin, 2.5, 4.0)
        got = stamp_scan(free, occ, ox0, oy0, res, lx, ly, angles, ranges, rmin, 2.5, 4.0)
        assert got == want, case
        np.testing.assert_array_equal(free, ref_f, err_msg=f"case {case}")
        np.testing.assert_array_equal(occ, ref_o, err_msg=f"case {case}")


def test_fan_angles_are_the_scans_angles_turned_bit_for_bit():
    rng = np.random.default_rng(5)
    for _ in range(30):
        n = int(rng.integers(1, 800))
        a0, inc = rng.uniform(-math.pi, 0.0), rng.uniform(1e-4, 2 * math.pi / n)
        theta = float(rng.choice([0.0, -0.0, math.pi, rng.uniform(-4.0, 4.0)]))
        scan = LaserScan(0.0, a0, a0 + (n - 1) * inc, inc, 0.0, 0.1, 0.02, 5.0, np.ones(n))
        want = scan.angles() + theta
        got = fan_angles(scan.angle_min, scan.angle_increment, theta, n)
        np.testing.assert_array_equal(got.view(np.int64), want.view(np.int64))


def test_update_stamps_what_the_window_move_the_raytrace_scan_and_the_body_stamp_stamp():
    # a robot drifting one way long enough that the window's store runs out, with steps back,
    # jumps further than the window, cycles without a scan and scans of every kind of reading
    rng = np.random.default_rng(23)
    padded = make_footprint(RECT, footprint_padding=0.03)
    space = ObservedSpace(RES, 50, 40, RECT, padded)
    parts = ObservedSpace(RES, 50, 40, RECT, padded)
    ref = ObservedSpace(RES, 50, 40, RECT, padded)
    pose = Pose2D(1.3, 1.0, 0.4)
    n = 61
    hits = moves = 0
    for step in range(90):
        jump = step in (30, 61)
        pose = Pose2D(pose.x + (rng.uniform(-4.0, 4.0) if jump else rng.uniform(-0.05, 0.1)),
                      pose.y + (rng.uniform(-4.0, 4.0) if jump else rng.uniform(0.0, 0.12)),
                      pose.theta + rng.uniform(-0.4, 0.4))
        now = 0.1 * step
        ranges = rng.uniform(0.0, 2.0, n).astype(np.float32)
        ranges[rng.random(n) < 0.1] = np.nan
        ranges[rng.random(n) < 0.1] = np.inf
        scan = None if step % 5 == 4 else LaserScan(now, -2.0, -2.0 + (n - 1) * 0.067, 0.067,
                                                     0.0, 0.1, 0.02, 1.8, ranges)
        lp = pose.compose(MOUNT)
        origin = (space.origin_x, space.origin_y)
        space.update(pose, scan, lp, now)
        moves += origin != (space.origin_x, space.origin_y)
        hits += int(np.sum(space.occupied == now))
        parts.recentre(pose.x, pose.y)
        ref.recentre(pose.x, pose.y)
        if scan is not None:
            parts.add_scan(scan, lp, now)
            raytrace_stamp(ref.free, ref.occupied, ref.origin_x, ref.origin_y, RES, lp.x, lp.y,
                           scan.angles() + lp.theta, np.asarray(scan.ranges, dtype=np.float64),
                           scan.range_min, scan.range_max, now)
        parts.add_body(pose, now)
        ref_free_body(ref.free, ref.occupied, ref.clearing_footprint, pose, ref.origin_x,
                      ref.origin_y, now)
        for got in (space, parts):
            assert (got.origin_x, got.origin_y) == (ref.origin_x, ref.origin_y)
            np.testing.assert_array_equal(got.free, ref.free, err_msg=f"step {step}")
            np.testing.assert_array_equal(got.occupied, ref.occupied, err_msg=f"step {step}")
    assert hits > 100 and moves > 60


def ref_free_body(free, occupied, fp, pose, ox, oy, now):
    """The body stamp with numpy: vertex cells, refused when one is off the grid, convex fill."""
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    xs = pose.x + c * fp[:, 0] - s * fp[:, 1]
    ys = pose.y + s * fp[:, 0] + c * fp[:, 1]
    with np.errstate(invalid="ignore"):  # a NaN pose: a cell far off the grid
        cells = np.column_stack([np.floor((xs - ox) / RES),
                                 np.floor((ys - oy) / RES)]).astype(np.int64)
    h, w = free.shape
    if np.any(cells < 0) or np.any(cells[:, 0] >= w) or np.any(cells[:, 1] >= h):
        return False
    _fill_convex_cells(free, cells, float(now))
    _fill_convex_cells(occupied, cells, NEVER)
    return True


def test_free_body_matches_the_numpy_reference():
    rng = np.random.default_rng(11)
    shape = (30, 40)
    outcomes = set()
    for fp in (np.array(RECT), np.array(ROUND)):
        for k in range(60):
            # inside the window, across its edges, or not a pose at all
            pose = Pose2D(rng.uniform(-0.3, 2.3), rng.uniform(-0.3, 1.8),
                          rng.uniform(-math.pi, math.pi))
            if k == 0:
                pose = Pose2D(math.nan, 1.0, 0.0)
            ox, oy = rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1)
            free = rng.uniform(0.0, 3.0, shape)
            occ = np.where(rng.random(shape) < 0.3, rng.uniform(0.0, 3.0, shape), NEVER)
            ref_f, ref_o = free.copy(), occ.copy()
            want = ref_free_body(ref_f, ref_o, fp, pose, ox, oy, 4.0)
            got = free_body(free, occ, fp, pose.x, pose.y, math.cos(pose.theta),
                            math.sin(pose.theta), ox, oy, RES, 4.0)
            assert got == want, (pose, ox, oy)
            np.testing.assert_array_equal(free, ref_f)
            np.testing.assert_array_equal(occ, ref_o)
            outcomes.add(got)
    assert outcomes == {True, False}


def test_first_unobserved_matches_the_sampled_reference():
    rng = np.random.default_rng(7)
    space = ObservedSpace(RES, 40, 40, RECT)
    fp = space.footprint
    for _ in range(25):
        start = Pose2D(1.0 + rng.uniform(-0.05, 0.05), 1.0 + rng.uniform(-0.05, 0.05),
                       rng.uniform(-math.pi, math.pi))
        pose = start.compose(Pose2D(rng.uniform(-0.12, 0.12), 0.0, rng.uniform(-0.6, 0.6)))
        # every cell observed free except one random cell near the robot
        space.free[:] = 5.0
        space.occupied[:] = NEVER
        ci, cj = int(rng.integers(10, 30)), int(rng.integers(10, 30))
        space.free[cj, ci] = NEVER
        got = first_unobserved(space.free, space.occupied, 0.0, 0.0, RES, fp, True,
                               np.array([[pose.x, pose.y, pose.theta]]),
                               np.array([start.x, start.y, start.theta]), 1.0, 0.0, False, 0.0)
        want = ref_needed(placed(fp, pose.x, pose.y, pose.theta),
                          placed(fp, start.x, start.y, start.theta), ci, cj)
        assert (got[0] == 0) == want, (start, pose, ci, cj)
        if want:
            assert got[1:] == (ci, cj)


def test_a_pose_that_stays_where_the_robot_stands_needs_nothing_observed():
    space = ObservedSpace(RES, 40, 40, RECT)
    space.recentre(1.0, 1.0)
    p = Pose2D(1.0, 1.0, 0.3)
    assert space.first_unobserved([p], p, 0.0) is None
    # a round robot turning on the spot sweeps nothing new; a rectangle does
    round_space = ObservedSpace(RES, 40, 40, ROUND)
    round_space.recentre(1.0, 1.0)
    turned = [Pose2D(1.0, 1.0, 0.3 + k * 0.2) for k in range(1, 10)]
    assert round_space.first_unobserved(turned, p, 0.0) is None
    assert space.first_unobserved(turned, p, 0.0) is not None


def test_a_footprint_grazing_a_cell_by_a_millimetre_does_not_cover_it():
    space = ObservedSpace(RES, 40, 40, RECT)
    space.free[:] = 5.0
    start = Pose2D(1.0, 1.0, 0.0)               # front edge at x 1.25, a cell face
    space.occupied[20, 25] = 6.0                # the cell x 1.25..1.30 ahead, seen occupied
    one_mm = [Pose2D(1.001, 1.0, 0.0)]
    three_mm = [Pose2D(1.003, 1.0, 0.0)]
    fp = space.footprint
    arr = lambda ps: np.array([[p.x, p.y, p.theta] for p in ps])  # noqa: E731
    s = np.array([start.x, start.y, start.theta])
    # the default depth tolerance (2 mm, navcore.motion.collision's slack) lets 1 mm through
    assert first_unobserved(space.free, space.occupied, 0.0, 0.0, RES, fp, True, arr(one_mm), s,
                            1.0, 0.0, True)[0] == -1
    assert first_unobserved(space.free, space.occupied, 0.0, 0.0, RES, fp, True, arr(three_mm),
                            s, 1.0, 0.0, True)[0] == 0
    assert first_unobserved(space.free, space.occupied, 0.0, 0.0, RES, fp, True, arr(one_mm), s,
                            1.0, 0.0, True, 0.0)[0] == 0


def test_the_window_rolls_with_the_robot_and_keeps_what_it_saw():
    space = ObservedSpace.around(RES, 4.0, 4.0, RECT)
    space.update(Pose2D(2.0, 2.0, 0.0), None, None, 1.0)
    assert (space.origin_x, space.origin_y) == (0.0, 0.0)
    seen = space.free_since(0.5)
    cells = np.argwhere(seen)
    assert len(cells) > 0
    space.update(Pose2D(2.52, 2.0, 0.0), None, None, 1.0)
    assert space.origin_x == pytest.approx(0.5)
    # the first body stamp is still there, 10 cells further left in the moved window
    moved = space.free_since(0.5)
    for j, i in cells:
        assert moved[j, i - 10]


def test_the_window_moves_as_shift_grid_moves_a_copy():
    # long runs one way (the store behind the window runs out and is recentred), steps back,
    # jumps further than the window; random stamps written between the moves
    rng = np.random.default_rng(9)
    space = ObservedSpace(RES, 12, 9, RECT)
    ref_free, ref_occ = space.free.copy(), space.occupied.copy()
    moves = [(1, 0)] * 30 + [(0, 1)] * 25 + [(-1, -1)] * 20 + [(0, -3), (5, 0), (-11, 0),
                                                               (12, 0), (0, 9), (3, -8)]
    moves += [tuple(int(v) for v in rng.integers(-4, 5, 2)) for _ in range(60)]
    space.recentre(0.3, 0.22)
    for dx, dy in moves:
        mask = rng.random(ref_free.shape) < 0.2
        stamps = rng.uniform(0.0, 9.0, ref_free.shape)
        for grid, ref in ((space.free, ref_free), (space.occupied, ref_occ)):
            grid[mask] = stamps[mask]
            ref[mask] = stamps[mask]
        x0, y0 = space.origin_x, space.origin_y
        space.recentre(x0 + (6 + dx) * RES + 0.01, y0 + (4.5 + dy) * RES + 0.01)
        assert (round((space.origin_x - x0) / RES), round((space.origin_y - y0) / RES)) == (dx, dy)
        ref_free, ref_occ = shift_grid(ref_free, dx, dy, NEVER), shift_grid(ref_occ, dx, dy, NEVER)
        np.testing.assert_array_equal(space.free, ref_free, err_msg=f"{(dx, dy)}")
        np.testing.assert_array_equal(space.occupied, ref_occ, err_msg=f"{(dx, dy)}")
        assert space.free.flags.c_contiguous and space.occupied.flags.c_contiguous


def scan_of(occ: np.ndarray, pose: Pose2D, fov: float = 4 * math.pi / 3, beams: int = 241,
            range_max: float = 5.6) -> tuple[LaserScan, Pose2D]:
    """A laser at MOUNT on the robot at ``pose``, cast on the world grid ``occ``."""
    lp = pose.compose(MOUNT)
    a = np.linspace(-fov / 2, fov / 2, beams)
    r = cast_rays(occ, 0.0, 0.0, RES, lp.x, lp.y, a + lp.theta, range_max)
    r = np.where(r >= range_max, np.inf, r)
    return LaserScan(0.0, float(a[0]), float(a[-1]), float(a[1] - a[0]), 0.0, 0.1, 0.02,
                     range_max, r), lp


def test_a_scan_sees_the_free_space_ahead_and_not_behind():
    occ = np.zeros((120, 120), np.uint8)
    occ[56:64, 30:36] = 1          # a box 1.2 m behind the robot
    occ[56:64, 100:106] = 1        # and one 2 m ahead
    space = ObservedSpace.around(RES, 6.0, 6.0, RECT)
    pose = Pose2D(3.0, 3.0, 0.0)
    scan, lp = scan_of(occ, pose)
    space.update(pose, scan, lp, 2.0)
    fresh = space.free_since(1.0)
    i = lambda x: int((x - space.origin_x) / RES)  # noqa: E731
    j = lambda y: int((y - space.origin_y) / RES)  # noqa: E731
    assert fresh[j(3.0), i(4.5)]                  # ahead: seen free
    assert not fresh[j(3.0), i(5.05)]             # the box ahead: seen occupied
    assert space.occupied[j(3.0), i(5.02)] == 2.0
    assert not fresh[j(3.0), i(2.4)]              # behind: never seen
    assert not fresh[j(3.0), i(1.6)] and space.occupied[j(3.0), i(1.6)] == NEVER


# --- the recoveries, tick by tick ------------------------------------------------------------
class GridWorld:
    """A scripted world: the true grid, a costmap (a copy of what the laser marked, which a
    clear can empty), the observed-space memory fed as Perception feeds it, and a node."""

    def __init__(self, occ: np.ndarray, pose: Pose2D, footprint=RECT):
        self.occ = occ
        self.costs = np.zeros_like(occ)
        cm = FakeCostmap(size_m=occ.shape[0] * RES, origin=0.0)
        cm.footprint = self._cost
        self.footprint = np.asarray(footprint, float)
        self.space = ObservedSpace.around(RES, 6.0, 6.0, footprint)
        self.world = ScriptedWorld(local_costmap=cm, global_costmap=cm)
        self.world.robot.teleport(pose)
        self.ns = f"/obs{next(_ns)}"
        self.bb = Client(name="obs", namespace=self.ns)
        self.bb.register_key("cmd_vel", access=Access.WRITE)

    def _cost(self, x, y, t):
        from navcore.costmap.footprint import footprint_cost
        return footprint_cost(self.costs, 0.0, 0.0, RES, self.footprint, x, y, t)

    def sense(self):
        pose = self.world.robot.pose()
        scan, lp = scan_of(self.occ, pose)
        self.space.update(pose, scan, lp, self.world.clock.now())

    def wait(self, seconds: float):
        self.world.clock.advance(seconds)

    def turn_to(self, theta: float):
        """Turn on the spot (teleported, as a scripted spin would end), sensing there."""
        p = self.world.robot.pose()
        self.world.robot.teleport(Pose2D(p.x, p.y, theta))
        self.sense()

    def node(self, node_type, **ports):
        comps = dict(self.world.components(), observed_space=self.space)
        n = make(node_type, namespace=self.ns, **ports)
        n.setup(**comps)
        return n

    def run(self, node, max_ticks=1000):
        for i in range(max_ticks):
            self.sense()
            self.bb.set("cmd_vel", Twist.zero())
            node.tick_once()
            if node.status != R:
                return node.status, i + 1
            self.world.step(self.bb.get("cmd_vel"))
        return node.status, max_ticks


def box_behind_world() -> np.ndarray:
    occ = np.zeros((120, 120), np.uint8)
    occ[54:66, 42:48] = 1   # x 2.1..2.4, y 2.7..3.3: 0.35 m behind the rear of a robot at x 3
    return occ


def test_backup_refuses_space_a_costmap_clear_erased_and_the_laser_never_saw():
    w = GridWorld(box_behind_world(), Pose2D(3.0, 3.0, 0.0))
    w.costs[54:66, 42:48] = LETHAL_OBSTACLE      # the costmap knew the box...
    w.costs[:] = 0                               # ...until a clear erased it
    node = w.node("BackUp", backup_dist=0.5, backup_speed=0.15, error_code_id="{code}")
    status, ticks = w.run(node)
    assert status == F and ticks == 1
    assert w.bb.get("cmd_vel") == Twist.zero()
    reader = Client(name="r", namespace=w.ns)
    reader.register_key("code", access=Access.READ)
    assert reader.get("code") == BackUpError.UNOBSERVED_SPACE
    assert w.world.robot.pose().x == pytest.approx(3.0)
    # without the check the same back-up would have driven into the box
    blind = w.node("BackUp", backup_dist=0.5, backup_speed=0.15, observed_within=0.0)
    w.run(blind)
    rear = w.world.robot.pose().x - 0.25
    assert rear < 2.4   # the rear edge went past the box's face


def test_backup_goes_into_space_seen_free_a_second_ago_and_stops_at_a_seen_box():
    occ = np.zeros((120, 120), np.uint8)
    w = GridWorld(occ, Pose2D(3.0, 3.0, 0.0))
    w.turn_to(math.pi)         # looks behind...
    w.wait(1.0)
    w.turn_to(0.0)             # ...and back: that was 1 s ago
    node = w.node("BackUp", backup_dist=0.4, backup_speed=0.15)
    status, _ = w.run(node)
    assert status == S
    assert w.world.robot.pose().x == pytest.approx(2.6, abs=0.01)
    # seen 20 s ago is too old for the default window (10 s)
    w2 = GridWorld(occ, Pose2D(3.0, 3.0, 0.0))
    w2.turn_to(math.pi)
    w2.wait(20.0)
    w2.turn_to(0.0)
    assert w2.run(w2.node("BackUp", backup_dist=0.4, backup_speed=0.15))[0] == F
    # a box seen behind (occupied), then erased from the costmap: refused before reaching it
    w3 = GridWorld(box_behind_world(), Pose2D(3.0, 3.0, 0.0))
    w3.turn_to(math.pi)
    w3.wait(1.0)
    w3.turn_to(0.0)
    status, _ = w3.run(w3.node("BackUp", backup_dist=0.5, backup_speed=0.15,
                               simulate_ahead_time=0.5))
    assert status == F
    assert 2.4 + 0.25 <= w3.world.robot.pose().x < 3.0   # moved back, never into the box


def test_drive_on_heading_backwards_checks_and_forwards_sees_its_way():
    occ = np.zeros((120, 120), np.uint8)
    w = GridWorld(occ, Pose2D(3.0, 3.0, 0.0))
    back = w.node("DriveOnHeading", dist_to_travel=-0.3, speed=-0.15,
                  error_code_id="{code}")
    assert w.run(back)[0] == F
    reader = Client(name="r", namespace=w.ns)
    reader.register_key("code", access=Access.READ)
    assert reader.get("code") == DriveOnHeadingError.UNOBSERVED_SPACE
    ahead = w.node("DriveOnHeading", dist_to_travel=0.3, speed=0.15)
    assert w.run(ahead)[0] == S
    assert w.world.robot.pose().x == pytest.approx(3.3, abs=0.01)


def test_spin_sweeps_unseen_space_but_never_space_last_seen_occupied():
    occ = np.zeros((120, 120), np.uint8)
    w = GridWorld(occ, Pose2D(3.0, 3.0, 0.0))
    # strict: the corners of a rectangle sweep the unseen space beside its rear
    status, _ = w.run(w.node("Spin", spin_dist=1.57, allow_unknown=False,
                             error_code_id="{code}"))
    reader = Client(name="r", namespace=w.ns)
    reader.register_key("code", access=Access.READ)
    assert status == F and reader.get("code") == SpinError.UNOBSERVED_SPACE
    # by default a turn may sweep never-seen space (turning is how it looks behind)
    assert w.run(w.node("Spin", spin_dist=1.57))[0] == S
    # and a round robot sweeps nothing new even strictly
    r = GridWorld(occ, Pose2D(3.0, 3.0, 0.0), footprint=ROUND)
    assert r.run(r.node("Spin", spin_dist=1.57, allow_unknown=False))[0] == S
    # a post beside the rear corner, seen (occupied) when the robot faced the other way, then
    # erased from the costmap by a clear: the turn that would sweep into it is refused
    post = np.zeros((120, 120), np.uint8)
    post[65:68, 53:56] = 1          # x 2.65..2.8, y 3.25..3.4: 3 cm beside the rear-left corner
    p = GridWorld(post, Pose2D(3.0, 3.0, 0.0))
    p.turn_to(math.pi)
    p.wait(30.0)
    p.turn_to(0.0)
    status, _ = p.run(p.node("Spin", spin_dist=-1.57, error_code_id="{code}"))
    reader = Client(name="r2", namespace=p.ns)
    reader.register_key("code", access=Access.READ)
    assert status == F and reader.get("code") == SpinError.UNOBSERVED_SPACE
    assert abs(p.world.robot.pose().theta) < 0.5


def test_back_off_follows_the_trail_it_drove_but_not_a_trail_gone_stale():
    occ = np.zeros((120, 120), np.uint8)
    w = GridWorld(occ, Pose2D(2.0, 3.0, 0.0))
    trail = []
    for k in range(21):        # drive 1 m forward, 0.05 m a tick, sensing all the way
        w.world.robot.teleport(Pose2D(2.0 + 0.05 * k, 3.0, 0.0))
        w.sense()
        trail.append(w.world.robot.pose())
        w.wait(0.1)
    w.bb.register_key("pose_history", access=Access.WRITE)
    w.bb.set("pose_history", trail)
    status, _ = w.run(w.node("BackOffToPreviousPose", distance=0.5, speed=0.1))
    assert status == S and w.world.robot.pose().x == pytest.approx(2.5, abs=0.1)
    w.wait(30.0)               # 30 s later the trail behind is no longer "recent"
    w.sense()
    w.bb.set("pose_history", trail[:12])
    status, _ = w.run(w.node("BackOffToPreviousPose", distance=0.3, speed=0.1,
                             error_code_id="{code}"))
    reader = Client(name="r", namespace=w.ns)
    reader.register_key("code", access=Access.READ)
    assert status == F and reader.get("code") == RecoveryError.UNOBSERVED_SPACE


def test_follow_path_turns_instead_of_reversing_blind_and_reverses_where_it_has_looked():
    from behaviors.testing import ReversingController, straight_path
    occ = box_behind_world()
    w = GridWorld(occ, Pose2D(3.0, 3.0, 0.0))
    w.world.controller = ReversingController()
    w.bb.register_key("path", access=Access.WRITE)
    w.bb.set("path", straight_path(Pose2D(3.0, 3.0, math.pi), Pose2D(1.0, 3.0, math.pi)))
    node = w.node("FollowPath")
    cmds = []
    for _ in range(30):     # (later this crude planner dithers back over where it has been)
        w.sense()
        w.bb.set("cmd_vel", Twist.zero())
        node.tick_once()
        cmds.append(w.bb.get("cmd_vel"))
        w.world.step(cmds[-1])
    # never backwards: it turned on the spot toward the path (its laser now sees the box) until
    # the planner's own command was forwards (the goal no longer behind)
    assert all(c.vx >= 0.0 for c in cmds) and cmds[0].wz != 0.0 and cmds[0].vx == 0.0
    first = next(i for i, c in enumerate(cmds) if c.vx > 0.0)
    assert all(c.vx == 0.0 and c.wz > 0.0 for c in cmds[:first])
    assert w.world.robot.trajectory[first].theta >= math.pi / 2 - 0.1
    assert w.space.occupied[int((3.0 - w.space.origin_y) / RES),
                            int((2.37 - w.space.origin_x) / RES)] > 0.0   # the box face
    # space just seen free (a look behind a second ago, no box): the same planner may reverse
    w2 = GridWorld(np.zeros((120, 120), np.uint8), Pose2D(3.0, 3.0, 0.0))
    w2.world.controller = ReversingController()
    w2.turn_to(math.pi)
    w2.wait(1.0)
    w2.turn_to(0.0)
    w2.bb.register_key("path", access=Access.WRITE)
    w2.bb.set("path", straight_path(Pose2D(3.0, 3.0, math.pi), Pose2D(2.0, 3.0, math.pi)))
    node2 = w2.node("FollowPath")
    w2.sense()
    w2.bb.set("cmd_vel", Twist.zero())
    node2.tick_once()
    assert w2.bb.get("cmd_vel").vx == pytest.approx(-0.3)
