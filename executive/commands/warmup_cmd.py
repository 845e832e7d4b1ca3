"""``mission warmup``: compile the numba kernels a simulated mission uses, once, into numba's cache.

numba compiles a kernel the first time it is called and keeps the machine code in its cache
(``__pycache__`` beside the sources, or ``$NUMBA_CACHE_DIR``); later runs load it in
milliseconds. The first mission after an install therefore spends most of its time compiling.
This command pays that cost up front by running the demo scenario once with nothing recorded,
which calls exactly the kernels a mission on the simulator calls, with the same argument types.
"""

from __future__ import annotations

import argparse
import sys
from typing import TextIO


def _cache_probe() -> int:
    return 1


def kernels_cold() -> bool:
    """True when numba's cache had no machine code for this installation yet (the probe kernel,
    cached like all others, had to be compiled): the first run after an install or upgrade."""
    from numba import njit  # not at import: `mission --help` imports every command module
    probe = njit(cache=True)(_cache_probe)
    probe()
    stats = getattr(probe, "stats", None)  # plain function under NUMBA_DISABLE_JIT
    return bool(stats is not None and stats.cache_misses)


def announce_compiling(stream: TextIO | None = None) -> bool:
    """On a terminal with a cold cache, say that the pause to come is compilation; True if said."""
    stream = stream if stream is not None else sys.stdout
    if not getattr(stream, "isatty", lambda: False)() or not kernels_cold():
        return False
    stream.write("compiling kernels (first run only; `mission warmup` does it ahead)...\n")
    stream.flush()
    return True


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--quiet", action="store_true", help="print nothing on success")


def run(args: argparse.Namespace) -> int:
    import os
    import time

    from executive.api import shipped_tree
    from executive.commands._common import fail
    from executive.scenario import load_scenario, run_scenario

    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    scenario = load_scenario(os.path.join(here, "data", "demo.yaml"))
    t0 = time.perf_counter()
    cold = kernels_cold()
    r = run_scenario(scenario, shipped_tree("smach_recovery"))
    if r.outcome == "error":
        return fail("warmup", r.detail)
    if not args.quiet:
        state = "compiled" if cold else "already compiled"
        print(f"kernels {state} ({time.perf_counter() - t0:.1f} s)")
    return 0
