"""Sweep throughput: runs per second on one and two local workers, and what Dask adds per run.

A fixed small sweep (two rooms, one with a box the map does not know, 4 seeds x 3 speeds = 24
runs of the SMACH-style tree) runs on warm workers (the numba kernels loaded, as a sweep's
workers are after ``warm_worker``), so the figures are the sweep's steady state:

    python bench/bench_sweep.py [--json] [--seeds N] [--rounds R]

``scaling_2_workers`` is runs/s on two workers over runs/s on one; ``dask_overhead_ms_per_run``
is the wall time a Dask LocalCluster (two workers) spends per run beyond the process pool's (same
runs), set against ``median_run_ms`` (the median wall time of one run in-process). Each executor
runs the sweep ``--rounds`` times, alternating, and its fastest round counts: on a machine shared
with other work a round is slowed by whatever else ran, never sped up. ``dask_extra_cpu_ms_per_run``
is the CPU time (all processes: workers, nannies, scheduler, client) the Dask round used per run
beyond the pool's: what Dask costs with the noise of other users' load taken out. On Linux a last pass reads each
run thread's ``/proc/thread-self/schedstat`` around the run, on the pool and on Dask:
``run_gil_wait_ms_*`` (wall minus time on a core minus time waiting for one: the run thread
asleep, waiting for the GIL) and ``run_switches_*`` (times the run thread was put on a core);
these hold up on a loaded machine where wall times do not.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import yaml  # noqa: E402

from executive.sweeps.runner import Executor, dask_client, run_task, warm_worker  # noqa: E402
from executive.sweeps.spec import load_sweep  # noqa: E402

_ROOM = "\n".join(["#" * 34] + ["#" + "." * 32 + "#"] * 20 + ["#" * 34])
SCENARIOS = {
    "straight": {"map": {"resolution": 0.1, "ascii": _ROOM}, "start": [0.6, 0.6, 0.0],
                 "goals": [[2.6, 0.6, 0.0]], "time_limit": 30},
    "past_box": {"map": {"resolution": 0.1, "ascii": _ROOM}, "start": [0.6, 0.7, 0.0],
                 "goals": [[2.8, 0.7, 0.0]], "objects": [{"box": [1.5, 0.3, 1.7, 0.95]}],
                 "time_limit": 30},
}


def make_sweep(folder: str, seeds: int) -> str:
    os.makedirs(os.path.join(folder, "scenarios"), exist_ok=True)
    for name, doc in SCENARIOS.items():
        with open(os.path.join(folder, "scenarios", f"{name}.yaml"), "w", encoding="utf-8") as f:
            yaml.safe_dump(dict(doc, name=name), f)
    path = os.path.join(folder, "sweep.yaml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"name: bench\nscenarios: 'scenarios/*.yaml'\nseeds: 1..{seeds}\n"
                "grid:\n  DWAPlannerROS.max_vel_x: [0.3, 0.45, 0.55]\n")
    return path


def _cpu_s() -> float:
    """CPU seconds used so far by this process and its live children (psutil comes with dask)."""
    import psutil
    me = psutil.Process()
    total = 0.0
    for p in [me] + me.children(recursive=True):
        try:
            t = p.cpu_times()
            total += t.user + t.system
        except psutil.NoSuchProcess:
            pass
    return total


def time_executor(tasks: list, workers: int, dask: str | None = None
                  ) -> tuple[float, float | None, list[dict]]:
    """Wall and CPU time (None without psutil) of the tasks on ``workers`` warm workers (a first
    batch starts and warms them)."""
    try:
        _cpu_s()
        cpu = _cpu_s
    except ImportError:
        cpu = None
    records: list[dict] = []
    with Executor(workers, dask) as ex:
        ex.run(tasks[:2 * workers], lambda t, r, timing: None)
        c0 = cpu() if cpu else 0.0
        t0 = time.perf_counter()
        ex.run(tasks, lambda t, r, timing: records.append(dict(r, **timing)))
        wall = time.perf_counter() - t0
        used = cpu() - c0 if cpu else None
    return wall, used, records


SCHEDSTAT = "/proc/thread-self/schedstat"


def _sched() -> tuple[float, float, int]:
    with open(SCHEDSTAT, encoding="ascii") as f:
        on_core_ns, waiting_ns, switches = map(int, f.read().split())
    return on_core_ns / 1e9, waiting_ns / 1e9, switches


def sched_run(task) -> tuple[float, int]:
    """run_task, and how long its thread slept (GIL) and how often it was put on a core."""
    s0, t0 = _sched(), time.perf_counter()
    run_task(task)
    wall, s1 = time.perf_counter() - t0, _sched()
    return wall - (s1[0] - s0[0]) - (s1[1] - s0[1]), s1[2] - s0[2]


def sched_figures(tasks: list) -> dict[str, float]:
    """Mean GIL wait and switches per run, on a 2-process pool and on a 2-worker LocalCluster."""
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor
    out: dict[str, float] = {}
    with ProcessPoolExecutor(2, mp_context=mp.get_context("spawn"),
                             initializer=warm_worker) as pool:
        list(pool.map(sched_run, tasks[:4]))
        res = list(pool.map(sched_run, tasks))
    out["pool"] = res
    try:
        client = dask_client("local", 2)
    except RuntimeError:
        return {}
    try:
        client.gather(client.map(sched_run, tasks[:4], pure=False))
        out["dask"] = client.gather(client.map(sched_run, tasks, pure=False))
    finally:
        cluster = client.cluster
        client.close()
        cluster.close()
    figures: dict[str, float] = {}
    for k, res in out.items():
        figures[f"run_gil_wait_ms_{k}"] = round(1000 * statistics.mean(r[0] for r in res), 2)
        figures[f"run_switches_{k}"] = round(statistics.mean(r[1] for r in res), 1)
    return figures


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    walls: dict[str, list[float]] = {"1": [], "2": [], "dask": []}
    cpus: dict[str, list[float]] = {"2": [], "dask": []}
    run_ms: list[float] = []
    with tempfile.TemporaryDirectory() as d:
        tasks = load_sweep(make_sweep(d, args.seeds)).tasks()
        for _ in range(args.rounds):
            wall, _, recs = time_executor(tasks, 1)
            walls["1"].append(wall)
            run_ms.append(1000 * statistics.median(r["wall_time_s"] for r in recs))
            wall, used, _ = time_executor(tasks, 2)
            walls["2"].append(wall)
            cpus["2"].append(used)
            try:
                wall, used, _ = time_executor(tasks, 2, dask="local")
            except RuntimeError:   # dask.distributed not installed
                continue
            walls["dask"].append(wall)
            cpus["dask"].append(used)
        sched = sched_figures(tasks) if os.path.exists(SCHEDSTAT) else {}
    n = len(tasks)
    wall1, wall2 = min(walls["1"]), min(walls["2"])
    median_run_ms = min(run_ms)
    figures = {"runs": n, "rounds": args.rounds, "runs_per_s_1_worker": round(n / wall1, 2),
               "runs_per_s_2_workers": round(n / wall2, 2),
               "scaling_2_workers": round(wall1 / wall2, 3),
               "median_run_ms": round(median_run_ms, 1)}
    if walls["dask"]:
        overhead = 1000 * (min(walls["dask"]) - wall2) * 2 / n   # two workers: per-run share
        figures["dask_overhead_ms_per_run"] = round(overhead, 2)
        figures["dask_overhead_share_of_median_run"] = round(overhead / median_run_ms, 3)
        if None not in cpus["2"] + cpus["dask"]:
            extra = [1000 * (c_dask - c_pool) / n for c_dask, c_pool in zip(cpus["dask"], cpus["2"])]
            figures["dask_extra_cpu_ms_per_run"] = round(statistics.median(extra), 2)
    figures.update(sched)
    figures["load_1min"] = round(os.getloadavg()[0], 2)
    if not args.json:
        for k, v in figures.items():
            print(f"{k:36s} {v}")
    print(json.dumps(figures) if args.json else "")


if __name__ == "__main__":
    main()
