"""``mission scenario run|check PATH...``: which tree solves which scenario, and are the files
right.

``check`` reports every problem of every file (``file:line: what``, the merged robot config
included) before anything runs. ``run`` never loses finished results: a scenario that does not
load or a run that raises is that run's ``error`` outcome and the others go on.
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from executive.commands._common import add_config_arguments, config_sources, fail


def add_arguments(p: argparse.ArgumentParser) -> None:
    sub = p.add_subparsers(dest="action", metavar="ACTION")
    r = sub.add_parser("run", help="run scenarios against trees and print a results table",
                       description="run scenarios against trees and print a results table")
    r.add_argument("paths", nargs="+", metavar="PATH", help="scenario files or directories")
    r.add_argument("--tree", action="append", metavar="TREE",
                   help="tree file (repeatable; default trees/smach_recovery.yaml)")
    add_config_arguments(r, "base robot config YAML the scenarios' profiles and overrides merge "
                            "into (default: the bundled robot, unless ROS files are given)")
    r.add_argument("--record", metavar="DIR", help="write a run folder per scenario and tree "
                                                   "under DIR")
    r.add_argument("--json", action="store_true", help="print results as JSON")
    r.add_argument("--junit", metavar="FILE", help="also write JUnit XML to FILE")
    r.add_argument("--seeds", metavar="SEEDS",
                   help="run every scenario with these seeds (1..10, 3 or 1,4,9) instead of "
                        "its own")
    r.add_argument("--seed", type=int, metavar="N", help="run every scenario with seed N")
    r.add_argument("--jobs", "-j", type=int, default=1, metavar="N",
                   help="worker processes (results are the same as with one)")
    r.add_argument("--wall-limit", type=float, metavar="S",
                   help="stop a run after S seconds of wall time (an error outcome; "
                        "default 300)")
    r.add_argument("--hw-emulated", action="store_true",
                   help="run through the real Kobuki and URG-04LX drivers and byte streams, "
                        "their device emulators driven by the simulator")
    c = sub.add_parser("check", help="validate scenario files without running them",
                       description="validate scenario files without running them: every "
                                   "problem of every file, as file:line: what")
    c.add_argument("paths", nargs="+", metavar="PATH")
    add_config_arguments(c, "base robot config YAML the scenarios' profiles and overrides merge "
                            "into (default: the bundled robot, unless ROS files are given)")


def check_files(files: list[str], config: Any = None) -> tuple[list, list[str]]:
    """(scenarios that loaded, every problem of every file)."""
    from executive.scenarios.parse import load_scenario
    from executive.scenarios.profiles import config_problems
    from executive.scenarios.source import ScenarioError, read_source
    loaded, errors = [], []
    for f in files:
        try:
            s = load_scenario(f)
        except ScenarioError as e:
            errors += e.errors
            continue
        try:
            errs = config_problems(s, read_source(f), config)
        except ScenarioError as e:
            errs = e.errors
        if errs:
            errors += errs
            continue
        loaded.append(s)
    return loaded, errors


def run(args: argparse.Namespace) -> int:
    import os

    from executive.scenarios.parse import load_scenario, parse_seeds, scenario_files
    from executive.scenarios.run import junit_xml, run_tasks, tasks_for, verdicts
    from executive.scenarios.source import ScenarioError
    from executive.tree_loader import TreeLoadError, load_tree_file, shipped_tree
    if args.action is None:
        return fail("scenario", "give an action: run or check (see mission scenario --help)")
    files = scenario_files(args.paths)
    if not files:
        return fail("scenario", f"no scenario files in {' '.join(args.paths)}")
    if args.action == "check":
        loaded, errors = check_files(files, config_sources(args))
        for s in loaded:
            seeds = s.run_seeds()
            print(f"{s.source}: ok ({s.name}, {len(s.goals)} goal(s), "
                  f"{len(s.events)} event(s), {len(seeds)} seed(s))")
        for e in errors:
            print(e, file=sys.stderr)
        if errors:
            print(f"scenario: {len(errors)} problem(s) in {len(files) - len(loaded)} of "
                  f"{len(files)} file(s)", file=sys.stderr)
        return 1 if errors else 0
    seeds = None
    if args.seeds is not None and args.seed is not None:
        return fail("scenario", "give --seeds or --seed, not both")
    try:
        if args.seeds is not None:
            seeds = parse_seeds(args.seeds)
        elif args.seed is not None:
            seeds = parse_seeds(str(args.seed))
    except ValueError as e:
        return fail("scenario", f"--seeds: {e}")
    if args.jobs < 1:
        return fail("scenario", "--jobs must be >= 1")
    trees = args.tree or [shipped_tree("smach_recovery")]
    for t in trees:  # fail fast: a broken tree is reported before any scenario runs
        try:
            load_tree_file(t, namespace="/scenario_check")
        except TreeLoadError as e:
            return fail("scenario", str(e))
    sources, needed = [], {}
    for f in files:
        try:
            s = load_scenario(f)
        except ScenarioError:
            s = None          # run_task reports it as this scenario's error outcome
        sources.append((f, s))
        if s is not None:
            needed[s.name] = s.needed() if seeds is None else (
                len(seeds) if s.pass_at_least is None else min(s.pass_at_least, len(seeds)))
    tasks = tasks_for(sources, trees, seeds, config_path=config_sources(args),
                      hardware="emulated" if args.hw_emulated else False,
                      wall_limit=args.wall_limit)
    if args.record:
        for t in tasks:
            stem = os.path.splitext(os.path.basename(t.tree))[0]
            name = t.scenario.name if t.scenario else os.path.splitext(
                os.path.basename(t.source))[0]
            t.record_dir = os.path.join(args.record, f"{name}__{stem}"
                                        + (f"__seed{t.seed}" if t.seed is not None else ""))
    results = run_tasks(tasks, jobs=args.jobs)
    vs = verdicts(results, needed)
    if args.junit:
        try:
            with open(args.junit, "w", encoding="utf-8") as fh:
                fh.write(junit_xml(results, vs))
        except OSError as e:
            print(f"scenario: cannot write {args.junit}: {e.strerror or e}", file=sys.stderr)
    if args.json:
        vby = {(v.scenario, v.tree): v for v in vs}
        out = []
        for r in results:   # one object per run; its scenario's verdict over all its seeds
            d = r.as_dict()
            v = vby[(r.scenario, r.tree)]
            d["verdict"] = {"met": v.met, "runs": len(v.runs), "needed": v.needed,
                            "passed": v.passed}
            out.append(d)
        print(json.dumps(out, indent=1))
    else:
        print_table(results, [os.path.splitext(os.path.basename(t))[0] for t in trees], vs)
    # a documented known_issue or a skip (absent real data) does not fail the command
    return 0 if all(v.passed or v.known_issue or v.skipped for v in vs) else 1


def _cell(r) -> str:
    word = "solved" if r.solved else r.outcome
    if r.outcome in ("error", "skipped"):
        return word
    mark = "" if r.passed else (" ?" if r.known_issue else " !")
    return f"{word} {r.sim_time:5.1f}s r={len(r.recoveries)}{mark}"


def print_table(results, tree_names: list[str], vs=None, out=None) -> None:
    """Scenario rows, one column per tree: solved/outcome, time, recoveries ('!' unexpected,
    '?' known issue); multi-seed scenarios get a row per seed and their tally."""
    from executive.scenarios.run import verdicts
    out = out if out is not None else sys.stdout
    vs = vs if vs is not None else verdicts(results, {})
    vby = {(v.scenario, v.tree): v for v in vs}
    by = {(r.scenario, r.tree, r.seed): r for r in results}
    names = list(dict.fromkeys(r.scenario for r in results))
    seeds = {n: list(dict.fromkeys(r.seed for r in results if r.scenario == n)) for n in names}
    w = max([len(n) + 8 for n in names] + [8])
    cw = max([len(t) for t in tree_names] + [24])
    out.write(f"{'scenario':{w}s}  " + "  ".join(f"{t:{cw}s}" for t in tree_names) + "\n")
    for n in names:
        multi = len(seeds[n]) > 1
        for s in seeds[n]:
            cells = []
            for t in tree_names:
                r = by.get((n, t, s))
                cells.append(f"{'-' if r is None else _cell(r):{cw}s}")
            label = f"{n} [{s}]" if multi else n
            out.write(f"{label:{w}s}  " + "  ".join(cells) + "\n")
        if multi:
            cells = []
            for t in tree_names:
                v = vby.get((n, t))
                cells.append(f"{'-' if v is None else f'{v.met}/{len(v.runs)} met (need {v.needed}): ' + ('PASS' if v.passed else 'FAIL'):{cw}s}")
            out.write(f"{n + ' tally':{w}s}  " + "  ".join(cells) + "\n")
    for t in tree_names:
        tv = [v for v in vs if v.tree == t]
        solved = sum(1 for v in tv if v.solved >= v.needed and not v.skipped)
        passed = sum(1 for v in tv if v.passed and not v.skipped)
        contacts = sum(r.collisions for r in results if r.tree == t)
        skipped = sum(1 for v in tv if v.skipped)
        out.write(f"{t}: solved {solved}/{len(tv)}, met expectation {passed}/{len(tv)}, "
                  f"contacts {contacts}" + (f", skipped {skipped}" if skipped else "") + "\n")
    for r in results:
        if not r.passed and r.outcome != "skipped":
            out.write(f"{'?' if r.known_issue else '!'} {r.scenario} [{r.seed}] / {r.tree}: "
                      f"{'; '.join(x.splitlines()[0] for x in r.failures)}"
                      + (f" ({r.reason})" if r.reason else "")
                      + (" [known issue]" if r.known_issue else "") + "\n")
    for r in results:
        if r.outcome == "skipped":
            out.write(f"- {r.scenario} / {r.tree}: skipped: {r.detail}\n")
    if any(not r.passed for r in results):
        out.write("(! unexpected, ? known issue documented in the scenario file)\n")
