"""``mission tune SPEC.yaml``: an Optuna search over the sweep file's ``search:`` space."""

from __future__ import annotations

import argparse
import os

from executive.commands._common import fail


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("spec", metavar="SPEC", help="a sweep file with a 'search:' section")
    p.add_argument("--out", metavar="DIR", help="results and study folder "
                                                "(default runs/tune/NAME)")
    p.add_argument("--trials", type=int, metavar="N", help="trials (default: the file's "
                                                           "'trials', else 20)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, metavar="N",
                   help="worker processes for each trial's runs")
    p.add_argument("--dask", metavar="ADDRESS", help="run each trial's runs on Dask")


def run(args: argparse.Namespace) -> int:
    from executive.sweeps.spec import SweepError, load_sweep
    from executive.sweeps.tune import tune
    try:
        spec = load_sweep(args.spec)
    except SweepError as e:
        return fail("tune", str(e))
    if args.trials is not None and args.trials < 1:
        return fail("tune", "--trials must be at least 1")
    try:
        result = tune(spec, args.out or os.path.join("runs", "tune", spec.name),
                      jobs=args.jobs, dask=args.dask, trials=args.trials)
    except (RuntimeError, ValueError) as e:
        return fail("tune", str(e))
    return 0 if result.get("best") is not None else 1
