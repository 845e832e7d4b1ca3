"""``mission validate TREE...``: load each tree and report every error, one line each.

Each problem reads ``file:line: Name (Type): what`` and all of a file's problems are listed at
once. Nav2 attributes kept but meaning nothing here are listed as notes with ``-v``.

With config options (``--config``, ``--launch`` ...), the robot config is loaded and
checked too. A file given in the list that is a map descriptor (it has ``image:``), a scenario
(``map:`` with ``goals:``/``expect:``) or a robot config (only config namespaces) is checked as
one; every file is checked, whatever the others hold.
"""

from __future__ import annotations

import argparse
import sys

from executive.commands._common import (add_config_arguments, add_nav2_distro,
                                        config_sources)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("trees", nargs="+", metavar="FILE",
                   help="tree files (YAML or BT.CPP XML); map, scenario and robot config YAML "
                        "files are recognised and checked too")
    p.add_argument("-v", "--verbose", action="store_true",
                   help="also list Nav2 attributes that are kept but have no meaning here")
    add_nav2_distro(p)
    add_config_arguments(p, "also validate this navbt robot config YAML")


def run(args: argparse.Namespace) -> int:
    from executive.tree_loader import TreeLoadError, load_tree_file
    bad = 0
    sources = config_sources(args)
    if sources.config or sources.has_ros():
        from executive.config import ConfigError, load_config_sources
        try:
            config = load_config_sources(sources)
            print(f"{sources.describe()}: ok ({len(config.namespaces)} namespaces, "
                  f"{sum(n.level == 'warning' for n in config.report)} warning(s); details: "
                  "mission config check)")
        except ConfigError as e:
            print(f"mission validate: {e}", file=sys.stderr)
            bad += 1
    for path in args.trees:
        kind = _kind(path)
        if kind != "tree":
            problems = _check_other(kind, path)
            for line in problems:
                print(f"mission validate: {line}", file=sys.stderr)
            if problems:
                bad += 1
            else:
                print(f"{path}: ok ({kind})")
            continue
        try:
            tree = load_tree_file(path, namespace="/validate", nav2_distro=args.nav2_distro)
        except TreeLoadError as e:
            for line in str(e).splitlines():
                print(f"mission validate: {line}", file=sys.stderr)
            bad += 1
            continue
        n = sum(1 for _ in tree.root.iterate())
        distro = f", Nav2 {tree.distro} semantics" if tree.distro else ""
        print(f"{path}: ok ({n} nodes, root {tree.root.name}{distro})")
        if args.verbose:
            for note in tree.ignored:
                print(f"  note: {note}")
    return 1 if bad else 0


_SCENARIO_KEYS = ("goals", "expect", "start", "faults", "objects")


def _kind(path: str) -> str:
    """``tree``, ``map``, ``scenario`` or ``config``, from the file's top-level keys (anything
    unreadable is left to the tree loader, which reports why)."""
    if path.lower().endswith(".xml"):
        return "tree"
    from navcore.safe_read import ReadError, load_yaml
    try:
        doc = load_yaml(path)
    except ReadError:
        return "tree"
    if not isinstance(doc, dict) or "trees" in doc or "main_tree" in doc:
        return "tree"
    if "image" in doc:
        return "map"
    if "map" in doc and any(k in doc for k in _SCENARIO_KEYS):
        return "scenario"
    from executive.config import COMPONENT_NAMESPACES, OWN_NAMESPACES, SIM_NAMESPACE
    if doc and set(doc) <= set(OWN_NAMESPACES) | set(COMPONENT_NAMESPACES) | {SIM_NAMESPACE}:
        return "config"
    return "tree"


def _check_other(kind: str, path: str) -> list[str]:
    """Every problem of a map, scenario or robot config file, one line each."""
    try:
        if kind == "map":
            from navcore.maps import load_map
            load_map(path)
        elif kind == "scenario":
            from executive.scenario import load_scenario
            load_scenario(path)
        else:
            from executive.config import load_config
            load_config(path)
    except ValueError as e:  # MapError, ScenarioError, ConfigError
        return str(e).splitlines()
    return []
