"""How well recorded scans agree with a map at given poses: the yardstick for a localiser's
accuracy against a reference trajectory that did not come from that map.

``endpoint_distances`` is the registration statistic of ``shared/data/SOURCES.md`` (distance of
every scan end point to the nearest occupied cell). ``best_fit_poses`` moves each pose to where
its own scan fits the map best (a brute-force scan-to-map match): where the map and the reference
trajectory disagree, these poses are what a map-based localiser can reach at best.

Poses are *laser* poses (N, 3) in the map frame, ``ranges`` (N, B), ``bearings`` (B,); readings at
or beyond ``max_range`` (and NaN) carry no end point.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.localization.distance_field import distance_field
from navcore.maps import OCCUPIED, OccupancyGrid


def _geometry(grid: OccupancyGrid) -> np.ndarray:
    o = grid.origin
    return np.array([o.x, o.y, math.cos(o.theta), math.sin(o.theta), grid.resolution])


@njit(cache=True, inline="always")
def _to_cells(wx: float, wy: float, geom: np.ndarray) -> tuple[float, float]:
    """Continuous cell coordinates of a world point (cell (i, j) spans [i, i+1) x [j, j+1))."""
    dx = wx - geom[0]
    dy = wy - geom[1]
    return (geom[2] * dx + geom[3] * dy) / geom[4], (-geom[3] * dx + geom[2] * dy) / geom[4]


@njit(cache=True)
def _endpoint_distances(occ: np.ndarray, geom: np.ndarray, poses: np.ndarray,
                        ranges: np.ndarray, bearings: np.ndarray, max_range: float,
                        search: int) -> np.ndarray:
    h, w = occ.shape
    out = np.empty(ranges.shape[0] * ranges.shape[1])
    k = 0
    for i in range(poses.shape[0]):
        for j in range(ranges.shape[1]):
            r = ranges[i, j]
            if not r < max_range:
                continue
            a = poses[i, 2] + bearings[j]
            fx, fy = _to_cells(poses[i, 0] + r * math.cos(a), poses[i, 1] + r * math.sin(a),
                               geom)
            cx = int(math.floor(fx))
            cy = int(math.floor(fy))
            best = float(search * search)
            for y in range(max(cy - search, 0), min(cy + search + 1, h)):
                for x in range(max(cx - search, 0), min(cx + search + 1, w)):
                    if occ[y, x]:
                        d2 = (x + 0.5 - fx) ** 2 + (y + 0.5 - fy) ** 2
                        if d2 < best:
                            best = d2
            out[k] = math.sqrt(best) * geom[4]
            k += 1
    return out[:k]


def endpoint_distances(grid: OccupancyGrid, poses: np.ndarray, ranges: np.ndarray,
                       bearings: np.ndarray, max_range: float, search: float = 1.0
                       ) -> np.ndarray:
    """Distance (m) from every end point to the centre of the nearest occupied cell (exact),
    ``search`` (m) for end points with none that close."""
    return _endpoint_distances(np.ascontiguousarray(grid.data == OCCUPIED), _geometry(grid),
                               np.asarray(poses, np.float64),
                               np.asarray(ranges, np.float64), np.asarray(bearings, np.float64),
                               float(max_range), max(int(round(search / grid.resolution)), 1))


@njit(cache=True)
def _fit_cost(dist: np.ndarray, geom: np.ndarray, x: float, y: float, t: float,
              ranges: np.ndarray, bearings: np.ndarray, max_range: float, cap: float) -> float:
    """Sum of squared end-point distances, each capped at ``cap`` so that clutter that is not in
    the map cannot drag the fit; the distance field is interpolated bilinearly between cell
    centres so that the cost varies smoothly below one cell."""
    h, w = dist.shape
    s = 0.0
    for j in range(ranges.shape[0]):
        r = ranges[j]
        if not r < max_range:
            continue
        a = t + bearings[j]
        fx, fy = _to_cells(x + r * math.cos(a), y + r * math.sin(a), geom)
        fx -= 0.5
        fy -= 0.5
        ix = int(math.floor(fx))
        iy = int(math.floor(fy))
        if ix < 0 or iy < 0 or ix + 1 >= w or iy + 1 >= h:
            d = cap
        else:
            ax = fx - ix
            ay = fy - iy
            d = ((1 - ax) * (1 - ay) * dist[iy, ix] + ax * (1 - ay) * dist[iy, ix + 1]
                 + (1 - ax) * ay * dist[iy + 1, ix] + ax * ay * dist[iy + 1, ix + 1])
            d = min(d, cap)
        s += d * d
    return s


@njit(cache=True)
def _grid_search(dist: np.ndarray, geom: np.ndarray, pose: np.ndarray, ranges: np.ndarray,
                 bearings: np.ndarray, max_range: float, cap: float, radius: float,
                 step: float, angle: float, angle_step: float) -> np.ndarray:
    best = math.inf
    out = pose.copy()
    nr = int(round(radius / step))
    na = int(round(angle / angle_step))
    for i in range(-nr, nr + 1):
        for j in range(-nr, nr + 1):
            for k in range(-na, na + 1):
                x = pose[0] + i * step
                y = pose[1] + j * step
                t = pose[2] + k * angle_step
                c = _fit_cost(dist, geom, x, y, t, ranges, bearings, max_range, cap)
                if c < best:
                    best = c
                    out[0] = x
                    out[1] = y
                    out[2] = t
    return out


@njit(cache=True)
def _best_fits(dist: np.ndarray, geom: np.ndarray, poses: np.ndarray, ranges: np.ndarray,
               bearings: np.ndarray, max_range: float, cap: float, radius: float,
               angle: float) -> np.ndarray:
    out = np.empty_like(poses)
    for i in range(poses.shape[0]):
        # coarse 5 cm / 0.5 degree grid over the whole window, then 1 cm / 0.1 degree windows
        # around the best until it stays put (the coarse best can sit a few cm off the basin)
        p = _grid_search(dist, geom, poses[i], ranges[i], bearings, max_range, cap, radius,
                         0.05, angle, math.radians(0.5))
        for _ in range(20):
            q = _grid_search(dist, geom, p, ranges[i], bearings, max_range, cap, 0.05, 0.01,
                             math.radians(0.5), math.radians(0.1))
            moved = abs(q[0] - p[0]) + abs(q[1] - p[1]) + abs(q[2] - p[2]) > 1e-9
            p = q
            if not moved:
                break
        out[i] = p
        out[i, 2] = (out[i, 2] + math.pi) % (2.0 * math.pi) - math.pi
    return out


def best_fit_poses(grid: OccupancyGrid, poses: np.ndarray, ranges: np.ndarray,
                   bearings: np.ndarray, max_range: float, radius: float = 0.5,
                   angle: float = math.radians(4.0), cap: float = 0.5) -> np.ndarray:
    """For each pose, the pose within ``radius`` (m) and ``angle`` (rad) where its scan fits the
    map best (least squared end-point distance, each capped at ``cap``)."""
    dist = distance_field(grid.data, grid.resolution, max(2.0 * cap, 1.0))
    return _best_fits(dist, _geometry(grid), np.asarray(poses, np.float64),
                      np.asarray(ranges, np.float64), np.asarray(bearings, np.float64),
                      float(max_range), float(cap), float(radius), float(angle))
