"""Robustness campaign (issue 18): fixed-seed fuzzing of every user-file loader and every device
codec, and the closed-loop fault drills.

For each loader area, ``--inputs`` mutated files (default 2,000) go through the loader; each is
accepted, refused with the layer's own error (a clean error) or a crash (anything else, or a
hang past ``--hang-s``). Each codec gets ``--codec-bytes`` (default 1 MiB) of random and mutated
bytes. Every fault drill of executive/fault_drill.py reports the control periods from the first
tick at which the fault is observable to the first zero command.

    python bench/bench_robustness.py --json

prints ``<area>_inputs``, ``<area>_clean_errors``, ``<area>_crashes`` for each loader and, per
codec, ``<codec>_codec_bytes``, ``<codec>_codec_inputs`` (chunks fed), ``<codec>_codec_clean_errors``
(frames the codec refused with its own error) and ``<codec>_codec_crashes``; then
``stop_latency_<fault>_periods`` for every drill.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import sys
import tempfile
import time
import tracemalloc

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from executive import fuzz  # noqa: E402
from executive.fault_drill import FAULTS, drill  # noqa: E402


class _Hang(Exception):
    pass


def _alarm(_signum: int, _frame: object) -> None:
    raise _Hang()


def fuzz_area(area: str, n: int, seed: int, hang_s: float) -> dict[str, float]:
    rng = np.random.default_rng(seed)
    seeds = fuzz.seed_files(area)
    clean = crashes = accepted = 0
    examples: list[str] = []
    peak = 0
    signal.signal(signal.SIGALRM, _alarm)
    with tempfile.TemporaryDirectory() as folder:
        for i in range(n):
            data = fuzz.mutate(seeds[i % len(seeds)], rng)
            tracemalloc.start()
            signal.setitimer(signal.ITIMER_REAL, hang_s)
            try:
                outcome = fuzz.load(area, data, folder)
            except _Hang:
                outcome = f"crash: hang past {hang_s} s"
            finally:
                signal.setitimer(signal.ITIMER_REAL, 0)
                peak = max(peak, tracemalloc.get_traced_memory()[1])
                tracemalloc.stop()
            if outcome == "ok":
                accepted += 1
            elif outcome == "clean":
                clean += 1
            else:
                crashes += 1
                if len(examples) < 3:
                    examples.append(outcome)
    for e in examples:
        print(f"  {area}: {e}", file=sys.stderr)
    return {f"{area}_inputs": n, f"{area}_clean_errors": clean, f"{area}_accepted": accepted,
            f"{area}_crashes": crashes, f"{area}_peak_memory_mb": round(peak / 2**20, 1)}


def fuzz_codec(name: str, total: int, seed: int) -> dict[str, float]:
    fed, chunks, refused, outcome = fuzz.feed_codec(name, total, np.random.default_rng(seed))
    if outcome != "clean":
        print(f"  {name}: {outcome}", file=sys.stderr)
    return {f"{name}_codec_bytes": fed, f"{name}_codec_inputs": chunks,
            f"{name}_codec_clean_errors": refused,
            f"{name}_codec_crashes": int(outcome != "clean")}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--inputs", type=int, default=2000, help="mutated files per loader")
    ap.add_argument("--codec-bytes", type=int, default=1 << 20, help="bytes per codec")
    ap.add_argument("--seed", type=int, default=18)
    ap.add_argument("--hang-s", type=float, default=20.0, help="a load longer than this is a hang")
    ap.add_argument("--json", action="store_true", help="print one JSON object last")
    args = ap.parse_args()
    figures: dict[str, float] = {}
    t0 = time.perf_counter()
    for i, area in enumerate(fuzz.AREAS):
        figures.update(fuzz_area(area, args.inputs, args.seed + i, args.hang_s))
        if not args.json:
            print(area, {k: v for k, v in figures.items() if k.startswith(area)})
    for i, name in enumerate(fuzz.CODECS):
        figures.update(fuzz_codec(name, args.codec_bytes, args.seed + 100 + i))
    figures["fuzz_total_s"] = round(time.perf_counter() - t0, 1)
    for fault in FAULTS:
        r = drill(fault, seed=args.seed)
        figures[f"stop_latency_{fault}_periods"] = round(r.stop_periods, 2)
        if not r.moving_before:
            print(f"  {fault}: the robot was not moving when the fault began", file=sys.stderr)
    figures["crashes_total"] = sum(v for k, v in figures.items() if k.endswith("_crashes"))
    if args.json:
        print(json.dumps(figures))
    else:
        for k, v in figures.items():
            print(f"{k}: {v}")


if __name__ == "__main__":
    main()
