"""``run_sweep``: every (scenario, seed, tree, point) of a sweep file, resumable.

The store is opened first; runs whose id it already holds are skipped, so a sweep that was
killed (or crashed, or ran out of time) is resumed by running the same command again, and a
finished point is never run twice. Each result is written the moment it arrives.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass
from typing import Any, TextIO

from executive.sweeps.runner import Executor
from executive.sweeps.spec import RunTask, SweepSpec
from executive.sweeps.store import ResultStore


@dataclass
class SweepSummary:
    planned: int
    skipped: int
    ran: int
    errors: int
    wall_s: float
    store: str


class Progress:
    """One line on a terminal, rewritten in place (done/total, rate, ETA); silent otherwise."""

    def __init__(self, total: int, out: TextIO = sys.stderr) -> None:
        self.total, self.done, self.out = total, 0, out
        self.t0 = time.perf_counter()
        self.tty = hasattr(out, "isatty") and out.isatty()

    def step(self, label: str = "") -> None:
        self.done += 1
        if not self.tty:
            return
        dt = time.perf_counter() - self.t0
        rate = self.done / dt if dt > 0 else 0.0
        eta = (self.total - self.done) / rate if rate > 0 else 0.0
        self.out.write(f"\r  {self.done}/{self.total} runs  {rate:.2f} runs/s  "
                       f"ETA {eta:.0f} s  {label[:40]:40s}")
        self.out.flush()

    def close(self) -> None:
        if self.tty:
            self.out.write("\n")


class _ResultWriter:
    """The executor's ``on_result``: each result into the store as it arrives, the error
    records counted, the progress line stepped."""

    def __init__(self, store: ResultStore, progress: Progress | None) -> None:
        self.store, self.progress = store, progress
        self.errors = 0

    def __call__(self, task: RunTask, record: dict[str, Any], timing: dict[str, Any]) -> None:
        self.store.add(record, timing)
        self.errors += record["outcome"] == "error"
        if self.progress is not None:
            self.progress.step(f"{record['scenario']} {record['outcome']}")


def run_tasks(tasks: list[RunTask], store: ResultStore, executor: Executor,
              progress: Progress | None = None) -> int:
    """Run ``tasks`` on ``executor``, writing each result to ``store`` as it arrives; returns
    the number of error records."""
    writer = _ResultWriter(store, progress)
    executor.run(tasks, writer)
    return writer.errors


def run_sweep(spec: SweepSpec, out_dir: str, jobs: int = 1, dask: str | None = None,
              out: TextIO = sys.stdout) -> SweepSummary:
    """Run (or resume) a sweep into ``out_dir/results.sqlite``."""
    t0 = time.perf_counter()
    store = ResultStore(out_dir)
    try:
        tasks = spec.tasks()
        finished = store.finished_ids()
        todo = [t for t in tasks if t.run_id not in finished]
        skipped = len(tasks) - len(todo)
        with open(spec.source, encoding="utf-8") as f:
            spec_text = f.read()
        session = store.begin(len(tasks), skipped, spec_text)
        store.set_meta("name", spec.name)
        store.set_meta("spec_path", os.path.abspath(spec.source))
        store.set_meta("parameters", sorted({k for p in spec.points for k in p}))
        where = f"Dask {dask}" if dask else (f"{jobs} processes" if jobs > 1 else "1 process")
        out.write(f"sweep {spec.name}: {len(tasks)} runs ({len(spec.scenarios)} scenarios, "
                  f"{len(spec.points)} points, {len(spec.trees)} trees); "
                  f"{skipped} already finished, {len(todo)} to run on {where} "
                  f"(session {session})\n")
        out.flush()
        progress = Progress(len(todo))
        with Executor(jobs, dask) as executor:
            errors = run_tasks(todo, store, executor, progress=progress)
        progress.close()
        return SweepSummary(len(tasks), skipped, len(todo), errors,
                            time.perf_counter() - t0, store.path)
    finally:
        store.close()
