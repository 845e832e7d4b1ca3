"""Imports every node module so that each node class registers itself (py_trees ports registry)."""

from behaviors import actions, conditions, controls, decorators, navigate, reconfigure, recoveries  # noqa: F401
