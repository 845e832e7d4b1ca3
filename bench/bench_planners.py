"""Benchmark the global planners: navfn and global_planner corner to corner.

Maps: ``navcore.synthetic_maps.office_map(n)`` for n = 1000, 2000, 4000 (0.05 m cells), lethal
where occupied, unknown where unknown, inflated as in the C++ baselines of
ros_navigation_internals.md section 8 (inscribed 0.2 m, inflation_radius 0.55, cost_scaling_factor
10), start and goal the free cells nearest (45, 45) and (n-45, n-45); plus the Willow Garage map
between the two free cells farthest apart along the diagonal. Each figure is the median of several
full ``make_plan`` calls after a warm-up (numba compiled and cached), in process CPU time.
``*_replan_1000_ms``: a ``reuse_search`` replan toward the same goal after a scan-sized cost change
near the robot, the robot 0.5 m further along (see ``replan_ms``).
``--json`` prints one JSON object as the last line.
``global_planner_astar_grid`` is ``use_dijkstra: false`` with ``use_grid_path: true``; its C++
figure is ROS's greedy single-assignment A*, which is not least-cost (ours is navfn's A*
wavefront, see navcore/planners/global_planner.py).

    python bench/bench_planners.py [--json] [--sizes 1000 2000 4000] [--repeat 5]
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path as FsPath

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.maps import load_map
from navcore.planners import GlobalPlanner, NavFn
from navcore.synthetic_maps import office_map
from navcore.types import Pose2D

# C++ makePlan figures of ros_navigation_internals.md 8.1, 8.2 (a family 6 model 167 Xeon at
# 2.6 GHz). The same C++ built -O2 and run on this project's CI host (a model 85 Xeon at 2.5 GHz)
# on these very maps took navfn 48 / 210 / 1290 ms and global_planner 73 / 347 / 1659 ms
# (medians, 2026-11-22): the speed-ups printed against these constants are the lower bound.
CPP_MS = {"navfn": {1000: 29.9, 2000: 134.0, 4000: 701.0},
          "global_planner": {1000: 41.0, 2000: 188.0, 4000: 889.0},
          "global_planner_astar_grid": {1000: 1.3, 2000: 4.7, 4000: 36.0}}


def costmap_from_grid(data: np.ndarray, resolution: float, origin: tuple[float, float]
                      ) -> Costmap2D:
    """Lethal where occupied, unknown where -1, inflated (inscribed 0.2, radius 0.55, csf 10)."""
    cm = Costmap2D(data.shape[1], data.shape[0], resolution, origin[0], origin[1])
    cm.costs[data >= 65] = 254
    cm.costs[data < 0] = 255
    try:
        from navcore.costmap.inflation import cost_table, inflate
    except ImportError:  # inflation not available yet: plain lethal/unknown map
        return cm
    inflate(cm.costs, cost_table(resolution, 0.2, 0.55, 10.0))
    return cm


def clock_ms(fn, repeat: int) -> float:
    """Median CPU time of ``fn`` in ms: the planners are single-threaded, and CPU time keeps other
    jobs on a shared machine out of the figure (wall time would count their time slices)."""
    fn()  # warm-up (JIT cache load, buffer allocation)
    times = []
    for _ in range(repeat):
        t0 = time.process_time()
        fn()
        times.append((time.process_time() - t0) * 1e3)
    return statistics.median(times)


def nearest_free(cm: Costmap2D, mx: int, my: int) -> Pose2D:
    """Centre of the free cell nearest to (mx, my) (the C++ corners may fall on a desk here)."""
    free = np.argwhere(cm.costs == 0)
    c = free[np.argmin((free[:, 0] - my) ** 2 + (free[:, 1] - mx) ** 2)]
    return Pose2D(*cm.map_to_world(int(c[1]), int(c[0])), 0.0)


def willow_endpoints(cm: Costmap2D) -> tuple[Pose2D, Pose2D]:
    """Free cells nearest the lower-left and upper-right corners of the map's free area."""
    free = np.argwhere(cm.costs == 0)
    s = free[np.argmin(free[:, 0] + free[:, 1])]
    g = free[np.argmax(free[:, 0] + free[:, 1])]
    to_pose = lambda c: Pose2D(*cm.map_to_world(int(c[1]), int(c[0])), 0.0)  # noqa: E731
    return to_pose(s), to_pose(g)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print a JSON object as the last line")
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 2000, 4000])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    out: dict[str, float] = {}
    for n in args.sizes:
        g = office_map(n)
        cm = costmap_from_grid(g.data, g.resolution, (g.origin.x, g.origin.y))
        start = nearest_free(cm, 45, 45)
        goal = nearest_free(cm, n - 45, n - 45)
        planners = {"navfn": NavFn(cm), "global_planner": GlobalPlanner(cm),
                    "global_planner_astar_grid": GlobalPlanner(cm, {"use_dijkstra": False,
                                                                    "use_grid_path": True})}
        for name, planner in planners.items():
            r = planner.make_plan(start, goal)
            if not r.ok:
                print(f"{name} {n}: FAILED ({r.reason})", file=sys.stderr)
                continue
            ms = clock_ms(lambda: planner.make_plan(start, goal), args.repeat)
            out[f"{name}_{n}_ms"] = round(ms, 2)
            cpp = CPP_MS[name].get(n)
            print(f"{name:26s} {n:5d}^2  {ms:8.2f} ms  (C++ {cpp} ms: speed-up x{cpp / ms:.2f})  "
                  f"path {len(r.path)} poses {r.path.length():.1f} m  "
                  f"updates/cell {planner.last_updates / (n * n):.2f}")
    root = FsPath(__file__).resolve().parents[1]
    for cand in (root.parent / "shared" / "data", root / ".." / "shared" / "data"):
        y = cand / "maps" / "willow_garage" / "willow-full-0.05.yaml"
        if y.exists():
            m = load_map(str(y))
            cm = costmap_from_grid(m.data, m.resolution, (m.origin.x, m.origin.y))
            start, goal = willow_endpoints(cm)
            for name, planner in (("navfn", NavFn(cm)), ("global_planner", GlobalPlanner(cm))):
                r = planner.make_plan(start, goal)
                if not r.ok:
                    print(f"{name} willow: FAILED ({r.reason})", file=sys.stderr)
                    continue
                ms = clock_ms(lambda: planner.make_plan(start, goal), args.repeat)
                out[f"{name}_willow_ms"] = round(ms, 2)
                print(f"{name:26s} willow {cm.size_x}x{cm.size_y}  {ms:8.2f} ms  "
                      f"path {r.path.length():.1f} m")
            break
    if 1000 in args.sizes:
        g = office_map(1000)
        for name, make in (("navfn", NavFn), ("global_planner", GlobalPlanner)):
            cm = costmap_from_grid(g.data, g.resolution, (g.origin.x, g.origin.y))
            ms, full_ms, repaired = replan_ms(cm, make, max(args.repeat, 9))
            out[f"{name}_replan_1000_ms"] = round(ms, 2)
            print(f"{name + '_replan':26s} 1000^2  {ms:8.2f} ms  (after a change of ~300 cells "
                  f"near the robot, 0.5 m further on; a full goal-rooted plan {full_ms:.2f} ms; "
                  f"{repaired} of the replans repaired)")
    if args.json:
        print(json.dumps(out))
    return 0


