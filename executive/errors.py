"""The executive's error for "this mission cannot be built" (the other layers have their own:
``TreeLoadError`` for trees, ``ConfigError`` for robot configs, ``ScenarioError`` for scenarios)."""

from __future__ import annotations


class WiringError(RuntimeError):
    """A component could not be built from the config; the message names it and why."""
