"""navcore.costmap.clear_memory and the clearing nodes' keep_confirmed port, on a scripted room:
an obstacle seen again soon after a clear survives the next clear; a stale one does not."""

from __future__ import annotations

import numpy as np
from py_trees.common import Status

from behaviors.base import make
from behaviors.testing import FakeRobot
from navcore.clock import SimClock
from navcore.costmap.clear_memory import ClearMemory, sensed_lethal_keys
from navcore.costmap.cost_values import LETHAL_OBSTACLE
from navcore.costmap.layered import LayeredCostmap
from navcore.synthetic_maps import ascii_map
from navcore.types import Pose2D

ROOM = "\n".join(["#" * 30] + ["#" + "." * 28 + "#"] * 18 + ["#" * 30])   # 3 m x 2 m
ROBOT = Pose2D(0.5, 1.0, 0.0)


def costmap(rolling: bool = False) -> LayeredCostmap:
    params = {"plugins": ["static_layer", "obstacle_layer"], "robot_radius": 0.1}
    if rolling:
        params = {"plugins": ["obstacle_layer"], "robot_radius": 0.1, "rolling_window": True,
                  "width": 2.0, "height": 2.0, "resolution": 0.1}
        return LayeredCostmap.from_params(params, clock=SimClock())
    return LayeredCostmap.from_params(params, static_map=ascii_map(ROOM, 0.1), clock=SimClock())


def see(cm: LayeredCostmap, x: float, ys=(0.85, 0.95, 1.05), at: Pose2D = ROBOT) -> None:
    """The sensor at ``at`` sees points at x."""
    pts = np.array([[x, y, 0.2] for y in ys])
    cm.add_points(pts, (at.x, at.y, 0.2))
    cm.update_map(at)


def cost(cm: LayeredCostmap, x: float, y: float) -> int:
    i, j = cm.costmap.world_to_map(x, y)
    return int(cm.costmap.costs[j, i])


def test_a_cell_marked_again_within_the_window_survives_the_next_clear():
    cm = costmap()
    mem = ClearMemory(window=10.0)
    see(cm, 2.0)
    assert cost(cm, 2.0, 0.95) == LETHAL_OBSTACLE
    assert mem.clear(cm, 0.0, cm.reset_layers) == 0         # first clear: nothing confirmed
    assert cost(cm, 2.0, 0.95) < LETHAL_OBSTACLE
    see(cm, 2.0)                                            # seen again 3 s later
    see(cm, 1.5, ys=(0.35,))                                # and a new cell, never cleared
    assert mem.clear(cm, 3.0, cm.reset_layers) == 3        # the three re-marked cells stay
    assert cost(cm, 2.0, 0.95) == LETHAL_OBSTACLE
    assert cost(cm, 1.5, 0.35) < LETHAL_OBSTACLE
    # a rolling map that moved: the same world cells are kept
    assert mem.clear(cm, 5.0, cm.reset_layers) == 3


def test_a_cell_marked_again_after_the_window_or_never_is_cleared():
    cm = costmap()
    mem = ClearMemory(window=10.0)
    see(cm, 2.0)
    mem.clear(cm, 0.0, cm.reset_layers)
    see(cm, 2.0)
    assert mem.clear(cm, 12.0, cm.reset_layers) == 0        # 12 s later: a new obstacle
    assert cost(cm, 2.0, 0.95) < LETHAL_OBSTACLE
    assert mem.clear(cm, 13.0, cm.reset_layers) == 0        # not seen again: gone for good
    assert len(sensed_lethal_keys(cm)) == 0


def test_a_confirmed_cell_the_sensor_sees_through_is_forgotten():
    cm = costmap()
    mem = ClearMemory(window=10.0)
    see(cm, 2.0)
    mem.clear(cm, 0.0, cm.reset_layers)
    see(cm, 2.0)
    assert mem.clear(cm, 2.0, cm.reset_layers) == 3
    see(cm, 2.8, ys=np.arange(0.7, 1.2, 0.02))              # rays now pass through x = 2.0
    assert cost(cm, 2.0, 0.95) < LETHAL_OBSTACLE
    assert mem.clear(cm, 4.0, cm.reset_layers) == 0
    assert cost(cm, 2.0, 0.95) < LETHAL_OBSTACLE


def test_keys_follow_the_world_on_a_rolling_costmap():
    cm = costmap(rolling=True)
    mem = ClearMemory(window=10.0)
    see(cm, 1.25, at=Pose2D(0.5, 1.0, 0.0))             # cell centres: no rounding edge
    before = sensed_lethal_keys(cm)
    mem.clear(cm, 0.0, cm.reset_layers)
    moved = Pose2D(0.8, 1.0, 0.0)                           # the window moves 0.3 m
    see(cm, 1.25, at=moved)
    assert {tuple(k) for k in sensed_lethal_keys(cm)} == {tuple(k) for k in before}
    assert mem.clear(cm, 1.0, cm.reset_layers) == len(before)


def test_clear_entire_costmap_keeps_confirmed_cells_only_when_asked():
    for keep, expected in ((True, LETHAL_OBSTACLE), (False, 0)):
        cm, clock = costmap(), SimClock()
        node = make("ClearEntireCostmap", namespace=f"/clearmem{keep}", costmap="global",
                    keep_confirmed=keep, confirm_window=5.0)
        node.setup(clock=clock, robot=FakeRobot(ROBOT), global_costmap=cm, control_period=0.05)
        see(cm, 2.0)
        node.tick_once()
        assert node.status == Status.SUCCESS and cost(cm, 2.0, 0.95) == 0
        clock.advance(2.0)
        see(cm, 2.0)
        node.tick_once()
        assert node.status == Status.SUCCESS
        assert cost(cm, 2.0, 0.95) == expected
