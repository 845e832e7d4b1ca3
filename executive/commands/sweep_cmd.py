"""``mission sweep SPEC.yaml`` runs a parameter / tree sweep (resumable);
``mission sweep report RESULTS`` prints its table and draws its pictures."""

from __future__ import annotations

import argparse
import os
import sys

from executive.commands._common import fail


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("paths", nargs="+", metavar="SPEC | report RESULTS",
                   help="a sweep file to run, or 'report' and a results folder")
    p.add_argument("--out", metavar="DIR",
                   help="results folder (default runs/sweeps/NAME); for report: where the "
                        "pictures go (default RESULTS/report)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, metavar="N",
                   help="worker processes (default: the number of cores; 1 runs in-process)")
    p.add_argument("--dask", metavar="ADDRESS",
                   help="run on Dask: a scheduler address (tcp://host:8786) or 'local' for a "
                        "LocalCluster of --jobs workers")
    p.add_argument("--check", action="store_true", help="check the sweep file and stop")
    p.add_argument("--no-runs", action="store_true",
                   help="report: do not re-run the best and worst runs to draw their run.png")


def _default_out(name: str) -> str:
    return os.path.join("runs", "sweeps", name)


def run(args: argparse.Namespace) -> int:
    from executive.sweeps.spec import SweepError, load_sweep
    if args.paths[0] == "report":
        if len(args.paths) != 2:
            return fail("sweep", "report takes one results folder: mission sweep report DIR")
        return report(args.paths[1], args.out, runs=not args.no_runs)
    if len(args.paths) != 1:
        return fail("sweep", "give one sweep file (or: mission sweep report RESULTS)")
    if args.jobs < 1:
        return fail("sweep", f"--jobs must be at least 1, got {args.jobs}")
    try:
        spec = load_sweep(args.paths[0])
    except SweepError as e:
        return fail("sweep", str(e))
    if args.check:
        print(f"{spec.source}: ok ({len(spec.tasks())} runs)")
        return 0
    from executive.sweeps.store import StoreError
    from executive.sweeps.sweep import run_sweep
    out = args.out or _default_out(spec.name)
    try:
        summary = run_sweep(spec, out, jobs=args.jobs, dask=args.dask)
    except (StoreError, RuntimeError) as e:
        return fail("sweep", str(e))
    print(f"sweep {spec.name}: ran {summary.ran} ({summary.errors} errors), skipped "
          f"{summary.skipped} finished, {summary.wall_s:.1f} s; results in {summary.store}")
    return 0


def report(results: str, out_dir: str | None, runs: bool = True) -> int:
    from executive.sweeps.report import best_and_worst, point_stats, write_report
    from executive.sweeps.store import ResultStore, StoreError
    try:
        store = ResultStore.open_existing(results)
    except StoreError as e:
        return fail("sweep", str(e))
    records = store.records()
    name = store.meta("name", "sweep")
    spec_path = store.meta("spec_path")
    store.close()
    if not records:
        return fail("sweep", f"{results}: no finished runs yet")
    out_dir = out_dir or os.path.join(os.path.dirname(store.path), "report")
    write_report(records, out_dir, sys.stdout, name=name)
    if runs and spec_path and os.path.isfile(spec_path):
        _draw_extremes(records, spec_path, out_dir, point_stats, best_and_worst)
    return 0


def _draw_extremes(records, spec_path, out_dir, point_stats, best_and_worst) -> None:
    """Re-run (deterministic: same seed, same run) the best point's fastest solved run and the
    worst point's first unsolved run with a run folder, for their run.png."""
    import json

    from executive.sweeps.apply import apply_point, tree_with_ports
    from executive.sweeps.spec import SweepError, load_sweep
    from executive.scenario import load_scenario, run_scenario
    try:
        spec = load_sweep(spec_path)
    except SweepError as e:
        print(f"(best/worst runs not drawn: {e})")
        return
    tasks = {t.run_id: t for t in spec.tasks()}
    pair = best_and_worst(point_stats(records))
    if pair is None:
        return
    for label, stats, want_solved in (("best", pair[0], True), ("worst", pair[1], False)):
        cands = [r for r in records if r["tree"] == stats.tree
                 and json.dumps(r["point"], sort_keys=True) == json.dumps(stats.point,
                                                                          sort_keys=True)
                 and r["run_id"] in tasks]
        pick = [r for r in cands if bool(r["solved"]) == want_solved] or cands
        if not pick:
            continue
        pick.sort(key=lambda r: (r["sim_time_s"] or 0.0) * (1 if want_solved else -1))
        t = tasks[pick[0]["run_id"]]
        folder = os.path.join(out_dir, f"{label}_run")
        s = apply_point(load_scenario(t.scenario), dict(t.point), t.config, seed=t.seed,
                        time_limit=t.time_limit)
        run_scenario(s, tree_with_ports(t.tree, dict(t.point)), record_dir=folder,
                     config_path=t.config)
        print(f"wrote {os.path.join(folder, 'run.png')} ({label}: {pick[0]['scenario']} "
              f"seed {t.seed}, {stats.point})")
