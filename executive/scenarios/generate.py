"""Seeded scenario generators: clutter with a guaranteed free path, patrols, start/goal pairs.

``materialize(scenario, seed)`` returns a copy of the scenario with the generated start, goals
and objects; the same scenario and seed always give the same copy (one ``numpy.random.Generator``
seeded from ``generate.seed``, or from the run's seed when the scenario gives none).

Free space is judged on the map's known-free cells (unknown and occupied cells are never chosen)
with the objects already in the scenario; "reachable" means connected to the start through cells
at least the requested clearance away from anything solid (a 4-connected wavefront).
"""

from __future__ import annotations

import copy
import math
from typing import Any

import numpy as np

from navcore.maps import OccupancyGrid
from navcore.raycast import distance_field
from navcore.types import Pose2D

from executive.scenarios.fields import _Bad, _int, _mapping, _num, _shape
from executive.scenarios.model import Scenario, Shape
from executive.scenarios.source import Path_, Problems, ScenarioError

_SPEC_KEYS = {
    "clutter": ("count", "region", "size", "shapes", "free_path_width"),
    "patrol": ("count", "min_distance", "clearance", "region"),
    "start_goal": ("min_distance", "clearance", "region"),
}


def check_spec(pb: Problems, path: Path_, key: str, v: Any) -> Any:
    """Validate one generator's mapping (clutter may be a list of them)."""
    if key == "clutter" and isinstance(v, list):
        return [check_spec(pb, path + (i,), key, x)[0] for i, x in enumerate(v)]
    d = _mapping(pb, path, v, _SPEC_KEYS[key])
    out: dict[str, Any] = {}
    if "region" in d:
        out["region"] = _shape(pb, path + ("region",), d["region"])
    if key == "clutter":
        out["count"] = _int(pb, path + ("count",), d.get("count", 0), 1)
        size = d.get("size", [0.2, 0.4])
        if not isinstance(size, list) or len(size) != 2:
            pb.add(path + ("size",), f"expected [smallest, largest] (m), got {size!r}")
            raise _Bad
        lo = _num(pb, path + ("size", 0), size[0], 0.0, strict_lo=True)
        hi = _num(pb, path + ("size", 1), size[1], lo)
        out["size"] = (lo, hi)
        shapes = d.get("shapes", ["box", "circle"])
        if not isinstance(shapes, list) or not shapes or any(s not in ("box", "circle")
                                                             for s in shapes):
            pb.add(path + ("shapes",), f"expected a list of box / circle, got {shapes!r}")
            raise _Bad
        out["shapes"] = list(shapes)
        if "region" not in out:
            pb.add(path, "clutter needs a region: {box: [x0, y0, x1, y1]}")
            raise _Bad
        out["free_path_width"] = _num(pb, path + ("free_path_width",),
                                      d.get("free_path_width", 0.9), 0.0, strict_lo=True)
        return [out]
    if key == "patrol":
        out["count"] = _int(pb, path + ("count",), d.get("count", 2), 1)
        if out["count"] > 100:
            pb.add(path + ("count",), f"at most 100 poses, got {out['count']}")
            raise _Bad
    out["min_distance"] = _num(pb, path + ("min_distance",), d.get("min_distance", 1.0), 0.0)
    out["clearance"] = _num(pb, path + ("clearance",), d.get("clearance", 0.5), 0.0,
                            strict_lo=True)
    return out


# --------------------------------------------------------------------------- grids
def _blocked(grid: OccupancyGrid, objects: list[Shape]) -> np.ndarray:
    """Cells that are not known free, with the objects drawn in."""
    occ = grid.data != 0
    for s in objects:
        _raster(grid, s, occ)
    return occ


