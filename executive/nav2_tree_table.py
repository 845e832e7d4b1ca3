"""Nav2's default navigator trees of each distribution against the scenario catalogue, next
to navbt's trees/nav2.yaml: the table of docs/trees.md ("Nav2's default trees in the
simulator"). bench/bench_nav2_trees.py prints the full table; the tests run a subset."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Iterable

from executive import nav2_model

DEFAULT_TREES = {"NavigateToPose": "navigate_to_pose_w_replanning_and_recovery.xml",
                 "NavigateThroughPoses": "navigate_through_poses_w_replanning_and_recovery.xml"}
REFERENCE = "nav2.yaml"


@dataclass(frozen=True)
class Row:
    scenario: str
    reference: str            # outcome of trees/nav2.yaml: "solved 13.5 s" or the failure
    results: dict[str, str]   # "NavigateToPose" / "NavigateThroughPoses" -> the same
    agree: dict[str, bool]    # same outcome (solved or not) as the reference


def _cell(result: object) -> str:
    r = result
    if r.solved:  # type: ignore[attr-defined]
        return f"solved {r.sim_time:.1f} s"  # type: ignore[attr-defined]
    return f"{r.outcome} ({r.reason or 'no reason'})"[:60]  # type: ignore[attr-defined]


def default_tree(data_root: Path, distro: str, navigator: str) -> Path:
    return data_root / "nav2_trees" / distro / DEFAULT_TREES[navigator]


def run_table(data_root: Path, distro: str, scenarios: Iterable[str | Path],
              trees_dir: Path) -> list[Row]:
    """One row per scenario: trees/nav2.yaml and both default trees of ``distro``."""
    from executive.scenario import load_scenario, run_scenario
    rows = []
    for path in scenarios:
        s = load_scenario(path)
        ref = run_scenario(s, str(trees_dir / REFERENCE))
        results, agree = {}, {}
        for nav in DEFAULT_TREES:
            r = run_scenario(s, str(default_tree(data_root, distro, nav)))
            results[nav] = _cell(r)
            agree[nav] = r.solved == ref.solved
        rows.append(Row(s.name, _cell(ref), results, agree))
    return rows


def markdown(distro: str, rows: list[Row]) -> str:
    """The table of one distribution; a cell marked (differs) disagrees with trees/nav2.yaml."""
    out = [f"**{distro}** (commit {nav2_model.COMMITS[distro][:10]})", "",
           "| scenario | trees/nav2.yaml | NavigateToPose | NavigateThroughPoses |",
           "|---|---|---|---|"]
    for r in rows:
        cells = [r.results[n] + ("" if r.agree[n] else " (differs)") for n in DEFAULT_TREES]
        out.append(f"| {r.scenario} | {r.reference} | {cells[0]} | {cells[1]} |")
    return "\n".join(out) + "\n"
