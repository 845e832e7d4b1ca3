"""The scenario data model: shapes, moving obstacles, events, expectations, generators, Scenario.

Plain dataclasses; ``executive.scenarios.parse`` builds them from a file and says where a value
is wrong, ``executive.scenarios.check`` judges a run against an ``Expectation``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from navcore.maps import OccupancyGrid
from navcore.types import Pose2D

from executive.world import MovingObstacle, Shape  # noqa: F401 (part of the model)

OUTCOMES = ("succeeded", "failed", "timeout")
TREES = ("move_base", "nav2", "near_goal_reconfigure", "smach_recovery")


@dataclass(frozen=True)
class TimeRef:
    """A moment: ``at`` seconds, or ``delay`` seconds after the event named ``event`` fired
    (``event`` may also be ``end`` for the end of the run)."""

    at: float = 0.0
    event: str = ""
    delay: float = 0.0


# Event actions and what their argument is (see docs/scenarios.md, "Events").
EVENT_ACTIONS = ("goal", "add_goal", "add", "remove", "fault", "end_fault", "phantom",
                 "move_phantom", "remove_phantom", "set")


@dataclass
class Event:
    """Something that happens during a run: at ``at`` seconds, or ``delay`` seconds after the
    first recovery whose type or name is ``after_recovery`` (``any`` for any) starts, or once
    such a recovery has been running for ``delay`` seconds (``while_recovery``: it is still
    running then, so a goal given at that moment must pre-empt it)."""

    name: str
    action: str
    arg: Any
    at: float | None = None
    after_recovery: str = ""
    while_recovery: str = ""
    delay: float = 0.0
    to: Any = None          # move_phantom: the new shape


@dataclass
class Window:
    """The robot is stopped (|v| <= ``v`` and |w| <= ``w``) from ``start`` until ``end``."""

    start: TimeRef
    end: TimeRef
    v: float = 0.02
    w: float = 0.05


@dataclass
class Expectation:
    """What must hold at the end of a run (every field optional; see docs/scenarios.md)."""

    outcome: tuple[str, ...] | None = ("succeeded",)
    reason: tuple[str, ...] | None = None
    recoveries_fired: list[str] = field(default_factory=list)      # all of
    recoveries_not_fired: list[str] = field(default_factory=list)  # none of
    recoveries_any_of: list[str] = field(default_factory=list)
    recoveries_at_least: dict[str, int] = field(default_factory=dict)  # "" = in total
    recoveries_at_most: dict[str, int] = field(default_factory=dict)
    recoveries_order: list[str] = field(default_factory=list)
    no_collision: bool = True
    max_time: float | None = None
    final_pose: tuple[Pose2D | None, float, float | None] | None = None  # (None = goal, d, yaw)
    goals_reached: tuple[int, int | None] | None = None                 # (min, max)
    stopped: list[Window] = field(default_factory=list)
    slow_in: list[tuple[Shape, float]] = field(default_factory=list)
    max_reverse_speed: float | None = None
    max_reverse_time: float | None = None
    via: list[Shape] = field(default_factory=list)
    avoid: list[Shape] = field(default_factory=list)
    preempt_within: float | None = None


@dataclass
class Generate:
    """Seeded generators (``executive.scenarios.generate``); ``seed`` None = the run's seed."""

    seed: int | None = None
    clutter: list[dict[str, Any]] = field(default_factory=list)
    patrol: dict[str, Any] | None = None
    start_goal: dict[str, Any] | None = None


@dataclass
class Scenario:
    name: str
    source: str
    grid: OccupancyGrid
    start: Pose2D
    goals: list[Pose2D]
    description: str = ""
    map_source: str = "inline"
    unknown_solid: bool = False
    profile: str = ""                     # path of the robot profile file, "" = none
    robot: dict[str, Any] = field(default_factory=dict)
    params: dict[str, dict[str, Any]] = field(default_factory=dict)
    objects: list[Shape] = field(default_factory=list)
    moving: list[MovingObstacle] = field(default_factory=list)
    phantoms: list[tuple[Shape, str]] = field(default_factory=list)
    faults: list[dict[str, Any]] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    time_limit: float = 120.0
    expect: Expectation = field(default_factory=Expectation)
    expect_by_tree: dict[str, Expectation] = field(default_factory=dict)
    seed: int = 0
    seeds: list[int] | None = None
    pass_at_least: int | None = None
    generate: Generate | None = None
    known_issue: str = ""                 # for every tree
    known_issues: dict[str, str] = field(default_factory=dict)   # by tree
    skip: str = ""                        # why it cannot run here (a real map is absent)
    wall_limit: float | None = None
    lines: dict[tuple, int] = field(default_factory=dict)   # file line of robot/params keys

    def expectation_for(self, tree_name: str) -> Expectation:
        """The expectation for a tree (by file stem, e.g. ``move_base``), else the default one."""
        return self.expect_by_tree.get(tree_name, self.expect)

    def known_issue_for(self, tree_name: str) -> str:
        return self.known_issues.get(tree_name, self.known_issue)

    def run_seeds(self) -> list[int]:
        return list(self.seeds) if self.seeds else [self.seed]

    def needed(self) -> int:
        """Seeds that must meet the expectation for the scenario to pass."""
        n = len(self.run_seeds())
        return n if self.pass_at_least is None else min(self.pass_at_least, n)