def _raster(grid: OccupancyGrid, s: Shape, out: np.ndarray, pad: float = 0.0) -> None:
    res = grid.resolution
    x0, y0, x1, y1 = s.bbox()
    ox, oy = grid.origin.x, grid.origin.y
    c0 = max(0, int(math.floor((x0 - pad - ox) / res)))
    c1 = min(grid.width, int(math.ceil((x1 + pad - ox) / res)))
    r0 = max(0, int(math.floor((y0 - pad - oy) / res)))
    r1 = min(grid.height, int(math.ceil((y1 + pad - oy) / res)))
    if c0 >= c1 or r0 >= r1:
        return
    xs = ox + (np.arange(c0, c1) + 0.5) * res
    ys = oy + (np.arange(r0, r1) + 0.5) * res
    X, Y = np.meshgrid(xs, ys)
    if s.kind == "circle":
        cx, cy, r = s.values
        m = (X - cx) ** 2 + (Y - cy) ** 2 <= (r + pad) ** 2
    else:
        dx = np.maximum(np.maximum(x0 - X, X - x1), 0.0)
        dy = np.maximum(np.maximum(y0 - Y, Y - y1), 0.0)
        m = dx * dx + dy * dy <= pad * pad
    out[r0:r1, c0:c1] |= m


def _clearance(grid: OccupancyGrid, occ: np.ndarray) -> np.ndarray:
    """Metres from each cell centre to the nearest blocked cell centre (half a cell less: the
    blocked cell's edge)."""
    d = np.asarray(distance_field(np.ascontiguousarray(occ, np.uint8)), np.float64)
    return np.maximum(d - 0.5, 0.0) * grid.resolution


def wavefront(free: np.ndarray, start: tuple[int, int]) -> np.ndarray:
    """4-connected steps from ``start`` (row, col) to every cell of ``free``; -1 unreachable."""
    dist = np.full(free.shape, -1, np.int32)
    if not free[start]:
        return dist
    front = np.zeros_like(free)
    front[start] = True
    dist[start] = 0
    seen = front.copy()
    step = 0
    while front.any():
        step += 1
        nxt = np.zeros_like(front)
        nxt[1:, :] |= front[:-1, :]
        nxt[:-1, :] |= front[1:, :]
        nxt[:, 1:] |= front[:, :-1]
        nxt[:, :-1] |= front[:, 1:]
        nxt &= free & ~seen
        dist[nxt] = step
        seen |= nxt
        front = nxt
    return dist


def _cell(grid: OccupancyGrid, x: float, y: float) -> tuple[int, int] | None:
    c = grid.world_to_map(x, y)
    return None if c is None else (int(c[1]), int(c[0]))


def _path(dist: np.ndarray, goal: tuple[int, int]) -> list[tuple[int, int]]:
    """Cells from the wavefront's start to ``goal``, walking down the step counts."""
    out = [goal]
    r, c = goal
    h, w = dist.shape
    while dist[r, c] > 0:
        d = dist[r, c]
        for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            rr, cc = r + dr, c + dc
            if 0 <= rr < h and 0 <= cc < w and dist[rr, cc] == d - 1:
                r, c = rr, cc
                break
        out.append((r, c))
    return out[::-1]


def _world(grid: OccupancyGrid, cell: tuple[int, int]) -> tuple[float, float]:
    r, c = cell
    return (grid.origin.x + (c + 0.5) * grid.resolution,
            grid.origin.y + (r + 0.5) * grid.resolution)


def _in_region(grid: OccupancyGrid, region: Shape | None) -> np.ndarray:
    m = np.zeros((grid.height, grid.width), bool)
    if region is None:
        m[:] = True
    else:
        _raster(grid, region, m)
    return m


def _poses(rng: np.random.Generator, grid: OccupancyGrid, candidates: np.ndarray, n: int,
           min_distance: float, first: tuple[float, float] | None, what: str) -> list[Pose2D]:
    """``n`` poses on candidate cells, at least ``min_distance`` apart (and from ``first``)."""
    rows, cols = np.nonzero(candidates)
    if len(rows) == 0:
        raise ScenarioError(f"generate: {what}: no free cell with the clearance asked for")
    taken: list[tuple[float, float]] = [first] if first is not None else []
    out: list[Pose2D] = []
    for _ in range(200 * n):
        if len(out) == n:
            break
        i = int(rng.integers(len(rows)))
        x, y = _world(grid, (int(rows[i]), int(cols[i])))
        if all(math.hypot(x - a, y - b) >= min_distance for a, b in taken):
            taken.append((x, y))
            out.append(Pose2D(x, y, float(rng.uniform(-math.pi, math.pi))))
    if len(out) < n:
        raise ScenarioError(f"generate: {what}: found {len(out)} of {n} free poses "
                            f"{min_distance:g} m apart")
    return out


