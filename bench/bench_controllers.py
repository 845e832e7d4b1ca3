"""One control cycle of the local planners on a 6 m x 6 m local costmap at 0.05 m.

The scene: a rectangular 0.5 x 0.44 m footprint at the centre, driving at 0.4 m/s along a gently
curving plan, boxes to both sides inflated as costmap_2d would (inscribed 0.22 m, radius 0.55 m).
Figures, per case, over N identical cycles: ``<case>_ms`` the fastest cycle (wall clock; on a
shared machine the uncontended cost), ``<case>_median_ms`` the median wall clock, ``<case>_cpu_ms``
the median CPU time of the calling thread (robust to other processes' load), and the number of
trajectories. Cases: DWA with the ROS defaults (which sample vy too: max_vel_y 0.1), the same
with a changed costmap every cycle (what it costs right after a local costmap update, when the
planner's per-window grids are rebuilt), the same for
a differential drive (max_vel_y = min_vel_y = 0), DWA with the
tuning guide's heavy setting (vx 20 x vth 40 samples, sim_time 4.0, sim_granularity 0.025,
differential drive), the same heavy setting scored exhaustively (no branch and bound, to show what
it saves), and trajectory rollout with its defaults.

    python bench/bench_controllers.py [--json] [--cycles N]
"""

from __future__ import annotations

import argparse
import json
import time
from typing import Any

import numpy as np

from navcore.controllers import make_controller
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.inflation import cost_table, inflate
from navcore.types import Path, Pose2D, Twist

FOOTPRINT = np.array([[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]])
HEAVY = {"vx_samples": 20, "vth_samples": 40, "sim_time": 4.0, "sim_granularity": 0.025,
         "max_vel_y": 0.0, "min_vel_y": 0.0}


def scene() -> tuple[Costmap2D, Path, Pose2D, Twist]:
    cm = Costmap2D(120, 120, 0.05, -3.0, -3.0)
    for x0, y0, x1, y1 in ((1.0, 0.9, 1.6, 1.4), (1.8, -1.5, 2.4, -0.9), (-1.0, 1.2, 0.2, 1.5),
                           (2.6, 0.9, 2.9, 1.2)):
        cm.costs[int((y0 + 3) / 0.05):int((y1 + 3) / 0.05),
                 int((x0 + 3) / 0.05):int((x1 + 3) / 0.05)] = 254
    inflate(cm.costs, cost_table(0.05, 0.22, 0.55, 10.0))
    xs = np.linspace(-1.0, 8.0, 181)
    ys = 0.3 * np.sin(xs / 2.0)
    path = Path(np.column_stack([xs, ys, np.arctan2(np.gradient(ys), np.gradient(xs))]))
    return cm, path, Pose2D(0.0, 0.0, 0.1), Twist(0.4, 0.0, 0.1)


def time_cycles(kind: str, params: dict[str, Any], cycles: int, exhaustive: bool = False,
                new_window: bool = False) -> tuple[float, float, float, int, str]:
    """(min ms, median ms, median CPU ms, trajectories per cycle, status) of ``cycles``
    identical cycles. With ``new_window`` the costmap changes before every cycle (a far corner
    cell toggles between 0 and 1), as after each local costmap update: nothing the planner
    derives from the window (distance grids, footprint bound) can be reused."""
    cm, path, pose, vel = scene()
    ctl = make_controller(kind, cm, FOOTPRINT, params)
    if exhaustive:
        ctl.exhaustive = True
    r = ctl.compute_velocity(pose, vel, path)  # compile / warm up
    times, cpu = [], []
    for _ in range(cycles):
        ctl.reset()
        if new_window:
            cm.costs[0, 0] ^= 1
        t0, c0 = time.perf_counter(), time.thread_time()
        r = ctl.compute_velocity(pose, vel, path)
        times.append((time.perf_counter() - t0) * 1e3)
        cpu.append((time.thread_time() - c0) * 1e3)
    n = 0 if r.trajectories is None else len(r.trajectories)
    return float(np.min(times)), float(np.median(times)), float(np.median(cpu)), n, r.status


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print the figures as JSON last")
    ap.add_argument("--cycles", type=int, default=200)
    args = ap.parse_args()
    dwa, rollout = "dwa_local_planner/DWAPlannerROS", "base_local_planner/TrajectoryPlannerROS"
    cases = (("dwa_default", dwa, {}, False, False),
             ("dwa_default_new_window", dwa, {}, False, True),
             ("dwa_default_diffdrive", dwa, {"max_vel_y": 0.0, "min_vel_y": 0.0}, False, False),
             ("dwa_heavy", dwa, HEAVY, False, False),
             ("dwa_heavy_exhaustive", dwa, HEAVY, True, False),
             ("trajectory_rollout_default", rollout, {}, False, False))
    figures: dict[str, float] = {}
    for name, kind, params, exhaustive, new_window in cases:
        cycles = max(5, args.cycles // 10) if exhaustive else args.cycles
        best, med, cpu, n, status = time_cycles(kind, params, cycles, exhaustive, new_window)
        print(f"{name:28s} {best:8.3f} ms min  {med:8.3f} ms median  {cpu:8.3f} ms cpu  "
              f"{n:5d} trajectories  ({status})")
        figures[f"{name}_ms"] = round(best, 3)
        figures[f"{name}_median_ms"] = round(med, 3)
        figures[f"{name}_cpu_ms"] = round(cpu, 3)
        figures[f"{name}_trajectories"] = n
    if args.json:
        print(json.dumps(figures))


if __name__ == "__main__":
    main()
