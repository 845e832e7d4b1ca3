"""Behaviour-tree figures: loading the shipped trees, and the cost of one tick of each with
no-op components (the tree alone, without the executive loop).

    python bench/bench_trees.py [--json] [--cpu] [--trees DIR]

``load_<tree>_ms``: parse + validate + build the YAML file. ``tick_<tree>_us``: mean
LoadedTree.tick() while navigating (FollowPath RUNNING, replanning at its rate) with
a ScriptedPlanner with a fixed path and a ScriptedController with a fixed command (0.2 m/s
straight on, the goal far ahead) and a kinematic robot.
``--cpu`` times with the process's CPU time instead of the wall clock (steadier on a shared
host); ``--trees DIR`` times the files of that name in DIR (another checkout's trees) instead
of the shipped ones.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

_clock = time.perf_counter

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def load_ms(path: str, repeats: int = 20) -> float:
    from executive.tree_loader import load_tree_file
    load_tree_file(path, namespace="/load_warm")  # imports the node library once, outside the timing
    t0 = _clock()
    for i in range(repeats):
        load_tree_file(path, namespace=f"/load_{i}")
    return 1e3 * (_clock() - t0) / repeats


def tick_us(path: str, ticks: int = 3000) -> float:
    from behaviors.testing import ScriptedController, ScriptedPlanner, ScriptedWorld, straight_path
    from executive.tree_loader import load_tree_file
    from navcore.types import Pose2D, Twist
    world = ScriptedWorld(planner=ScriptedPlanner(fixed_path=straight_path(Pose2D(),
                                                                           Pose2D(5.0, 0.0))),
                          controller=ScriptedController(fixed_command=Twist(0.2, 0.0, 0.0)))
    tree = load_tree_file(path, namespace=f"/tick_{os.path.basename(path).split('.')[0]}")
    tree.setup(**world.components())
    tree.set("goal", Pose2D(1000.0, 0.0, 0.0))
    for _ in range(50):
        world.step(tree.tick())
    elapsed = 0.0
    for _ in range(ticks):  # time the tick only, not the fake robot's integration
        t0 = _clock()
        cmd = tree.tick()
        elapsed += _clock() - t0
        world.step(cmd)
    assert tree.status.name == "RUNNING", f"{path}: expected to be navigating, {tree.status}"
    return 1e6 * elapsed / ticks


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="last line: one JSON object")
    parser.add_argument("--cpu", action="store_true", help="time with the process CPU time")
    parser.add_argument("--trees", metavar="DIR", help="time DIR/<tree>.yaml instead")
    args = parser.parse_args()
    global _clock
    if args.cpu:
        _clock = time.process_time
    from executive.tree_loader import SHIPPED_TREES, shipped_tree
    figures = {}
    for name in SHIPPED_TREES:
        path = os.path.join(args.trees, f"{name}.yaml") if args.trees else shipped_tree(name)
        figures[f"load_{name}_ms"] = round(load_ms(path), 2)
        figures[f"tick_{name}_us"] = round(tick_us(path), 1)
        print(f"{name:24s} load {figures[f'load_{name}_ms']:7.2f} ms   "
              f"tick {figures[f'tick_{name}_us']:7.1f} us")
    if args.json:
        print(json.dumps(figures))


if __name__ == "__main__":
    main()