def materialize(scenario: Scenario, seed: int) -> Scenario:
    """A copy of ``scenario`` with its generators run for ``seed`` (itself if it has none)."""
    g = scenario.generate
    if g is None:
        return scenario
    rng = np.random.default_rng(g.seed if g.seed is not None else seed)
    sc = copy.copy(scenario)
    sc.objects = list(scenario.objects)
    grid = sc.grid
    occ = _blocked(grid, sc.objects)
    clear = _clearance(grid, occ)
    for spec, what in ((g.start_goal, "start_goal"), (g.patrol, "patrol")):
        if spec is None:
            continue
        ok = (clear >= spec["clearance"]) & _in_region(grid, spec.get("region"))
        if what == "start_goal":
            start = _poses(rng, grid, ok, 1, 0.0, None, what)[0]
            sc.start = start
        s = _cell(grid, sc.start.x, sc.start.y)
        if s is None:
            raise ScenarioError(f"generate: {what}: the start is outside the map")
        reach = wavefront(clear >= spec["clearance"], s) >= 0
        n = 1 if what == "start_goal" else spec["count"]
        sc.goals = _poses(rng, grid, ok & reach, n, spec["min_distance"],
                          (sc.start.x, sc.start.y), what)
    for spec in g.clutter:
        width = spec["free_path_width"]
        keep = np.zeros_like(occ)
        here = _cell(grid, sc.start.x, sc.start.y)
        for goal in sc.goals:
            there = _cell(grid, goal.x, goal.y)
            if here is None or there is None:
                raise ScenarioError("generate: clutter: start or goal outside the map")
            dist = wavefront(clear >= width / 2.0, here)
            if dist[there] < 0:
                raise ScenarioError(f"generate: clutter: no path {width:g} m wide from "
                                    f"({_world(grid, here)[0]:.2f}, {_world(grid, here)[1]:.2f})"
                                    f" to ({goal.x:.2f}, {goal.y:.2f}) on the map")
            for cell in _path(dist, there):
                x, y = _world(grid, cell)
                _raster(grid, Shape("circle", (x, y, 1e-6)), keep, pad=width / 2.0)
            here = there
        x0, y0, x1, y1 = spec["region"].bbox()
        lo, hi = spec["size"]
        placed = 0
        for _ in range(100 * spec["count"]):
            if placed == spec["count"]:
                break
            size = float(rng.uniform(lo, hi))
            x, y = float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1))
            kind = spec["shapes"][int(rng.integers(len(spec["shapes"])))]
            if kind == "circle":
                s = Shape("circle", (x, y, size / 2.0), f"clutter{len(sc.objects)}")
            else:
                s = Shape("box", (x - size / 2, y - size / 2, x + size / 2, y + size / 2),
                          f"clutter{len(sc.objects)}")
            m = np.zeros_like(occ)
            _raster(grid, s, m)
            if (m & keep).any() or not m.any():
                continue
            sc.objects.append(s)
            placed += 1
        if placed < spec["count"]:
            raise ScenarioError(f"generate: clutter: placed {placed} of {spec['count']} objects "
                                f"off the {width:g} m free path")
    return sc


def free_path_exists(grid: OccupancyGrid, objects: list[Shape], a: Pose2D, b: Pose2D,
                     width: float) -> bool:
    """Whether a path ``width`` wide joins a and b around the map and the objects."""
    clear = _clearance(grid, _blocked(grid, objects))
    s, t = _cell(grid, a.x, a.y), _cell(grid, b.x, b.y)
    if s is None or t is None:
        return False
    return bool(wavefront(clear >= width / 2.0, s)[t] >= 0)

