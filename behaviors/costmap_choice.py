"""The nodes that measure space around a pose on one costmap with the robot's footprint: a
``costmap`` port naming "local" or "global", and that costmap's footprint polygon."""

from __future__ import annotations

from typing import Any

import numpy as np

from navcore.motion.line_up import footprint_of


class MeasuresOnCostmap:
    """Mixin of a Leaf with a ``costmap`` input port: ``take_costmaps`` in ``setup``, then
    ``costmap_and_footprint`` in ``update`` (footprint None: a scripted costmap without one)."""

    CHOICES = {"costmap": ("local", "global")}

    def take_costmaps(self, kwargs: dict[str, Any]) -> None:
        self.costmaps = {"local": kwargs.get("local_costmap"),
                         "global": kwargs.get("global_costmap")}

    def costmap_and_footprint(self) -> tuple[Any, np.ndarray | None]:
        handle = self.costmaps.get(self.get_input("costmap"))  # type: ignore[attr-defined]
        return handle, footprint_of(handle)
