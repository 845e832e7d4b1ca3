"""Nav2 behaviour-tree nodes that navbt's first node set lacked (issue 19): path handling,
goal lists, selectors, the route-graph nodes and CancelControl, with Nav2's ports and
semantics. Importing this package registers them."""

from behaviors.nav2 import (cancel_control, goal_lists, global_updated_goal, path_actions,  # noqa: F401
                            path_conditions, path_longer_on_approach, route, selectors)
