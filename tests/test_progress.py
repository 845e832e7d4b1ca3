"""The terminal progress line: measured against the goals and path left, ETA and speed-up."""

from __future__ import annotations

import io
import re
from types import SimpleNamespace

import numpy as np

from navcore.clock import SimClock
from navcore.types import Path, Pose2D
from executive.progress import Progress, TickProgress, remaining_path


class Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


class FakeWall:
    def __init__(self) -> None:
        self.t = 100.0

    def now(self) -> float:
        return self.t


def test_remaining_path_along_the_plan_or_straight():
    path = Path(np.array([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 4.0, 0.0]]))
    assert remaining_path(path, Pose2D(0.0, 1.0), None) == 1.0 + 7.0
    assert remaining_path(path, Pose2D(3.0, 1.0), None) == 3.0        # on the path
    assert remaining_path(path, Pose2D(4.0, 1.0), None) == 1.0 + 3.0  # beside it
    assert remaining_path(None, Pose2D(0.0, 0.0), Pose2D(3.0, 4.0)) == 5.0
    assert remaining_path(None, Pose2D(), None) == 0.0


def test_progress_counts_goals_and_path_left_with_eta_and_speedup():
    goals = [Pose2D(10.0, 0.0), Pose2D(10.0, 5.0)]
    bb = {"goal": goals[0], "path": Path(np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]))}
    clock, wall = SimClock(), FakeWall()
    ex = SimpleNamespace(clock=clock, robot=SimpleNamespace(pose=lambda: pose[0]),
                         trace=SimpleNamespace(recoveries=[{"recovery": "Spin"}]),
                         blackboard_get=lambda k: bb.get(k))
    stream = Tty()
    on_tick = TickProgress(Progress(stream, every=1), 600.0, goals=goals, wall_clock=wall)
    pose = [Pose2D(0.0, 0.0)]
    on_tick(ex)
    # 5 s simulated in 0.5 s wall at 1 m/s: halfway along the first goal's 10 m path
    clock.sleep_until(5.0)
    wall.t += 0.5
    pose[0] = Pose2D(5.0, 0.0)
    on_tick(ex)
    line = stream.getvalue().split("\r")[-1]
    assert re.search(r"\]  25% goal 1/2 10\.0 m left", line), line   # 5 m + 5 m to goal 2
    assert "ETA 10 s sim = 1.0 s wall" in line and "t=5.0 s sim, x10.0 real time" in line
    assert "recoveries 1" in line
    # the second goal: the first is done
    bb["goal"], bb["path"] = goals[1], None
    clock.sleep_until(10.0)
    wall.t += 0.5
    pose[0] = Pose2D(10.0, 0.0)
    on_tick(ex)
    line = stream.getvalue().split("\r")[-1]
    assert re.search(r"\]  50% goal 2/2 5\.0 m left", line), line


def test_quiet_progress_does_no_work():
    ex = SimpleNamespace()  # any attribute access would fail
    TickProgress(Progress(io.StringIO(), every=1), 600.0)(ex)
