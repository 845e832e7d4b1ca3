"""Recovery helpers benchmark: the map-only route (navcore.planners.map_route) and the clear
memory (navcore.costmap.clear_memory) on a synthetic office map at 0.05 m.

    python bench/bench_recovery_memory.py [--json] [--repeat N] [--size CELLS]

``map_only_build_ms``: composing the static layers and inflation into a map-only costmap;
``map_only_plan_ms``: one navfn plan corner to corner on it (the planner reused, as IsDetourLong
and IsGoalReachableOnMap do); ``clear_with_memory_ms`` against ``clear_plain_ms``: a global
clear with and without the memory, with 2000 sensed lethal cells in the obstacle layer. Best of
N runs after one warm-up (numba compilation excluded); the machine is shared, so compare A/B in
the same minute only.
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

from navcore.clock import SimClock
from navcore.costmap.clear_memory import ClearMemory
from navcore.costmap.layered import LayeredCostmap
from navcore.planners import make_planner
from navcore.planners.map_route import MapOnlyRoute, map_only_costmap
from navcore.synthetic_maps import office_map
from navcore.types import Pose2D


def _best_ms(fn, repeat: int) -> float:
    fn()
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, (time.perf_counter() - t0) * 1000.0)
    return best


def _free_pose(cm: LayeredCostmap, corner: tuple[float, float]) -> Pose2D:
    """The free cell of the map-only costmap nearest to ``corner`` (metres)."""
    mo = map_only_costmap(cm)
    ys, xs = np.nonzero(mo.costs == 0)
    wx = mo.origin_x + (xs + 0.5) * mo.resolution
    wy = mo.origin_y + (ys + 0.5) * mo.resolution
    i = int(np.argmin(np.hypot(wx - corner[0], wy - corner[1])))
    return Pose2D(float(wx[i]), float(wy[i]), 0.0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--size", type=int, default=400, help="map side in cells")
    a = ap.parse_args()
    grid = office_map(a.size, 0.05, seed=1)
    cm = LayeredCostmap.from_params(
        {"plugins": ["static_layer", "obstacle_layer", "inflation_layer"], "robot_radius": 0.2,
         "inflation_layer": {"inflation_radius": 0.55}}, static_map=grid, clock=SimClock())
    side = a.size * 0.05
    start, goal = _free_pose(cm, (0.5, 0.5)), _free_pose(cm, (side - 0.5, side - 0.5))
    route = MapOnlyRoute(cm, make_planner("navfn/NavfnROS", cm.costmap))
    out = {"map_cells": a.size * a.size,
           "map_only_build_ms": round(_best_ms(lambda: map_only_costmap(cm), a.repeat), 3),
           "map_only_plan_ms": round(_best_ms(lambda: route.plan(start, goal), a.repeat), 3)}
    length = route.length(start, goal)
    if length is None:
        raise SystemExit("bench_recovery_memory: no map-only route corner to corner")
    out["map_only_path_m"] = round(length, 3)
    rng = np.random.default_rng(0)
    pts = np.column_stack([rng.uniform(0.5, side - 0.5, 2000), rng.uniform(0.5, side - 0.5, 2000),
                           np.full(2000, 0.2)])

    def fill() -> None:
        g = cm.layer("obstacle_layer").grid
        ix = ((pts[:, 0] - g.origin_x) / g.resolution).astype(int)
        iy = ((pts[:, 1] - g.origin_y) / g.resolution).astype(int)
        g.costs[iy, ix] = 254

    mem = ClearMemory(10.0)
    cm.update_map(start)

    def with_memory() -> None:
        fill()
        mem.clear(cm, 0.0, cm.reset_layers)

    def plain() -> None:
        fill()
        cm.reset_layers()
    out["clear_with_memory_ms"] = round(_best_ms(with_memory, a.repeat), 3)
    out["clear_plain_ms"] = round(_best_ms(plain, a.repeat), 3)
    out["load_avg_1min"] = round(os.getloadavg()[0], 2)
    if not a.json:
        for k, v in out.items():
            print(f"{k:24s} {v}")
    print(json.dumps(out))


if __name__ == "__main__":
    main()
