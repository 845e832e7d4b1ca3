"""``mission demo``: the recovery tree gets a simulated robot out of a stuck spot on a bundled map.

No arguments needed: it runs ``executive/data/demo.yaml`` (a scenario) with the SMACH-style
recovery tree on a simulated clock, shows a progress line on a terminal, writes a run folder and
prints its path.
"""

from __future__ import annotations

import argparse


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--tree", help="tree to run (default: the shipped smach_recovery.yaml)")
    p.add_argument("--out", help="run folder (default: ./mission-demo-<n>)")
    from executive.commands._common import add_config_arguments
    add_config_arguments(p, "robot config YAML (default: the bundled robot)")


def _fresh_dir(base: str) -> str:
    import os
    n = 1
    while os.path.exists(f"{base}-{n}"):
        n += 1
    return f"{base}-{n}"


def run(args: argparse.Namespace) -> int:
    import os

    from executive.commands._common import config_sources, fail
    from executive.config import ConfigSources
    from executive.api import ConfigError, TreeLoadError, WiringError, shipped_tree
    from executive.progress import Progress, progress_callback
    from executive.scenario import ScenarioError, load_scenario, run_scenario
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    scenario = load_scenario(os.path.join(here, "data", "demo.yaml"))
    tree = args.tree or shipped_tree("smach_recovery")
    out = args.out or _fresh_dir(os.path.abspath("mission-demo"))
    from executive.commands.warmup_cmd import (announce_compiling, end_navigation_warmup,
                                               kernels_cold, start_navigation_warmup)
    progress = Progress()
    print(f"demo: {scenario.description.splitlines()[0] if scenario.description else scenario.name}")
    cold = kernels_cold()
    announce_compiling(cold=cold)
    sources = config_sources(args)
    # the second compiling process knows only the bundled robot's planners
    default_robot = sources == ConfigSources()
    helper = start_navigation_warmup() if cold and default_robot else None
    ok = False
    try:
        r = run_scenario(scenario, tree, record_dir=out, config_path=sources,
                         on_tick=progress_callback(progress, scenario.time_limit,
                                                   goals=scenario.goals))
        ok = r.outcome != "error"
    except (ScenarioError, TreeLoadError, WiringError, ConfigError) as e:
        progress.done()
        return fail("demo", str(e))
    finally:
        end_navigation_warmup(helper, keep=ok)
    progress.done()
    if r.outcome == "error":
        return fail("demo", r.detail)
    rec = ", ".join(x["name"] for x in r.recoveries) or "none"
    print(f"{r.outcome} in {r.sim_time:.1f} s simulated ({r.sim_time / max(r.wall_time, 1e-9):.1f}x "
          f"real time); recoveries: {rec}; collisions: {r.collisions}")
    print(out)
    return 0 if r.solved else 1
