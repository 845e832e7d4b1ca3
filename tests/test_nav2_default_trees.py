"""Nav2's default NavigateToPose and NavigateThroughPoses trees of every distribution,
unchanged, run scenarios of the catalogue in the simulator with the outcome of navbt's
trees/nav2.yaml (a subset; bench/bench_nav2_trees.py runs the whole catalogue for the tables
of docs/trees.md)."""

from __future__ import annotations

from pathlib import Path

import pytest

from executive import nav2_model
from executive.nav2_tree_table import DEFAULT_TREES, markdown, run_table
from tests.conftest import data_root

HERE = Path(__file__).resolve().parent
SUBSET = [HERE / "scenarios" / f"{name}.yaml"
          for name in ("unknown_box", "goal_in_obstacle", "phantom_obstacle", "doorway_bad_angle")]


@pytest.mark.parametrize("distro", nav2_model.DISTROS)
def test_default_trees_agree_with_nav2_yaml(distro):
    root = data_root()
    if root is None:
        pytest.skip("../shared/data not found (set NAVBT_DATA): Nav2's trees are not here")
    rows = run_table(root, distro, SUBSET, HERE.parent / "trees")
    assert [r.scenario for r in rows] == ["unknown_box", "goal_in_obstacle", "phantom_obstacle",
                                          "doorway_bad_angle"]
    assert [r.reference.split()[0] for r in rows] == ["solved", "failed", "solved", "solved"]
    for r in rows:
        for nav in DEFAULT_TREES:
            assert r.agree[nav], (distro, r.scenario, nav, r.results[nav], r.reference)
    text = markdown(distro, rows)
    assert text.count("\n| ") == 5 and "(differs)" not in text
