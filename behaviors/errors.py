"""behaviors' one base exception: every error class of behaviors derives from ``BehaviorError``,
beside its other base (``ComponentError`` is also a ``RuntimeError``, ``ScriptError`` a
``ValueError``)."""

from __future__ import annotations


class BehaviorError(Exception):
    """Base of the behaviour layer's errors (``ComponentError``, ``ScriptError``)."""
