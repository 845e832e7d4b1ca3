"""``mission validate TREE...``: load each tree and report every error, one line each.

Each problem reads ``file:line: Name (Type): what`` and all of a file's problems are listed at
once. Nav2 attributes kept but meaning nothing here are listed as notes with ``-v``.

With config options (``--config``, ``--launch`` ...), the robot config is loaded and
checked too.
"""

from __future__ import annotations

import argparse
import sys

from executive.commands._common import (add_config_arguments, add_nav2_distro,
                                        config_sources)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("trees", nargs="+", metavar="TREE", help="tree files (YAML or BT.CPP XML)")
    p.add_argument("-v", "--verbose", action="store_true",
                   help="also list Nav2 attributes that are kept but have no meaning here")
    add_nav2_distro(p)
    add_config_arguments(p, "also validate this navbt robot config YAML")


def run(args: argparse.Namespace) -> int:
    from executive.loading import TreeLoadError, load_loaded
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
        try:
            tree = load_loaded(path, namespace="/validate", nav2_distro=args.nav2_distro)
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
