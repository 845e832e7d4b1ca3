"""Your own robot I/O around the simulator: a battery that drains as the robot drives, and a tree
that stops navigating when the battery runs low (Nav2's IsBatteryLow).

    python examples/battery_robot.py [--drain 0.2]     # charge lost per metre driven

The robot I/O (``hw.interfaces.RobotIO``) is the simulator's, except for the base: its battery
is ours. The tree navigates only while IsBatteryLow fails (a ReactiveSequence checks it every
tick) and fails the mission as soon as the charge is at or below half.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from executive import MissionResult, Pose2D, load_config, open_mission, parse_tree
from hw.interfaces import BatteryState
from hw.sim import Simulator, SimWorld
from navcore.clock import SimClock
from navcore.synthetic_maps import ascii_map
from navcore.types import Odometry, Twist

ROOM = ascii_map("\n".join(["#" * 30] + ["#" + "." * 28 + "#"] * 10 + ["#" * 30]),
                 resolution=0.2)

TREE = """
main_tree: Main
trees:
  Main:
    ReactiveSequence:
      children:
        - Inverter:
            child:
              IsBatteryLow: {min_battery: 0.5}
        - PipelineSequence:
            children:
              - RateController:
                  hz: 1.0
                  child:
                    ComputePathToPose: {goal: "{goal}", path: "{path}"}
              - FollowPath: {path: "{path}"}
"""


class DrainingBase:
    """The simulator's base with a battery of our own: ``drain`` of the charge per metre."""

    def __init__(self, base, drain: float) -> None:
        self.base, self.drain = base, drain
        self.charge, self._last = 1.0, None

    def send(self, cmd: Twist) -> None:
        self.base.send(cmd)

    def odometry(self) -> Odometry | None:
        odom = self.base.odometry()
        if odom is not None:
            if self._last is not None:
                metres = math.hypot(odom.pose.x - self._last.x, odom.pose.y - self._last.y)
                self.charge = max(0.0, self.charge - self.drain * metres)
            self._last = odom.pose
        return odom

    def battery(self) -> BatteryState:
        return BatteryState(voltage=11.0 + 1.6 * self.charge, percentage=self.charge)

    def events(self):
        return self.base.events()


class BatteryRobot:
    """RobotIO: the simulator, with the draining base."""

    def __init__(self, sim: Simulator, drain: float) -> None:
        self.sim = sim
        self.base = DrainingBase(sim.base, drain)
        self.laser = sim.laser

    def step_to(self, t: float) -> None:
        self.sim.step_to(t)

    def true_pose(self) -> Pose2D:
        return self.sim.true_pose()

    def in_collision(self) -> bool:
        return bool(self.sim.in_collision())


def main(drain: float = 0.2, seed: int = 0) -> tuple[MissionResult, BatteryRobot]:
    config = load_config()
    clock = SimClock()          # the simulator stamps its messages with the mission's clock
    start = Pose2D(1.0, 1.2)
    sim = Simulator(SimWorld(ROOM, []), config.ns("sim"), clock, np.random.default_rng(seed),
                    start=start)
    robot = BatteryRobot(sim, drain)
    with open_mission(parse_tree(TREE), config, ROOM, start, io=robot, clock=clock,
                      seed=seed) as nav:
        nav.go_to_pose(Pose2D(5.0, 1.2))
        result = nav.run(time_limit=60.0)
    return result, robot


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--drain", type=float, default=0.2, help="charge lost per metre (0.2)")
    args = ap.parse_args()
    result, robot = main(args.drain)
    print(f"{result.outcome} after {result.distance:.2f} m in {result.sim_time:.1f} s; "
          f"battery {robot.base.charge:.0%}")
