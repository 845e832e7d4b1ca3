"""costmap_2d: the cost grid, its layers, footprints and the layered (master) costmap."""

from navcore.costmap.cost_values import (FREE_SPACE, INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE,
                                         NO_INFORMATION)
from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.footprint import (circumscribed_radius, footprint_cost, inscribed_radius,
                                       make_footprint)
from navcore.costmap.inflation import InflationLayer, cost_table, inflate
from navcore.costmap.layered import LayeredCostmap
from navcore.costmap.obstacle_layer import ObstacleLayer
from navcore.costmap.static_layer import StaticLayer
from navcore.costmap.voxel_layer import VoxelLayer

__all__ = ["Costmap2D", "FREE_SPACE", "INSCRIBED_INFLATED_OBSTACLE", "LETHAL_OBSTACLE",
           "NO_INFORMATION", "InflationLayer", "LayeredCostmap", "ObstacleLayer", "StaticLayer",
           "VoxelLayer", "circumscribed_radius", "cost_table", "footprint_cost", "inflate",
           "inscribed_radius", "make_footprint"]
