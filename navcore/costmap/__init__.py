"""costmap_2d: the cost grid, its layers, footprints and the layered (master) costmap."""

from navcore.costmap.cost_values import (FREE_SPACE, INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE,
                                         NO_INFORMATION)
from navcore.costmap.costmap2d import Costmap2D

__all__ = ["Costmap2D", "FREE_SPACE", "INSCRIBED_INFLATED_OBSTACLE", "LETHAL_OBSTACLE",
           "NO_INFORMATION"]
