"""examples/: the scripts run and do what their docstrings say."""

from __future__ import annotations

import os
import runpy

import pytest

EXAMPLES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "examples")


def test_battery_robot_navigates_until_its_battery_is_low():
    main = runpy.run_path(os.path.join(EXAMPLES, "battery_robot.py"))["main"]
    full, robot = main(drain=0.0)
    assert full.succeeded and robot.base.charge == 1.0
    low, robot = main(drain=0.2)
    # IsBatteryLow (min_battery 0.5) ends the mission after about 0.5 / 0.2 = 2.5 m
    assert low.outcome == "failed" and robot.base.charge <= 0.5
    assert low.distance == pytest.approx(2.5, abs=0.3) and low.distance < full.distance
