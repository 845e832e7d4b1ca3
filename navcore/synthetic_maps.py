"""Procedural maps of our own: office floors for benchmarks and demos, corridors for tuning tests.

Deterministic for a given seed. Values are OccupancyGrid ones (0 free, 100 occupied, -1 unknown).
"""

from __future__ import annotations

import numpy as np

from navcore.maps import OCCUPIED, UNKNOWN, OccupancyGrid
from navcore.types import Pose2D


def office_map(size: int, resolution: float = 0.05, seed: int = 0, room: float = 6.0,
               wall: float = 0.15, door: float = 1.0) -> OccupancyGrid:
    """A ``size`` x ``size`` floor of rooms on a grid of ``room`` metres, walls ``wall`` thick,
    one or two doors ``door`` wide per wall, an unknown border one room wide outside the outer wall,
    and a few desks. Every room is reachable from every other.
    """
    rng = np.random.default_rng(seed)
    g = np.zeros((size, size), np.int16)
    cell = max(int(round(room / resolution)), 8)
    t = max(int(round(wall / resolution)), 1)
    d = max(int(round(door / resolution)), 3)
    n = max(size // cell, 1)
    # interior walls with doors
    for k in range(n + 1):
        p = min(k * cell, size - t)
        g[p:p + t, :] = OCCUPIED
        g[:, p:p + t] = OCCUPIED
    for i in range(n):
        for j in range(n):
            y0, x0 = i * cell, j * cell
            # door in the wall on the right of room (i, j) and on the top of it
            if j + 1 < n:
                y = y0 + t + int(rng.integers(0, max(cell - t - d, 1)))
                g[y:y + d, (j + 1) * cell:(j + 1) * cell + t] = 0
            if i + 1 < n:
                x = x0 + t + int(rng.integers(0, max(cell - t - d, 1)))
                g[(i + 1) * cell:(i + 1) * cell + t, x:x + d] = 0
            # a desk in most rooms, clear of the doors
            if rng.random() < 0.7 and cell > 4 * d:
                w = int(rng.integers(d, 2 * d))
                h = int(rng.integers(d // 2 + 1, d))
                cy = y0 + cell // 2 + int(rng.integers(-cell // 8, cell // 8 + 1))
                cx = x0 + cell // 2 + int(rng.integers(-cell // 8, cell // 8 + 1))
                g[cy:cy + h, cx:cx + w] = OCCUPIED
    # everything beyond the last full room is unknown, as outside a mapped building
    edge = min(n * cell + t, size)
    g[edge:, :] = UNKNOWN
    g[:, edge:] = UNKNOWN
    return OccupancyGrid(g, resolution, Pose2D(0.0, 0.0, 0.0))


def corridor_map(length: float = 12.0, width: float = 3.0, resolution: float = 0.05,
                 wall: float = 0.2) -> OccupancyGrid:
    """A straight corridor along +x, ``width`` metres between the walls' inner faces.

    The corridor's centre line is y = 0; the map origin sits below the lower wall.
    """
    nx = int(round(length / resolution))
    t = int(round(wall / resolution))
    inner = int(round(width / resolution))
    ny = inner + 2 * t
    g = np.zeros((ny, nx), np.int16)
    g[:t, :] = OCCUPIED
    g[-t:, :] = OCCUPIED
    return OccupancyGrid(g, resolution, Pose2D(0.0, -(t + inner / 2) * resolution, 0.0))


def ascii_map(text: str, resolution: float = 0.1, origin: Pose2D = Pose2D()) -> OccupancyGrid:
    """A grid drawn as text: ``#`` occupied, ``.`` or space free, ``?`` unknown. First line = top."""
    lines = [ln for ln in text.strip("\n").splitlines()]
    if not lines:
        raise ValueError("ascii_map: empty drawing")
    w = max(len(ln) for ln in lines)
    g = np.zeros((len(lines), w), np.int16)
    for r, ln in enumerate(lines):
        for c, ch in enumerate(ln.ljust(w)):
            if ch == "#":
                g[r, c] = OCCUPIED
            elif ch == "?":
                g[r, c] = UNKNOWN
            elif ch not in ". SG":
                raise ValueError(f"ascii_map: line {r + 1} column {c + 1}: unknown character {ch!r} "
                                 "(use '#', '.', ' ', '?')")
    return OccupancyGrid(g[::-1].copy(), resolution, origin)
