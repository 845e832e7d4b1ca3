"""Running a sweep's runs: one run in a worker, and the executors that spread them.

``run_task`` is the whole job of a worker: load the scenario, apply the point, run it in the
simulator, return the record. It never raises: a run that fails is an ``error`` record, and the
sweep goes on. Executors: in-process (``jobs=1``), a process pool on the local cores, or Dask
(``dask.distributed``: a scheduler address or a LocalCluster). Each worker warms the numba kernels
once when it starts (``warm_worker``), not once per run. Results come back in completion order
and are written to the store one by one by the caller's ``on_result``.
"""

from __future__ import annotations

import os
import socket
import tempfile
import time
import traceback
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Callable, Iterable

from executive.sweeps.spec import RunTask

OnResult = Callable[[RunTask, dict[str, Any], dict[str, Any]], None]
MAX_WORKER_DEATHS = 2   # a run whose worker died this often is recorded as an error

_scenarios: dict[str, Any] = {}
_tree_dir: str | None = None
warmed = False   # this process has run warm_worker


def navbt_version() -> str:
    try:
        from importlib.metadata import version
        return version("navbt")
    except Exception:  # noqa: BLE001 - not installed (a source checkout on sys.path)
        return "unknown"


def warm_worker() -> str:
    """Compile (or load from numba's cache) the kernels a run needs, once per worker process."""
    global warmed
    from executive.scenario import run_scenario, scenario_from_mapping
    from executive.tree_loader import shipped_tree
    doc = {"name": "warmup", "map": {"resolution": 0.1, "ascii": "\n".join(
        ["#" * 24] + ["#" + "." * 22 + "#"] * 10 + ["#" * 24])},
        "start": [0.5, 0.5, 0.0], "goals": [[1.5, 0.5, 0.0]], "time_limit": 5}
    run_scenario(scenario_from_mapping(doc, "<warmup>"), shipped_tree("smach_recovery"))
    warmed = True
    return f"{socket.gethostname()}:{os.getpid()}"


def _scenario(path: str) -> Any:
    from executive.scenario import load_scenario
    if path not in _scenarios:
        _scenarios[path] = load_scenario(path)
    return _scenarios[path]


class PoseLog:
    """The body's true pose after each cycle of a run (``run_scenario``'s ``on_tick``), for the
    clearance and turning metrics."""

    def __init__(self) -> None:
        self.poses: list[tuple[float, float, float]] = []

    def on_tick(self, ex: Any) -> None:
        p = ex.io.true_pose()
        if p is not None:
            self.poses.append((p.x, p.y, p.theta))


def run_task(task: RunTask) -> tuple[dict[str, Any], dict[str, Any]]:
    """Run one task; returns (record, timing). Never raises."""
    global _tree_dir
    t0 = time.perf_counter()
    point = dict(task.point)
    record = _error_record(task, None)   # filled in as the run gets on
    try:
        from executive.scenario import run_scenario
        from executive.sweeps.apply import apply_point, tree_with_ports
        from executive.sweeps.metrics import min_clearance, turning_per_metre
        scenario = apply_point(_scenario(task.scenario), point, task.config, seed=task.seed,
                               time_limit=task.time_limit)
        if _tree_dir is None:
            _tree_dir = tempfile.mkdtemp(prefix="navbt-sweep-")
        sub = os.path.join(_tree_dir, task.run_id)
        os.makedirs(sub, exist_ok=True)
        tree = tree_with_ports(task.tree, point, sub)
        log = PoseLog()
        r = run_scenario(scenario, tree, config_path=task.config, on_tick=log.on_tick)
        clearance = min_clearance(log.poses, scenario.grid, scenario.objects)
        turning = turning_per_metre(log.poses)
        record.update(outcome=r.outcome, reason=r.reason or None, passed=int(r.passed),
                      solved=int(r.solved), sim_time_s=round(r.sim_time, 6),
                      recoveries=r.recovery_types, n_recoveries=len(r.recoveries),
                      contacts=int(r.collisions), path_length_m=round(r.distance, 6),
                      min_clearance_m=None if clearance is None else round(clearance, 6),
                      turning_rad_per_m=None if turning is None else round(turning, 6),
                      goals_reached=int(r.goals_reached), goals_total=len(scenario.goals))
    except Exception as e:  # noqa: BLE001 - one broken run is that run's error, never the sweep's
        tb = traceback.extract_tb(e.__traceback__)
        at = f" at {os.path.basename(tb[-1].filename)}:{tb[-1].lineno}" if tb else ""
        record["error"] = f"{type(e).__name__}: {e}{at}"
    timing = {"wall_time_s": round(time.perf_counter() - t0, 4),
              "worker": f"{socket.gethostname()}:{os.getpid()}"}
    return record, timing


