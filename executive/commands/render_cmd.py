"""``mission render TREE [-f svg|png|dot|txt] [-o FILE] [--ports] [--collapse NAME]``: draw a tree."""

from __future__ import annotations

import argparse
import sys

from executive.commands._common import fail


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("tree", help="tree file (YAML or BT.CPP XML)")
    p.add_argument("-f", "--format", choices=("svg", "png", "dot", "txt"), default="txt",
                   help="output format (default txt)")
    p.add_argument("-o", "--output", help="output file (default: stdout for txt/dot, "
                                          "TREE.<format> for svg/png)")
    p.add_argument("--ports", action="store_true",
                   help="show each node's ports: constants that differ from the default and "
                        "the blackboard keys it reads ({key}) and writes (-> {key})")
    p.add_argument("--collapse", action="append", default=[], metavar="SUBTREE",
                   help="draw this SubTree instance as one node (repeat; 'all' for every one)")


def run(args: argparse.Namespace) -> int:
    import os

    from executive.render import RenderError, render_tree
    from executive.tree_loader import TreeLoadError, load_tree_file
    collapse = ["*" if c == "all" else c for c in args.collapse]
    try:
        loaded = load_tree_file(args.tree, namespace="/render")
        data = render_tree(loaded.root, args.format, ports=args.ports, collapse=collapse,
                           title=loaded.main_tree) if args.format != "txt" else \
            render_tree(loaded.root, "txt")
    except (TreeLoadError, RenderError) as e:
        return fail("render", str(e))
    except (OSError, UnicodeDecodeError) as e:
        return fail("render", f"{args.tree}: cannot read tree ({e})")
    out = args.output
    if out is None and args.format in ("svg", "png"):
        out = os.path.splitext(os.path.basename(args.tree))[0] + "." + args.format
    if out is None or out == "-":
        sys.stdout.buffer.write(data)
        sys.stdout.flush()
        return 0
    try:
        with open(out, "wb") as f:
            f.write(data)
    except OSError as e:
        return fail("render", f"{out}: cannot write ({e.strerror or e})")
    print(out)
    return 0
