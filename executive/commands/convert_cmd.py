"""``mission convert TREE [-o OUT]``: YAML -> BT.CPP v4 XML, or XML -> YAML."""

from __future__ import annotations

import argparse
import sys

from executive.commands._common import add_nav2_distro, fail


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("tree", help="a .yaml tree (converted to XML) or a .xml tree (to YAML)")
    p.add_argument("-o", "--output", help="output file (default stdout); its extension may "
                                          "choose the format")
    p.add_argument("--to", choices=("xml", "yaml"), help="target format (default: the other one)")
    add_nav2_distro(p)


def run(args: argparse.Namespace) -> int:
    from executive.tree_loader import TreeLoadError, load_tree_file, to_xml, to_yaml
    target = args.to
    if target is None and args.output:
        target = "xml" if args.output.endswith(".xml") else "yaml" if args.output.endswith(
            (".yaml", ".yml")) else None
    if target is None:
        target = "yaml" if args.tree.endswith(".xml") else "xml"
    try:
        loaded = load_tree_file(args.tree, namespace="/convert", nav2_distro=args.nav2_distro)
        text = to_xml(loaded) if target == "xml" else to_yaml(loaded)
    except TreeLoadError as e:
        return fail("convert", str(e))
    if args.output:
        try:
            with open(args.output, "w", encoding="utf-8") as f:
                f.write(text)
        except OSError as e:
            return fail("convert", f"{args.output}: cannot write ({e.strerror or e})")
        print(args.output)
    else:
        sys.stdout.write(text if text.endswith("\n") else text + "\n")
    return 0
