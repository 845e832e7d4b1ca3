"""``mission validate TREE...``: load each tree and report every error, one line each."""

from __future__ import annotations

import argparse
import sys


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("trees", nargs="+", metavar="TREE", help="tree files (YAML or BT.CPP XML)")


def run(args: argparse.Namespace) -> int:
    from executive.loading import TreeLoadError, load_tree_file
    bad = 0
    for path in args.trees:
        try:
            tree = load_tree_file(path, namespace="/validate")
        except TreeLoadError as e:
            print(f"mission validate: {e}", file=sys.stderr)
            bad += 1
            continue
        n = sum(1 for _ in tree.root.iterate())
        print(f"{path}: ok ({n} nodes, root {tree.root.name})")
    return 1 if bad else 0
