"""What the goal-occupied, dithering and detour-age checks cost per call.

    python bench/bench_goal_checks.py [--json] [--repeat N]

On a 20 m x 20 m map at 5 cm (400 x 400 cells) with a wall, a doorway and a box the sensors
marked: ``label_free_us`` (the 4-connected labelling of a 1 m tolerance window),
``free_goal_ms`` (NearestFreeGoal's search: a goal on the box, the nearest reachable free cell
within 0.5 m, navfn plans included), ``free_goal_free_us`` (the same for a free goal: one cell
lookup), ``gate_ms`` (FindGateOnPath over 3 m of path), ``blocking_age_ms`` (the sensed cells
along a 10 m map-only route and their newest observed-space stamp) and ``dither_update_us``
(one IsDithering bookkeeping step). Medians of ``--repeat`` calls (default 50).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))

from navcore.clock import SimClock  # noqa: E402
from navcore.costmap.blocking import blocking_cells, last_seen_occupied  # noqa: E402
from navcore.costmap.layered import LayeredCostmap  # noqa: E402
from navcore.costmap.observed_space import ObservedSpace  # noqa: E402
from navcore.motion.dither import DitherCheck  # noqa: E402
from navcore.motion.gate import gate_on_path  # noqa: E402
from navcore.planners import make_planner  # noqa: E402
from navcore.planners.free_goal import label_free, nearest_reachable_free_goal  # noqa: E402
from navcore.synthetic_maps import ascii_map  # noqa: E402
from navcore.types import Path, Pose2D  # noqa: E402

RES = 0.05
FOOTPRINT = [[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]]


def world() -> LayeredCostmap:
    g = np.full((400, 400), ".")
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = "#"
    g[:, 200:204] = "#"                                   # a wall at x 10 m ...
    g[400 - 212:400 - 188, 200:204] = "."                 # ... with a 1.2 m doorway at y 10 m
    cm = LayeredCostmap.from_params(
        {"plugins": ["static_layer", "obstacle_layer", "inflation_layer"],
         "footprint": FOOTPRINT, "inflation_layer": {"inflation_radius": 0.55}},
        static_map=ascii_map("\n".join("".join(r) for r in g), RES), clock=SimClock())
    xs = np.arange(5.0, 6.0, 0.03)                        # a box the laser outlined
    pts = np.concatenate([np.column_stack([xs, np.full_like(xs, 5.0)]),
                          np.column_stack([np.full_like(xs, 5.0), xs - 0.0])])
    cm.add_points(np.column_stack([pts, np.full(len(pts), 0.2)]), (4.0, 4.0, 0.2))
    cm.update_map(Pose2D(4.0, 4.0, 0.0))
    return cm


def median_time(fn, repeat: int) -> float:
    fn()                                                  # compile / warm
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--repeat", type=int, default=50)
    args = ap.parse_args()
    cm = world()
    planner = make_planner("navfn/NavfnROS", cm.costmap)
    robot = Pose2D(2.0, 2.0, 0.0)
    reach = lambda p: planner.make_plan(robot, p).ok  # noqa: E731
    window = np.random.default_rng(1).random((41, 41)) < 0.6
    line = np.array([[2.0 + 0.05 * i, 10.0, 0.0] for i in range(300)])
    path = Path(line)
    observed = ObservedSpace.around(RES, 12.0, 12.0, FOOTPRINT)
    observed.recentre(8.0, 8.0)
    dither = DitherCheck()
    k = iter(range(10 ** 9))
    figures = {
        "label_free_us": median_time(lambda: label_free(window), args.repeat) * 1e6,
        "free_goal_ms": median_time(lambda: nearest_reachable_free_goal(
            cm.costmap, Pose2D(5.02, 5.5, 0.0), 0.5, reach, seen_from=(robot.x, robot.y)),
            args.repeat) * 1e3,
        "free_goal_free_us": median_time(lambda: nearest_reachable_free_goal(
            cm.costmap, Pose2D(3.0, 3.0, 0.0), 0.5, reach), args.repeat) * 1e6,
        "gate_ms": median_time(lambda: gate_on_path(
            cm.costmap, path, Pose2D(8.0, 10.0, 0.0), np.asarray(cm.footprint), 3.0, 0.4),
            args.repeat) * 1e3,
        "blocking_age_ms": median_time(lambda: last_seen_occupied(
            observed, blocking_cells(cm, Path(np.array([[4.0 + 0.05 * i, 5.5, 0.0]
                                                        for i in range(200)])), 0.35)),
            args.repeat) * 1e3,
        "dither_update_us": median_time(lambda: (dither.update(0.1 * next(k), 1.0, 1.0, 5.0,
                                                               0.5),
                                                 dither.dithering(0.1, 10.0, 1.0)),
                                        args.repeat) * 1e6,
    }
    figures = {n: round(v, 3) for n, v in figures.items()}
    for n, v in figures.items():
        print(f"{n:20s} {v}")
    if args.json:
        print(json.dumps(figures))


if __name__ == "__main__":
    main()