def _error_record(task: RunTask, why: str | None) -> dict[str, Any]:
    """The record of a run that did not finish (``why``: the error; None while it runs)."""
    return {"run_id": task.run_id, "scenario": os.path.basename(task.scenario),
            "seed": task.seed, "tree": os.path.splitext(os.path.basename(task.tree))[0],
            "point": dict(task.point), "outcome": "error", "reason": None, "passed": 0,
            "solved": 0, "sim_time_s": None, "recoveries": [], "n_recoveries": 0,
            "contacts": None, "path_length_m": None, "min_clearance_m": None,
            "turning_rad_per_m": None, "goals_reached": None, "goals_total": None,
            "error": why, "navbt_version": navbt_version()}


# --------------------------------------------------------------------------- executors
def run_serial(tasks: Iterable[RunTask], on_result: OnResult) -> None:
    """In this process, one after another."""
    for t in tasks:
        record, timing = run_task(t)
        on_result(t, record, timing)


class Executor:
    """Where runs go: this process (``jobs=1``), a pool of ``jobs`` local processes, or Dask.
    Kept open across batches (a study's trials), so its workers start and warm once."""

    def __init__(self, jobs: int = 1, dask: str | None = None) -> None:
        self.jobs, self.dask = max(1, jobs), dask
        self._pool: ProcessPoolExecutor | None = None
        self._client: Any = None

    def __enter__(self) -> "Executor":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def run(self, tasks: list[RunTask], on_result: OnResult) -> None:
        if not tasks:
            return
        if self.dask:
            if self._client is None:
                self._client = dask_client(self.dask, self.jobs)
            run_dask(tasks, self._client, on_result)
        elif self.jobs == 1:
            run_serial(tasks, on_result)
        else:
            self._run_pool(tasks, on_result)

    def _new_pool(self) -> ProcessPoolExecutor:
        import multiprocessing as mp
        # spawn: no fork of a process that holds threads and open files
        return ProcessPoolExecutor(max_workers=self.jobs, mp_context=mp.get_context("spawn"),
                                   initializer=warm_worker)

    def _run_pool(self, tasks: list[RunTask], on_result: OnResult) -> None:
        """A worker that dies (killed, out of memory) breaks the pool: a new pool takes over the
        unfinished runs; a run whose worker died ``MAX_WORKER_DEATHS`` times is an error."""
        pending = list(tasks)
        deaths: dict[str, int] = {}
        while pending:
            if self._pool is None:
                self._pool = self._new_pool()
            queue = list(pending)
            running: dict[Future, RunTask] = {}
            broken = False
            while (queue or running) and not broken:
                while queue and len(running) < 2 * self.jobs:
                    t = queue.pop(0)
                    running[self._pool.submit(run_task, t)] = t
                done, _ = wait(running, return_when=FIRST_COMPLETED)
                for f in done:
                    t = running.pop(f)
                    try:
                        record, timing = f.result()
                    except BrokenProcessPool:
                        broken = True
                        deaths[t.run_id] = deaths.get(t.run_id, 0) + 1
                        if deaths[t.run_id] >= MAX_WORKER_DEATHS:
                            pending.remove(t)
                            on_result(t, _error_record(t, "worker process died while running "
                                                          "this run"), {"worker": "?"})
                        continue
                    pending.remove(t)
                    on_result(t, record, timing)
            if broken:
                for f, t in running.items():   # the rest of the in-flight runs died with it
                    if f.done() and not f.cancelled() and f.exception() is None:
                        record, timing = f.result()
                        pending.remove(t)
                        on_result(t, record, timing)
                self._pool.shutdown(wait=False, cancel_futures=True)
                self._pool = None

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None
        if self._client is not None:
            cluster = getattr(self._client, "cluster", None)
            if self.dask != "local":   # leave a shared cluster as we found it
                from executive.sweeps.dask_plugin import WarmKernels
                try:
                    self._client.unregister_worker_plugin(WarmKernels.name)
                except Exception:  # noqa: BLE001 - scheduler gone: nothing left to clean
                    pass
            self._client.close()
            if cluster is not None and self.dask == "local":
                cluster.close()
            self._client = None


