"""Cold and warm start of ``mission demo``: wall (and CPU) time of a whole demo run, once with an
empty numba cache (``NUMBA_CACHE_DIR`` pointed at a fresh temporary directory, so every kernel
the demo needs compiles) and then again on that cache (every kernel loads). Both runs are
subprocesses of this script, in the same minute, from the checkout this file lives in.

    python bench/bench_startup.py [--json] [--warm-runs N]
    python bench/bench_startup.py --kernels [--json]

``demo_cold_s`` / ``demo_warm_s``: wall seconds (the warm figure is the median of N runs);
``*_cpu_s``: user + system seconds of the child and of the processes it waited for (the cold demo
compiles in two, see ``executive/commands/warmup_cmd.py``), which another job on a shared
machine does not inflate; ``demo_cold_run_cpu_s``: the cold run's own process alone (on idle
cores the cold wall time is about the larger of it and the second process's CPU);
``cold_over_warm``: the wall ratio.

``--kernels``: instead, one cold demo in one process (no second compiling process) with a
listener on numba's ``numba:compile`` events: the CPU seconds each kernel the demo calls from
Python takes to compile, the kernels it calls included (``compile_<module.kernel>_cpu_s``).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


# ``mission demo`` (executive.cli's main), then the CPU seconds of this process alone on stderr
_DEMO = """
import resource, sys
from executive.cli import main
rc = main(["demo", "--out", sys.argv[1]])
ru = resource.getrusage(resource.RUSAGE_SELF)
sys.stderr.write(f"\\nrun_cpu_s={ru.ru_utime + ru.ru_stime}\\n")
sys.exit(rc)
"""


def run_demo(cache_dir: str, out_dir: str) -> tuple[float, float, float]:
    """(wall s, cpu s, cpu s of the run's own process) of one ``mission demo`` writing to
    ``out_dir`` with that numba cache."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir)
    env.pop("NUMBA_DISABLE_JIT", None)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", _DEMO, out_dir], cwd=ROOT, env=env,
                          capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise SystemExit(f"bench_startup: mission demo failed ({proc.returncode}):\n"
                         f"{proc.stdout[-2000:]}{proc.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    own = float(proc.stderr.rsplit("run_cpu_s=", 1)[1].split()[0])
    return wall, cpu, own


_KERNELS = r"""
import json, os, sys, time
from numba.core import event
import executive.commands.warmup_cmd as warmup
warmup.start_navigation_warmup = lambda: None  # one process: every kernel compiles here
stack, top = [], {}

class Compiles(event.Listener):
    def on_start(self, ev):
        stack.append(time.process_time())
    def on_end(self, ev):
        dt = time.process_time() - stack.pop()
        if not stack:  # called from Python: its callees are in dt
            f = ev.data["dispatcher"].py_func
            name = f"{f.__module__}.{f.__qualname__}".replace(".<locals>", "")
            top[name] = top.get(name, 0.0) + dt

event.register("numba:compile", Compiles())
from executive.cli import main
rc = main(["demo", "--out", sys.argv[1]])
print(json.dumps({"rc": rc, "top": top}))
"""


def compile_profile(tmp: str) -> dict[str, float]:
    """Compile CPU seconds per kernel called from Python in one cold demo (see module doc)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=os.path.join(tmp, "numba-cache"))
    env.pop("NUMBA_DISABLE_JIT", None)
    proc = subprocess.run([sys.executable, "-c", _KERNELS, os.path.join(tmp, "out")], cwd=ROOT,
                          env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"bench_startup: profiled demo failed:\n{proc.stderr[-2000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])["top"]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print a JSON object as the last line")
    ap.add_argument("--warm-runs", type=int, default=3)
    ap.add_argument("--kernels", action="store_true",
                    help="per-kernel compile CPU of one cold demo in one process instead")
    args = ap.parse_args(argv)
    if args.kernels:
        with tempfile.TemporaryDirectory(prefix="navbt-startup-") as tmp:
            top = compile_profile(tmp)
        for name, cpu in sorted(top.items(), key=lambda kv: -kv[1]):
            print(f"{cpu:6.2f} s CPU  {name}")
        print(f"{sum(top.values()):6.2f} s CPU  all ({len(top)} kernels called from Python)")
        if args.json:
            figures = {f"compile_{n}_cpu_s": round(c, 2) for n, c in top.items()}
            figures["compile_all_cpu_s"] = round(sum(top.values()), 2)
            print(json.dumps(figures))
        return 0
    with tempfile.TemporaryDirectory(prefix="navbt-startup-") as tmp:
        cache = os.path.join(tmp, "numba-cache")
        cold_wall, cold_cpu, cold_own = run_demo(cache, os.path.join(tmp, "cold"))
        warm = [run_demo(cache, os.path.join(tmp, f"warm{i}")) for i in range(args.warm_runs)]
    warm_wall = statistics.median(w for w, _, _ in warm)
    warm_cpu = statistics.median(c for _, c, _ in warm)
    figures = {"demo_cold_s": round(cold_wall, 2), "demo_warm_s": round(warm_wall, 2),
               "demo_cold_cpu_s": round(cold_cpu, 2), "demo_warm_cpu_s": round(warm_cpu, 2),
               "demo_cold_run_cpu_s": round(cold_own, 2),
               "cold_over_warm": round(cold_wall / warm_wall, 2)}
    print(f"mission demo, empty numba cache: {cold_wall:6.2f} s wall ({cold_cpu:6.2f} s CPU, "
          f"{cold_own:.2f} s of it in the run's own process)")
    print(f"mission demo, warm cache:        {warm_wall:6.2f} s wall ({warm_cpu:6.2f} s CPU), "
          f"median of {args.warm_runs}")
    print(f"cold / warm: {cold_wall / warm_wall:.2f}x wall, {cold_cpu / warm_cpu:.2f}x CPU")
    if args.json:
        print(json.dumps(figures))
    return 0


if __name__ == "__main__":
    sys.exit(main())