def replan_ms(cm: Costmap2D, make, repeat: int) -> tuple[float, float, int]:
    """Median CPU ms of a ``reuse_search`` replan toward the same goal after a scan-sized change
    (an obstacle blob of ~250 lethal cells appears 0.75-2 m from the robot, last time's blob is
    gone) with the robot 0.5 m further along its path; also the median of full plans of the
    same planner (fresh workspace) and how many replans were repairs."""
    n = cm.size_x
    start, goal = nearest_free(cm, 45, 45), nearest_free(cm, n - 45, n - 45)
    base = cm.costs.copy()
    planner = make(cm, {"reuse_search": True})
    r = planner.make_plan(start, goal)
    rng = np.random.default_rng(7)
    times, full, repaired = [], [], 0
    for i in range(repeat + 1):
        d = np.r_[0.0, np.cumsum(np.hypot(*np.diff(r.path.poses[:, :2], axis=0).T))]
        x, y = r.path.poses[np.searchsorted(d, 0.5), :2]
        start = Pose2D(float(x), float(y), 0.0)
        cx, cy = cm.world_to_map(start.x, start.y)
        a, dist = rng.uniform(0, 2 * np.pi), rng.uniform(15, 40)
        bx, by = int(cx + dist * np.cos(a)), int(cy + dist * np.sin(a))
        ys, xs = np.mgrid[by - 9:by + 10, bx - 9:bx + 10]
        blob = ((xs - bx) ** 2 + (ys - by) ** 2 < 81) & (xs > 0) & (ys > 0) & (xs < n - 1) \
            & (ys < n - 1)
        cm.costs[:] = base
        cm.costs[ys[blob], xs[blob]] = 254
        t0 = time.process_time()
        r = planner.make_plan(start, goal)
        if i:  # the first replan also compiles the repair kernels
            times.append((time.process_time() - t0) * 1e3)
            repaired += planner.last_repaired
            fresh = make(cm, {"reuse_search": True})
            t0 = time.process_time()
            fresh.make_plan(start, goal)
            full.append((time.process_time() - t0) * 1e3)
    cm.costs[:] = base
    return statistics.median(times), statistics.median(full), repaired


if __name__ == "__main__":
    sys.exit(main())
