"""``mission warmup``: compile the numba kernels a simulated mission uses, once, into numba's cache.

numba compiles a kernel the first time it is called and keeps the machine code in its cache
(``__pycache__`` beside the sources, or ``$NUMBA_CACHE_DIR``); later runs load it in
milliseconds. The first mission after an install therefore spends most of its time compiling.
This command pays that cost up front by running the demo scenario once with nothing recorded,
which calls exactly the kernels a mission on the simulator calls, with the same argument types.

numba compiles one kernel at a time in a process. On a cold cache the demo (and this command)
therefore starts a second process, ``mission warmup --part navigation``, that compiles the local
and global planners' kernels (``warm_navigation``) while the first compiles the simulator's and
the costmaps', which a run needs first; the run then loads the planners' kernels from the cache.
Both processes compile the same machine code a single one would: only where it is compiled
changes, never what a run computes.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from typing import TextIO


def kernels_cold() -> bool:
    """True when numba's cache had no machine code for this installation yet (the probe kernel,
    cached like all others, had to be compiled): the first run after an install, an upgrade or
    a change of a kernel source (navcore.kernel_cache drops the cache then)."""
    from numba import njit  # not at import: `mission --help` imports every command module
    from navcore.kernel_cache import cache_probe
    probe = njit(cache=True)(cache_probe)
    probe()
    stats = getattr(probe, "stats", None)  # plain function under NUMBA_DISABLE_JIT
    return bool(stats is not None and stats.cache_misses)


def announce_compiling(stream: TextIO | None = None, cold: bool | None = None) -> bool:
    """On a terminal with a cold cache (``cold``: already known), say that the pause to come is
    compilation; True if said."""
    stream = stream if stream is not None else sys.stdout
    if not getattr(stream, "isatty", lambda: False)():
        return False
    if not (kernels_cold() if cold is None else cold):
        return False
    stream.write("compiling kernels (first run only; `mission warmup` does it ahead)...\n")
    stream.flush()
    return True


def warm_navigation(scenario_path: str) -> None:
    """Compile the kernels of the scenario's local planner (first: a run needs them last) and
    global planner by using them once, as a run does, on its map and robot config: one control
    cycle in the free local costmap, then two plans from its start to its first goal (the second
    reuses the first one's search records)."""
    import numpy as np

    from executive.scenario import load_scenario
    from executive.scenarios.generate import materialize
    from executive.scenarios.profiles import scenario_config
    from executive.stack import build_controller, build_costmaps, build_planner
    from navcore.clock import SimClock
    from navcore.types import Path, Pose2D, Twist

    sc = materialize(load_scenario(scenario_path), 0)
    config = scenario_config(sc, None)
    global_cm, local_cm = build_costmaps(config, sc.grid, SimClock())
    for cm in (global_cm, local_cm):  # free space, set directly: the costmap kernels are the run's
        cm.costmap.costs[...] = 0
    local = local_cm.costmap
    x = local.origin_x + local.size_x * local.resolution / 2
    y = local.origin_y + local.size_y * local.resolution / 2
    xs = np.linspace(x, x + 1.5, 31)
    path = Path(np.stack([xs, np.full_like(xs, y), np.zeros_like(xs)], axis=1))
    build_controller(config, local_cm).compute_velocity(Pose2D(x, y, 0.0), Twist(0.1), path)
    planner = build_planner(config, global_cm)
    for _ in range(2):
        planner.make_plan(sc.start, sc.goals[0])


def start_navigation_warmup() -> subprocess.Popen | None:
    """``mission warmup --part navigation`` in a second process (its output discarded), or None
    when NUMBA_DISABLE_JIT is set or there is one CPU. The caller waits for it."""
    import os
    if os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0") or (os.cpu_count() or 1) < 2:
        return None
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    env = dict(os.environ)  # same numba cache, same checkout
    env["PYTHONPATH"] = os.pathsep.join([root] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH")
                                                  else []))
    return subprocess.Popen([sys.executable, "-m", "executive.cli", "warmup", "--part",
                             "navigation", "--quiet"], env=env, stdin=subprocess.DEVNULL,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def end_navigation_warmup(helper: subprocess.Popen | None, keep: bool) -> None:
    """After the run: let the second process finish when ``keep`` (its kernels serve the next
    runs too; at most 5 minutes), else stop it at once (a failed run should not wait for it).
    numba writes each cache file whole, so a stopped compile only leaves that kernel to a later
    run."""
    if helper is None:
        return
    if not keep:
        helper.kill()
    try:
        helper.wait(timeout=300)
    except subprocess.TimeoutExpired:
        helper.kill()
        helper.wait()


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.add_argument("--part", choices=("all", "navigation"), default="all",
                   help="navigation: only the planners' kernels (what the demo's second process "
                        "compiles)")


def run(args: argparse.Namespace) -> int:
    import os
    import time

    from executive.api import shipped_tree
    from executive.commands._common import fail
    from executive.scenario import load_scenario, run_scenario

    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    demo = os.path.join(here, "data", "demo.yaml")
    t0 = time.perf_counter()
    cold = kernels_cold()
    if args.part == "navigation":
        warm_navigation(demo)
    else:
        helper = start_navigation_warmup() if cold else None
        ok = False
        try:
            r = run_scenario(load_scenario(demo), shipped_tree("smach_recovery"))
            ok = r.outcome != "error"
        finally:
            end_navigation_warmup(helper, keep=ok)
        if r.outcome == "error":
            return fail("warmup", r.detail)
    if not args.quiet:
        state = "compiled" if cold else "already compiled"
        print(f"kernels {state} ({time.perf_counter() - t0:.1f} s)")
    return 0
