"""Imports every node module so that each node class registers itself (py_trees ports registry).

Nodes live one per file (a few small families share one) in the packages below, as Nav2's
plugins do: ``actions`` (including the recoveries), ``conditions``, ``controls``, ``decorators``.
"""

import importlib
import pkgutil

import behaviors

PACKAGES = ("actions", "conditions", "controls", "decorators", "nav2", "btcpp")

for _package in PACKAGES:
    _path = [p + "/" + _package for p in behaviors.__path__]
    for _info in pkgutil.iter_modules(_path):
        importlib.import_module(f"behaviors.{_package}.{_info.name}")
