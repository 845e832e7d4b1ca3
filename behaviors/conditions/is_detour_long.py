"""IsDetourLong: the plan is much longer than the route on the static map alone."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, Port, PortInformation, Status
from behaviors.conditions.condition import Condition, yes
from navcore.costmap.blocking import blocking_cells, last_seen_occupied
from navcore.planners.map_route import MapOnlyRoute, is_detour
from navcore.types import Path, Pose2D


class IsDetourLong(Condition):
    """SUCCESS when ``path`` is at least ``ratio`` times, and ``min_extra`` metres, longer than
    the plan from its first pose to ``goal`` on the global costmap's static layers and inflation
    alone (what the sensors added left out): the plan is a long detour round something sensed,
    worth clearing or looking again before driving it. At most ``max_per_goal`` SUCCESSes per
    goal (0 = no limit), so that a detour round a real obstacle is taken after one look. With
    ``age`` > 0 the detour counts only when the sensed cells blocking the map-only route (the
    lethal cells of the obstacle layers within the robot's circumscribed radius of it) have not
    been seen occupied for ``age`` seconds, by the observed-space memory (a beam ending in a
    cell stamps it, whatever the costmaps clear): an obstacle seen a moment ago stands there,
    and its detour is driven at once (that look counts against ``max_per_goal``, so the detour
    is not questioned again once the obstacle is out of sight behind); one nobody has seen for
    a while (or ever: a phantom) is worth clearing first. Without the memory (none configured) ``age`` is not applied. FAILURE
    without a path or goal, or when the map has no route either (that is not a detour)."""

    INPUT_PORTS = {
        "path": PortInformation(Path, True, "the plan to judge"),
        "goal": PortInformation(Pose2D, True, "its goal"),
        "ratio": Port(float, False, "plan length / map-only length that counts", 2.0, low=1.0),
        "min_extra": Port(float, False, "metres the plan must be longer as well", 2.0, low=0.0),
        "max_per_goal": Port(int, False, "SUCCESSes per goal; 0 = no limit", 1, low=0),
        "age": Port(float, False, "s the blocking cells must have gone unseen; 0 = not "
                    "checked", 0.0, low=0.0),
        "planner_id": PortInformation(str, False, "whose kind and parameters the map-only "
                                      "plan uses", "GridBased"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"path": "path", "goal": "goal"}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        costmap = self.component(kwargs, "global_costmap")
        planners = kwargs.get("planners") or {}
        self.route = MapOnlyRoute(costmap, planners.get(self.get_input("planner_id")))
        self.costmap = costmap
        self.observed = kwargs.get("observed_space")
        self._path: Path | None = None
        self._verdict = False
        self._goal: Pose2D | None = None
        self._fired = 0

    def update(self) -> Status:
        path, goal = self.read("path"), self.read("goal")
        if path is None or len(path) < 2 or goal is None:
            self.say("no path or goal")
            return FAILURE
        if not self.route.available:
            self.say("the global costmap has no layers: cannot tell the map apart")
            return FAILURE
        if goal is not self._goal and goal != self._goal:  # (the same object: no dataclass ==)
            self._goal, self._fired = goal, 0
        limit = self.get_input("max_per_goal")
        if limit > 0 and self._fired >= limit:
            return FAILURE           # spent for this goal: no map-only plan for each replan
        if path is not self._path:   # judge each plan once
            self._path = path
            length = path.length()
            min_extra = self.get_input("min_extra")
            if length < min_extra:   # no route (length >= 0) leaves it min_extra longer
                self._verdict = False
                self.say(f"plan {length:.2f} m: shorter than min_extra, no detour")
                return FAILURE
            x, y, th = (float(v) for v in path.poses[0])
            route = self.route.plan(Pose2D(x, y, th), goal)
            map_length = route.path.length() if route.ok and route.path is not None \
                and len(route.path) > 0 else None
            self._verdict = map_length is not None and is_detour(
                length, map_length, self.get_input("ratio"), min_extra)
            self.say(f"plan {length:.2f} m, map-only "
                     f"{'none' if map_length is None else f'{map_length:.2f} m'}")
            age = self.get_input("age")
            if self._verdict and age > 0.0 and self.observed is not None:
                cells = blocking_cells(self.costmap, route.path,
                                       getattr(self.costmap, "circumscribed_radius", 0.0))
                seen = last_seen_occupied(self.observed, cells)
                unseen = self.clock.now() - seen
                self._verdict = unseen >= age
                if not self._verdict:
                    self._fired += 1    # the sensors had their look: drive this detour
                self.say(f"{len(cells)} blocking cells, last seen "
                         f"{'never' if seen == -float('inf') else f'{unseen:.1f} s ago'}")
        if not self._verdict:
            return FAILURE
        self._fired += 1
        return yes(True)
