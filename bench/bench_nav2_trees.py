"""Nav2's default NavigateToPose / NavigateThroughPoses trees of Humble, Jazzy, Kilted and
main, unchanged, against the scenario catalogue in the simulator, next to trees/nav2.yaml.

    python bench/bench_nav2_trees.py [--distro jazzy ...] [--scenario NAME ...] [--json]

Prints one markdown table per distribution (the tables of docs/trees.md) and, with --json, a
last line of figures: runs, agreements with trees/nav2.yaml, wall time. Needs
../shared/data (or $NAVBT_DATA) for Nav2's trees.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def main() -> int:
    from executive import nav2_model
    from executive.nav2_tree_table import DEFAULT_TREES, markdown, run_table
    from tests.conftest import data_root
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--distro", action="append", choices=nav2_model.DISTROS)
    p.add_argument("--scenario", action="append", help="scenario name (default: all)")
    p.add_argument("--json", action="store_true")
    args = p.parse_args()
    data = data_root()
    if data is None:
        print("../shared/data not found: set NAVBT_DATA", file=sys.stderr)
        return 2
    catalogue = sorted((ROOT / "tests" / "scenarios").glob("*.yaml"))
    if args.scenario:
        catalogue = [c for c in catalogue if c.stem in args.scenario]
    figures: dict[str, float] = {}
    t0 = time.perf_counter()
    for distro in args.distro or nav2_model.DISTROS:
        rows = run_table(data, distro, catalogue, ROOT / "trees")
        print(markdown(distro, rows))
        for nav in DEFAULT_TREES:
            figures[f"{distro}_{nav}_agree_count"] = sum(r.agree[nav] for r in rows)
        figures[f"{distro}_scenarios_count"] = len(rows)
    figures["wall_s"] = round(time.perf_counter() - t0, 1)
    if args.json:
        print(json.dumps(figures))
    return 0


if __name__ == "__main__":
    sys.exit(main())
