"""The way back along a recorded trail (BackOffToPreviousPose)."""

from __future__ import annotations

from typing import Any

from navcore.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE
from navcore.types import Pose2D


def back_off_trail(history: list[Pose2D], pose: Pose2D, distance: float, max_distance: float,
                   handle: Any = None) -> list[Pose2D]:
    """The trail poses from the one nearest ``pose`` back ``distance`` metres along
    ``history`` (oldest first), newest first; when that pose's footprint is in inscribed cost
    on ``handle`` (a costmap handle; None: not checked), on to the first pose free of it, at
    most ``max_distance`` back. Empty when there is no trail to go back along."""
    if not history:
        return []
    near = min(range(len(history)), key=lambda i: history[i].distance_to(pose))
    limit = max(distance, max_distance)
    trail: list[Pose2D] = []
    travelled = 0.0
    prev = history[near]
    for p in reversed(history[:near + 1]):
        travelled += p.distance_to(prev)
        if travelled > limit + 1e-9:
            break
        trail.append(p)
        prev = p
        if travelled >= distance and (handle is None or 0 <= int(handle.footprint_cost(
                p.x, p.y, p.theta)) < INSCRIBED_INFLATED_OBSTACLE):
            break
    return trail if travelled > 0.0 else []
