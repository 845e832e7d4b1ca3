"""Speed of the closed loop through the real drivers (``hardware="emulated"``): a catalogue
scenario run with the Kobuki and URG-04LX drivers over ``sim://`` byte streams, against the same
scenario on the simulator's direct interfaces (both localised by AMCL, so the difference is the
drivers, codecs and emulators).

Usage: python bench/bench_hw_emulated.py [--json] [--scenario tests/scenarios/goal_minus_x.yaml]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]


def run(scenario_path: str, tree: str, hardware: str | bool) -> tuple[float, float, str]:
    """(simulated s, wall s, outcome) of one run; the config gets an amcl namespace so the
    direct run localises the same way as the driver run."""
    from executive.config import DEFAULT_CONFIG, config_from_mapping
    from executive.mission import World, build_mission, run_mission
    from executive.scenario import load_scenario
    s = load_scenario(scenario_path)
    doc = yaml.safe_load(DEFAULT_CONFIG.read_text())
    doc["robot"] = dict(doc["robot"], **s.robot)
    for ns, values in s.params.items():
        doc[ns] = dict(doc.get(ns) or {}, **values)
    doc.setdefault("amcl", {})
    config = config_from_mapping(doc, "bench")
    t0 = time.perf_counter()
    m = build_mission(tree, config, s.grid, s.start, seed=s.seed, hardware=hardware,
                      world=World(s.objects, s.moving, s.phantoms, s.faults))
    result = run_mission(m, s.goals, s.time_limit)
    wall = time.perf_counter() - t0
    m.executive.shutdown()
    if hasattr(m.executive.io, "close"):
        m.executive.io.close()
    return result.sim_time, wall, result.outcome


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print a JSON line of the figures last")
    ap.add_argument("--scenario", default=str(ROOT / "tests" / "scenarios" / "goal_minus_x.yaml"))
    ap.add_argument("--tree", default=str(ROOT / "trees" / "move_base.yaml"))
    a = ap.parse_args()
    run(a.scenario, a.tree, "emulated")          # warm-up: numba compilation, imports
    figures = {}
    for label, hw in (("direct", False), ("drivers", "emulated")):
        sim_s, wall_s, outcome = run(a.scenario, a.tree, hw)
        print(f"{label:8s} {outcome:9s} {sim_s:6.1f} s simulated in {wall_s:5.2f} s wall: "
              f"x{sim_s / wall_s:5.1f} real time")
        figures[f"{label}_x_realtime"] = round(sim_s / wall_s, 2)
        figures[f"{label}_wall_s"] = round(wall_s, 3)
    if a.json:
        print(json.dumps(figures))


if __name__ == "__main__":
    main()
