"""navbt's executive: trees, wiring, the control loop and the ``mission`` CLI.

The public API (executive/api.py, documented in docs/api.md) is importable from here:
``from executive import open_mission, load_tree``. Names load on first use, so that
``mission --help`` does not import the whole stack.
"""

from __future__ import annotations

from typing import Any

_API = ("load_tree", "parse_tree", "load_config", "load_map", "shipped_tree", "free_start",
        "open_mission", "Navigator", "Feedback", "MissionResult",
        "World", "Pose2D", "RobotIO", "ExecutiveError", "TreeLoadError", "ConfigError",
        "WiringError", "ConfigSources")

__all__ = list(_API)


def __getattr__(name: str) -> Any:
    if name in _API:
        from executive import api
        return getattr(api, name)
    raise AttributeError(f"module 'executive' has no attribute {name!r}")
