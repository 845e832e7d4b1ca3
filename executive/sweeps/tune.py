"""``mission tune``: search a sweep file's ``search:`` space with Optuna instead of a grid.

Each trial is one point, run over every (scenario, seed, tree) of the sweep; its runs go to the
same results store as a grid sweep's (so a resumed study never re-runs a finished run). The
objective is lexicographic: the success rate first, then the mean simulated time of the solved
runs (as a tie-break smaller than one run's worth of success rate); contacts are a hard
constraint (``Trial.set_constraint``: a point with any contact is infeasible). The study is
stored beside the results (``study.sqlite``) and the best feasible point is written as a robot
config overlay (``best_config.yaml``) and, when it sets tree ports, a tree file beside it.
"""

from __future__ import annotations

import os
import sys
from typing import Any, TextIO

import yaml

from executive.sweeps.apply import merged_params, split_point, tree_with_ports
from executive.sweeps.runner import Executor
from executive.sweeps.spec import RunTask, SearchDim, SweepSpec
from executive.sweeps.store import ResultStore
from executive.sweeps.sweep import run_tasks


def score(records: list[dict[str, Any]], time_limit: float) -> tuple[float, int]:
    """(objective to maximise, contacts) of one point's runs."""
    n = len(records)
    solved = [r for r in records if r["solved"]]
    rate = len(solved) / n if n else 0.0
    mean_t = sum(r["sim_time_s"] for r in solved) / len(solved) if solved else time_limit
    # below half a run's worth of success rate, so a faster point never beats a more successful one
    tie = min(mean_t, time_limit) / time_limit / (2 * max(n, 1))
    return rate - tie, sum(r["contacts"] or 0 for r in records)


def _suggest(trial: Any, d: SearchDim) -> Any:
    if d.choices:
        return trial.suggest_categorical(d.key, list(d.choices))
    if d.integer:
        return trial.suggest_int(d.key, int(d.low), int(d.high), step=int(d.step or 1),
                                 log=d.log)
    return trial.suggest_float(d.key, d.low, d.high, step=d.step, log=d.log)


class _Objective:
    """One Optuna trial: the suggested point (over ``fixed``) run over every base task on
    ``executor`` into ``store``, scored by ``score``, contacts set as its constraint."""

    def __init__(self, spec: SweepSpec, fixed: dict[str, Any], base_tasks: list[RunTask],
                 limit: float, store: ResultStore, executor: Executor, out: TextIO) -> None:
        self.spec, self.fixed, self.base_tasks, self.limit = spec, fixed, base_tasks, limit
        self.store, self.executor, self.out = store, executor, out

    def __call__(self, trial: Any) -> float:
        store = self.store
        point = dict(self.fixed)
        point.update({d.key: _suggest(trial, d) for d in self.spec.search})
        tasks = [RunTask(t.scenario, t.seed, t.tree, tuple(sorted(point.items())), t.config,
                         t.time_limit) for t in self.base_tasks]
        finished = store.finished_ids()
        run_tasks([t for t in tasks if t.run_id not in finished], store, self.executor)
        ids = {t.run_id for t in tasks}
        records = [r for r in store.records() if r["run_id"] in ids]
        value, contacts = score(records, self.limit)
        trial.set_user_attr("contacts", contacts)
        trial.set_constraint("contacts", float(contacts))   # feasible when <= 0
        trial.set_user_attr("success_rate", sum(r["solved"] for r in records) / len(records))
        self.out.write(f"  trial {trial.number}: {point} -> success "
                       f"{100 * trial.user_attrs['success_rate']:.0f}%, contacts {contacts}\n")
        return value


def tune(spec: SweepSpec, out_dir: str, jobs: int = 1, dask: str | None = None,
         trials: int | None = None, out: TextIO = sys.stdout) -> dict[str, Any]:
    """Run an Optuna study over ``spec.search``; returns the best point and its score."""
    try:
        import optuna
    except ImportError:
        raise RuntimeError("mission tune needs optuna: pip install 'navbt[sweep]'") from None
    if not spec.search:
        raise ValueError(f"{spec.source}: mission tune needs a 'search:' section")
    os.makedirs(out_dir, exist_ok=True)
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    store = ResultStore(out_dir)
    fixed = spec.points[0] if len(spec.points) == 1 else {}
    base_tasks = spec.tasks([{}])
    limit = max((t.time_limit or 0.0) for t in base_tasks) or 600.0

    sampler = optuna.samplers.TPESampler(seed=spec.sampler_seed)
    study = optuna.create_study(study_name=spec.name, direction="maximize", sampler=sampler,
                                storage=f"sqlite:///{os.path.join(out_dir, 'study.sqlite')}",
                                load_if_exists=True)
    store.begin(0, 0)
    done_trials = len([t for t in study.trials if t.state.is_finished()])
    todo = max(0, (trials or spec.trials) - done_trials)
    out.write(f"tune {spec.name}: {done_trials} trials done, {todo} to run, "
              f"{len(base_tasks)} runs per trial\n")

    with Executor(jobs, dask) as executor:   # one set of warm workers for every trial
        study.optimize(_Objective(spec, fixed, base_tasks, limit, store, executor, out),
                       n_trials=todo)
    feasible = [t for t in study.trials if t.state.is_finished() and t.value is not None
                and t.user_attrs.get("contacts", 1) == 0]
    store.close()
    if not feasible:
        out.write("no feasible point (every trial had contacts)\n")
        return {"best": None}
    best = max(feasible, key=lambda t: (t.value, -t.number))
    point = dict(fixed)
    point.update(best.params)
    written = write_best(point, spec, out_dir)
    out.write(f"best: {point} (success {100 * best.user_attrs['success_rate']:.0f}%, "
              f"score {best.value:.4f}); wrote {', '.join(written)}\n")
    return {"best": point, "value": best.value, "files": written}


def write_best(point: dict[str, Any], spec: SweepSpec, out_dir: str) -> list[str]:
    """A ready-to-use robot config overlay (and tree with the ports set) for ``point``."""
    params, ports = split_point(point)
    written = []
    overlay = merged_params({}, params)
    path = os.path.join(out_dir, "best_config.yaml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"# best point of the study '{spec.name}': paste into your robot config\n")
        yaml.safe_dump(overlay, f, sort_keys=True)
    written.append(path)
    if ports:
        tree_dir = os.path.join(out_dir, "best_trees")
        os.makedirs(tree_dir, exist_ok=True)
        for t in spec.trees:
            written.append(tree_with_ports(t, point, tree_dir))
    return written
