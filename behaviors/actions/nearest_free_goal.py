"""NearestFreeGoal: the goal, or the nearest reachable free pose to it when it is occupied."""

from __future__ import annotations

from behaviors.actions.planning import PLAN_IN, PlanningAction
from behaviors.base import SUCCESS, Port, PortInformation, Status
from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE
from navcore.error_codes import PlannerError
from navcore.planners.free_goal import FreeGoal, nearest_reachable_free_goal, needs_free_goal
from navcore.types import Pose2D


class NearestFreeGoal(PlanningAction):
    """Where to plan to: ``free_goal`` is ``goal`` when its cell on the global costmap costs less
    than ``cost_threshold`` (the planners' impassable cost), else the free cell nearest to the
    goal within the square of half-side ``tolerance`` that the planner reaches from the robot
    (the planners' ``default_tolerance``, made explicit; cells in the robot's line of sight
    first, since the costmap shows the unseen inside of a box as free), with the goal's yaw; at most
    ``max_plans`` reachability plans per tick. ``goal_substituted`` says which: a tree that
    follows a path to ``free_goal`` and succeeds has reached the substitute, not the goal.
    SUCCESS with both written; FAILURE with GOAL_OCCUPIED when the goal is occupied and no free
    cell within ``tolerance`` is reachable, INVALID_GOAL without a goal. With a planner other
    than navfn or global_planner the goal passes unchanged (carrot_planner walks back from an
    occupied goal itself)."""

    INPUT_PORTS = {
        "goal": PortInformation(Pose2D, True, "goal pose in map"),
        "tolerance": Port(float, False, "m: half-side of the square searched round an occupied "
                          "goal (Nav2 NavFn's tolerance default); 0 = no substitute", 0.5,
                          low=0.0),
        "cost_threshold": Port(int, False, "cell cost at which the goal counts as occupied",
                               INSCRIBED_INFLATED_OBSTACLE, low=1, high=255),
        "max_plans": Port(int, False, "reachability plans per tick at most", 8, low=1, high=100),
        **PLAN_IN,
    }
    OUTPUT_PORTS = {
        "free_goal": PortInformation(Pose2D, True, "the pose to plan to"),
        "goal_substituted": PortInformation(bool, False, "free_goal is not the goal"),
        "error_code_id": PortInformation(int, False, "a PlannerError; 0 on success"),
        "error_msg": PortInformation(str, False, "why there is no free goal"),
    }
    DEFAULT_KEYS = {"goal": "goal", "free_goal": "free_goal",
                    "goal_substituted": "goal_substituted",
                    "error_code_id": "free_goal_error_code", "error_msg": "free_goal_error_msg"}

    def setup(self, **kwargs) -> None:
        super().setup(**kwargs)
        self.costmap = self.component(kwargs, "global_costmap")

    def update(self) -> Status:
        goal = self.read("goal")
        if goal is None:
            return self.fail(PlannerError.INVALID_GOAL, "no goal on the blackboard")
        planner = self.planner()
        if planner is None:
            return self.no_planner()
        start = self.start()
        found = FreeGoal(goal, False, 0)         # carrot_planner settles it its own way
        if needs_free_goal(planner):
            found = nearest_reachable_free_goal(
                self.costmap.costmap, goal, self.get_input("tolerance"),
                lambda p: self.plan(planner, start, p)[0] is not None,
                self.get_input("max_plans"), self.get_input("cost_threshold"),
                (start.x, start.y))
        if found.pose is None:
            return self.fail(PlannerError.GOAL_OCCUPIED,
                             f"goal occupied, no reachable free cell within "
                             f"{self.get_input('tolerance'):g} m ({found.plans} plans)")
        if found.substituted:
            self.say(f"goal occupied: driving to ({found.pose.x:.2f}, {found.pose.y:.2f}), "
                     f"{found.pose.distance_to(goal):.2f} m from it")
        self.write("free_goal", found.pose)
        self.write("goal_substituted", found.substituted)
        self.write("error_code_id", int(PlannerError.NONE))
        self.write("error_msg", "")
        return SUCCESS
