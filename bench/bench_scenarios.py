"""Scenario catalogue figures: every shipped tree against the whole catalogue (all seeds).

    python bench/bench_scenarios.py [--json] [--jobs N] [--tree TREE]... [PATH...]

Runs every scenario of tests/scenarios (or the given paths) against each tree (default: the four
shipped trees) on ``--jobs`` worker processes (default 2), prints the results table, then the
figures: ``catalogue_s`` (wall seconds for the whole catalogue, multi-seed scenarios included,
with the first tree: smach_recovery by default, what ``mission scenario run tests/scenarios
--jobs 2`` costs), ``all_trees_s``, ``scenarios``, ``runs`` (per tree) and per tree
``solved_<tree>`` (scenarios solved: every goal without a contact, multi-seed ones on at least
their ``pass_at_least`` seeds), ``met_<tree>`` (scenarios whose expectation held by their
k-of-n rule), ``contacts_<tree>`` (contact episodes over all runs), ``mean_sim_s_<tree>`` and
``errors_<tree>``. Scenarios skipped for absent real data count in none of them.
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
SHIPPED = ("smach_recovery", "nav2", "move_base", "near_goal_reconfigure")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("paths", nargs="*", default=[os.path.join(ROOT, "tests", "scenarios")])
    ap.add_argument("--tree", action="append")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    from executive.commands.scenario_cmd import print_table
    from executive.scenarios import (load_scenario, run_scenario, run_tasks, scenario_files,
                                     tasks_for, verdicts)
    trees = args.tree or [os.path.join(ROOT, "trees", f"{t}.yaml") for t in SHIPPED]
    files = scenario_files(args.paths)
    scenarios = [(f, load_scenario(f)) for f in files]
    needed = {s.name: s.needed() for _, s in scenarios}
    # warm the numba caches so the figures measure running, not loading compiled kernels
    run_scenario(scenarios[0][1], trees[0])
    results, walls = [], {}
    for t in trees:
        t0 = time.perf_counter()
        results += run_tasks(tasks_for(scenarios, [t]), jobs=args.jobs)
        walls[t] = time.perf_counter() - t0
    names = [os.path.splitext(os.path.basename(t))[0] for t in trees]
    vs = verdicts(results, needed)
    print_table(results, names, vs)
    figures: dict[str, float | int] = {
        "catalogue_s": round(walls[trees[0]], 1),
        "all_trees_s": round(sum(walls.values()), 1),
        "scenarios": len(scenarios),
        "runs": sum(1 for r in results if r.tree == names[0]),
        "simulated_s": round(sum(r.sim_time for r in results), 1),
        "jobs": args.jobs,
    }
    for n in names:
        tv = [v for v in vs if v.tree == n and not v.skipped]
        rs = [r for r in results if r.tree == n and r.outcome != "skipped"]
        figures[f"solved_{n}"] = sum(1 for v in tv if v.solved >= v.needed)
        figures[f"met_{n}"] = sum(1 for v in tv if v.passed)
        figures[f"contacts_{n}"] = sum(r.collisions for r in rs)
        figures[f"errors_{n}"] = sum(1 for r in rs if r.outcome == "error")
        figures[f"mean_sim_s_{n}"] = round(sum(r.sim_time for r in rs) / max(len(rs), 1), 1)
    figures["skipped"] = sum(1 for v in vs if v.skipped and v.tree == names[0])
    print(f"catalogue: {figures['runs']} runs of {len(scenarios)} scenarios per tree; "
          f"{names[0]} {walls[trees[0]]:.1f} s wall on {args.jobs} job(s)")
    if args.json:
        print(json.dumps(figures))


if __name__ == "__main__":
    main()
