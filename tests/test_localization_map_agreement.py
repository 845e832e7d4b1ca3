"""navcore.localization.map_agreement on synthetic maps: the end-point distance against a
brute-force search over all occupied cells, and the scan-to-map fit recovering a known pose."""

from __future__ import annotations

import math

import numpy as np

from navcore.localization.map_agreement import best_fit_poses, endpoint_distances
from navcore.maps import OCCUPIED, OccupancyGrid
from navcore.raycast import cast_rays
from navcore.synthetic_maps import office_map
from navcore.types import Pose2D

GRID = office_map(240, seed=3)  # 12 m x 12 m, 6 m rooms, desks
BEARINGS = -math.pi / 2 + math.pi / 180 * np.arange(180)  # the CARMEN convention


def scans_at(grid: OccupancyGrid, poses: np.ndarray, rmax: float = 12.0) -> np.ndarray:
    """Scans whose end points lie half a cell inside the wall: where a grid built from end points
    (the real maps) has the centres of its occupied cells; the ray caster stops at the face."""
    occ = np.ascontiguousarray(grid.data == OCCUPIED).astype(np.uint8)
    r = np.stack([cast_rays(occ, grid.origin.x, grid.origin.y, grid.resolution, p[0], p[1],
                            BEARINGS + p[2], rmax) for p in poses])
    return np.where(r < rmax, r + 0.5 * grid.resolution, rmax)


def test_endpoint_distances_match_a_brute_force_search_on_random_points() -> None:
    rng = np.random.default_rng(5)
    g = OccupancyGrid(GRID.data, GRID.resolution, Pose2D(-3.0, 2.0, 0.4))  # origin yaw too
    poses = np.c_[rng.uniform(-2, 8, 40), rng.uniform(2, 12, 40), rng.uniform(-3, 3, 40)]
    ranges = rng.uniform(0.1, 4.0, (40, 180))
    ranges[:, ::7] = 30.0  # no return: no end point
    got = endpoint_distances(g, poses, ranges, BEARINGS, 30.0, search=1.0)
    occ_y, occ_x = np.nonzero(g.data == OCCUPIED)
    lx, ly = (occ_x + 0.5) * g.resolution, (occ_y + 0.5) * g.resolution
    c, s = math.cos(0.4), math.sin(0.4)
    cx, cy = -3.0 + c * lx - s * ly, 2.0 + s * lx + c * ly  # occupied cell centres, world
    a = poses[:, 2:3] + BEARINGS
    keep = ranges < 30.0
    ex = (poses[:, 0:1] + ranges * np.cos(a))[keep]
    ey = (poses[:, 1:2] + ranges * np.sin(a))[keep]
    want = np.sqrt(((ex[:, None] - cx) ** 2 + (ey[:, None] - cy) ** 2).min(axis=1))
    assert got.shape == want.shape
    # the window search is exact within its reach; beyond it the answer is the reach
    near = want < 0.95
    assert np.allclose(got[near], want[near], atol=1e-9)
    assert np.all(got[~near] >= 0.95 - 1e-9) and np.all(got <= 1.0 + 1e-9)


def test_scans_cast_from_a_pose_fit_back_to_it_from_a_displaced_start() -> None:
    rng = np.random.default_rng(2)
    true = np.array([[3.1, 2.7, 0.3], [8.6, 9.2, -2.0], [4.5, 4.5, -2.4], [8.0, 8.0, 2.9]])
    ranges = scans_at(GRID, true)
    start = true + np.c_[rng.uniform(-0.3, 0.3, (4, 2)), rng.uniform(-0.05, 0.05, 4)]
    fit = best_fit_poses(GRID, start, ranges, BEARINGS, 12.0)
    # measured: within 1.7 cm and 0.2 degrees (the map is quantised to 5 cm cells)
    assert np.all(np.hypot(*(fit[:, :2] - true[:, :2]).T) < 0.03)
    assert np.all(np.abs((fit[:, 2] - true[:, 2] + math.pi) % (2 * math.pi) - math.pi)
                  < math.radians(0.5))
    # and the cast end points lie on the walls: within a cell centre's reach
    d = endpoint_distances(GRID, true, ranges, BEARINGS, 12.0)
    assert np.median(d) < 0.03 and np.percentile(d, 95) < 0.04
