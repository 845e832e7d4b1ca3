"""Scenario catalogue figures: wall time of the whole catalogue and the simulated-to-wall ratio.

    python bench/bench_scenarios.py [--json] [--tree TREE]... [PATH...]

Runs every scenario of tests/scenarios (or the given paths) against each tree (default: the
shipped smach_recovery and move_base trees), prints the results table, then the figures:
``catalogue_s`` (wall seconds for all runs), ``scenario_realtime_factor`` (simulated seconds per
wall second over all runs), and per tree the number of scenarios solved.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("paths", nargs="*", default=[os.path.join(ROOT, "tests", "scenarios")])
    ap.add_argument("--tree", action="append")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    from executive.commands.scenario_cmd import print_table
    from executive.scenario import load_scenario, run_scenario, scenario_files
    trees = args.tree or [os.path.join(ROOT, "trees", "move_base.yaml"),
                          os.path.join(ROOT, "trees", "smach_recovery.yaml")]
    scenarios = [load_scenario(p) for p in scenario_files(args.paths)]
    # warm the numba caches so the figure measures running, not loading compiled kernels
    run_scenario(scenarios[0], trees[0])
    results = []
    t0 = time.perf_counter()
    for s in scenarios:
        for t in trees:
            results.append(run_scenario(s, t))
    wall = time.perf_counter() - t0
    sim = sum(r.sim_time for r in results)
    names = [os.path.splitext(os.path.basename(t))[0] for t in trees]
    print_table(results, names)
    figures = {"catalogue_s": round(wall, 2),
               "scenario_realtime_factor": round(sim / wall, 1),
               "scenarios": len(scenarios), "runs": len(results),
               "simulated_s": round(sim, 1)}
    for n in names:
        figures[f"solved_{n}"] = sum(1 for r in results if r.tree == n and r.solved)
    print(f"catalogue: {len(results)} runs, {sim:.0f} s simulated in {wall:.1f} s wall "
          f"({sim / wall:.1f}x real time)")
    if args.json:
        print(json.dumps(figures))


if __name__ == "__main__":
    main()
