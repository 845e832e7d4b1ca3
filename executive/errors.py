"""The executive's one base exception, and its error for "this mission cannot be built".

Every error class of the executive derives from ``ExecutiveError`` beside its other base
(``TreeLoadError`` for trees and ``ConfigError`` for robot configs are also ``ValueError``s;
``ScenarioError``, ``SweepError``, ``ParamsError``, ... likewise), so a caller catches one type
for the layer. navcore, hw and behaviors have their own: ``NavcoreError``, ``HwError``,
``BehaviorError``."""

from __future__ import annotations


class ExecutiveError(Exception):
    """Base of the executive's errors."""


class WiringError(ExecutiveError, RuntimeError):
    """A component could not be built from the config; the message names it and why."""