def dask_client(address: str, jobs: int) -> Any:
    """A dask.distributed Client whose workers warm their kernels once (``WarmKernels``):
    ``local`` starts a LocalCluster of ``jobs`` single-threaded worker processes on 127.0.0.1;
    anything else is a scheduler address (tcp://host:8786)."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise RuntimeError("--dask needs dask.distributed: pip install 'navbt[sweep]'") from None
    if address == "local":
        import dask
        with dask.config.set(QUIET_WORKERS):   # the nannies hand this config to their workers
            cluster = LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True,
                                   host="127.0.0.1", dashboard_address=None)
        client = Client(cluster)
    else:
        client = Client(address)
    from executive.sweeps.dask_plugin import WarmKernels
    client.register_plugin(WarmKernels())   # returns when every present worker is warm
    return client


# What a LocalCluster's workers do besides running tasks, slowed to what a sweep needs. By
# default every worker wakes its event loop ~170 times a second (the statistical profiler walks
# the task thread's stack every 10 ms, the tick monitor every 20 ms, the system monitor every
# 500 ms): each wake-up takes the GIL from the run, and on a loaded machine the run thread then
# waits for a core again. A sweep reads no profiles; blocked-loop warnings (>3 s) and memory limits
# still work at 1 s. docs/sweeps.md gives the same settings as environment variables for
# `dask worker` on a real cluster.
QUIET_WORKERS = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.worker.memory.monitor-interval": "1s",
}


def run_tasks(tasks: list[RunTask]) -> list[tuple[dict[str, Any], dict[str, Any]]]:
    """``run_task`` for each of a few runs: one Dask task (see ``run_dask``)."""
    return [run_task(t) for t in tasks]


# Runs per Dask task. Each task costs Dask's processes ~15-20 ms of CPU (scheduler, worker
# event loop, result hand-over: docs/performance.md), a fifth of a 0.1 s run on two cores; a few
# runs per task divide it, while TASKS_PER_WORKER tasks for each worker keep the load balanced.
# A run's record is written when its task ends, so a killed sweep reruns at most the runs of the
# tasks in flight (MAX_RUNS_PER_TASK each), as a pool reruns the runs in flight.
MAX_RUNS_PER_TASK = 4
TASKS_PER_WORKER = 4


def chunk_size(n_tasks: int, n_workers: int) -> int:
    """How many runs go in one Dask task for ``n_tasks`` runs on ``n_workers`` workers."""
    return max(1, min(MAX_RUNS_PER_TASK, n_tasks // (TASKS_PER_WORKER * max(1, n_workers))))


def run_dask(tasks: list[RunTask], client: Any, on_result: OnResult) -> None:
    """On a Dask cluster whose workers are warm (``WarmKernels``), a few runs per task
    (``chunk_size``); results are written run by run as each task ends. Dask re-runs a task
    whose worker died; a task that keeps killing workers is split and its runs tried one by one,
    so the run that kills its worker is the one recorded as an error."""
    from dask.distributed import as_completed
    workers = len(client.scheduler_info().get("workers", {})) or 1
    k = chunk_size(len(tasks), workers)
    chunks = [tasks[i:i + k] for i in range(0, len(tasks), k)]
    futures = client.map(run_tasks, chunks, pure=False)
    by_key = {f.key: c for f, c in zip(futures, chunks)}
    done = as_completed(futures)
    for f in done:
        chunk = by_key.pop(f.key)
        try:
            results = f.result()
        except Exception as e:  # noqa: BLE001 - KilledWorker and friends
            if len(chunk) > 1:   # try its runs alone: only the culprit becomes an error
                for t in chunk:
                    g = client.submit(run_tasks, [t], pure=False)
                    by_key[g.key] = [t]
                    done.add(g)
            else:
                t = chunk[0]
                on_result(t, _error_record(t, f"{type(e).__name__}: {e}"), {"worker": "?"})
            f.release()
            continue
        for t, (record, timing) in zip(chunk, results):
            on_result(t, record, timing)
        f.release()
