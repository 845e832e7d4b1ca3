"""Executive figures: tree + loop overhead with no-op components, and one full control cycle
with real components in the simulator.

    python bench/bench_executive.py [--json] [--cpu] [--trees DIR]

``tick_overhead_us``: mean wall time of one Executive.step (sense, tick, gate, record) over the
shipped trees with every component replaced by a no-op (behaviors.testing.noop_components,
hw.testing.KinematicRobot), i.e. what the tree and the executive cost on top of the algorithms.
``cycle_ms``: mean Executive.step with the real costmaps, planner, controller and simulator on
the bundled demo scenario. ``--cpu`` times with the process's CPU time instead of the wall clock
(steadier on a shared host); ``--trees DIR`` gives the tick overhead of the tree files in DIR
(another checkout's) instead of the shipped ones.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

_clock = time.perf_counter

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))


def tree_overhead(tree_path: str, steps: int = 2000) -> float:
    """Mean microseconds per Executive.step for one tree with no-op components."""
    from navcore.clock import SimClock
    from navcore.types import Pose2D
    from executive.executive import Executive, _mission_ids
    from executive.tree_loader import load_tree_file
    from executive.config import config_from_mapping
    from behaviors.base import FAILURE, SUCCESS
    from behaviors.testing import noop_components
    from hw.testing import KinematicRobot
    ns = f"/bench_{next(_mission_ids)}"
    tree = load_tree_file(tree_path, namespace=ns)
    robot = KinematicRobot()
    components = noop_components(config_from_mapping({}, "<noop>").all_parameters())
    ex = Executive(tree, robot, SimClock(), 0.05, components, namespace=ns)
    goals = [Pose2D(3.0, 0.0), Pose2D(0.0, 0.0)]
    ex.set_goal(goals[0])
    for _ in range(50):  # warm up
        ex.step()
    k = 0
    t0 = _clock()
    for i in range(steps):
        status = ex.step()
        if status is SUCCESS or status is FAILURE:
            k += 1
            ex.set_goal(goals[k % 2])
    dt = _clock() - t0
    ex.shutdown()
    return 1e6 * dt / steps


def real_cycle(steps: int = 300) -> float:
    """Mean milliseconds per full control cycle on the demo scenario (real components)."""
    from executive.tree_loader import shipped_tree
    from executive.mission import World, build_mission
    from executive.scenario import load_scenario, scenario_config
    from behaviors.base import FAILURE, SUCCESS
    s = load_scenario(os.path.join(os.path.dirname(HERE), "executive", "data", "demo.yaml"))
    config = scenario_config(s)
    world = World(s.objects, s.moving, s.phantoms, s.faults)
    m = build_mission(shipped_tree("smach_recovery"), config, s.grid, s.start, world=world)
    ex = m.executive
    ex.set_goal(s.goals[0])
    for _ in range(20):  # compile and warm up
        ex.step()
    t0 = _clock()
    n = 0
    for _ in range(steps):
        status = ex.step()
        n += 1
        if status is SUCCESS or status is FAILURE:
            break
    dt = _clock() - t0
    ex.shutdown()
    return 1e3 * dt / n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--cpu", action="store_true", help="time with the process CPU time")
    ap.add_argument("--trees", metavar="DIR", help="tree files to time (default: the shipped)")
    args = ap.parse_args()
    global _clock
    if args.cpu:
        _clock = time.process_time
    trees_dir = args.trees or os.path.join(os.path.dirname(HERE), "trees")
    files = sorted(f for f in os.listdir(trees_dir) if f.endswith(".yaml"))
    figures: dict[str, float] = {}
    per_tree = []
    for f in files:
        us = tree_overhead(os.path.join(trees_dir, f))
        per_tree.append(us)
        name = os.path.splitext(f)[0]
        figures[f"tick_overhead_{name}_us"] = round(us, 1)
        print(f"{f:32s} tick overhead {us:8.1f} us (no-op components)")
    if per_tree:
        figures["tick_overhead_us"] = round(sum(per_tree) / len(per_tree), 1)
        print(f"{'mean':32s} tick overhead {figures['tick_overhead_us']:8.1f} us")
    ms = real_cycle()
    figures["cycle_ms"] = round(ms, 3)
    print(f"full control cycle (demo scenario, real components): {ms:.3f} ms")
    if args.json:
        print(json.dumps(figures))


if __name__ == "__main__":
    main()
