"""Shared fixtures: where the real test data lives, and a skip with a reason when it is absent."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

_HERE = Path(__file__).resolve().parent


def data_root() -> Path | None:
    """``$NAVBT_DATA`` if set, else ``../shared/data`` beside the checkout; None when absent."""
    env = os.environ.get("NAVBT_DATA")
    candidates = [Path(env)] if env else []
    candidates += [_HERE.parent.parent / "shared" / "data", _HERE.parent / ".." / "shared" / "data"]
    for c in candidates:
        if (c / "maps").is_dir():
            return c.resolve()
    return None


@pytest.fixture(scope="session")
def shared_data() -> Path:
    root = data_root()
    if root is None:
        pytest.skip("real data not found: set NAVBT_DATA or place shared/data beside the checkout")
    return root


REAL_MAPS = {
    "willow_garage": "willow_garage/willow-full-0.05.yaml",
    "intel_lab": "intel_lab/intel.yaml",
    "aces": "aces/aces.yaml",
    "aws_small_house": "aws_small_house/map.yaml",
    "turtlebot3_world": "turtlebot3_world/map.yaml",
    "robotis_office": "robotis_office/map_office_raw.yaml",
}


@pytest.fixture(scope="session")
def demo_run(tmp_path_factory) -> Path:
    """The demo scenario (stale doorway, three recoveries) recorded once per session: the run
    folder that the picture, replay-page, browser and MCAP tests read."""
    from executive.tree_loader import shipped_tree
    from executive.scenario import load_scenario, run_scenario
    out = tmp_path_factory.mktemp("runs") / "demo"
    scenario = load_scenario(_HERE.parent / "executive" / "data" / "demo.yaml")
    result = run_scenario(scenario, shipped_tree("smach_recovery"), record_dir=str(out))
    assert result.outcome == "succeeded" and len(result.recoveries) == 3
    return out
