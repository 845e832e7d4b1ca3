"""Tight-spot helpers benchmark: the room across a goal, the pre-pose search, the straight-entry
check (navcore.motion.line_up) and the straightest escape (navcore.motion.start_escape), on a
5 m x 4 m room at 0.05 m with a 0.7 m bay, the default robot's padded footprint.

    python bench/bench_tight_spots.py [--json] [--repeat N]

``goal_room_ms``: the width across the goal (what IsGoalInNarrowSpace costs a tick);
``pre_pose_ms``: ComputePrePose's search (entry depth, free pre-pose, passable line);
``entry_check_ms``: ApproachStraight's per-tick check of 1 s of motion at 0.1 m/s inside the bay;
``escape_ms``: StartEscape's search from a start 13 cm beside a wall (14 motions of 1 m).
Best of N runs after one warm-up (numba compilation excluded); the machine is shared, so
compare A/B in the same minute only.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from navcore.clock import SimClock
from navcore.costmap.layered import LayeredCostmap
from navcore.motion.line_up import entry_blocked, goal_room, pre_pose, segment_poses
from navcore.motion.start_escape import straightest_escape
from navcore.synthetic_maps import ascii_map
from navcore.types import Pose2D

RES = 0.05
FOOTPRINT = [[0.25, 0.22], [0.25, -0.22], [-0.25, -0.22], [-0.25, 0.22]]


def _best_ms(fn, repeat: int) -> float:
    fn()
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, (time.perf_counter() - t0) * 1000.0)
    return best


def room_with_bay() -> tuple[LayeredCostmap, Pose2D]:
    """The room, a 0.7 m bay 0.8 m deep at its south wall, and the goal in it."""
    w, h = 100, 80
    g = np.full((h, w), ".")
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = "#"
    g[h - 17:h - 1, 32:33] = "#"      # x 1.6 .. 1.65, y 0.05 .. 0.85
    g[h - 17:h - 1, 47:48] = "#"      # x 2.35 .. 2.4: 0.7 m between
    grid = ascii_map("\n".join("".join(r) for r in g), RES)
    cm = LayeredCostmap.from_params(
        {"plugins": ["static_layer", "inflation_layer"], "footprint": FOOTPRINT,
         "footprint_padding": 0.03,
         "inflation_layer": {"inflation_radius": 0.55, "cost_scaling_factor": 10.0}},
        static_map=grid, clock=SimClock())
    cm.update_map(Pose2D(2.5, 2.0, 0.0))
    return cm, Pose2D(2.0, 0.5, -np.pi / 2)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--repeat", type=int, default=20)
    a = ap.parse_args()
    cm, goal = room_with_bay()
    fp = np.asarray(cm.footprint)
    inside = segment_poses(goal.compose(Pose2D(-0.4, 0.0, 0.0)), goal, 0.05)[:3]
    start = Pose2D(3.5, 0.42, 0.0)
    figures = {
        "goal_room_ms": round(_best_ms(lambda: goal_room(cm.costmap, goal, fp), a.repeat), 3),
        "pre_pose_ms": round(_best_ms(lambda: pre_pose(cm, goal, fp, 1.0, 0.15), a.repeat), 3),
        "entry_check_ms": round(_best_ms(lambda: entry_blocked(cm, inside), a.repeat), 3),
        "escape_ms": round(_best_ms(lambda: straightest_escape(cm, start, 1.0), a.repeat), 3),
    }
    if a.json:
        print(json.dumps(figures))
    else:
        for k, v in figures.items():
            print(f"{k:>16s}  {v}")


if __name__ == "__main__":
    main()
