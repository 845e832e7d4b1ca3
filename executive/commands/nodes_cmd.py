"""``mission nodes [NAME]``: every node type with a line of doc, or one node's ports in full."""

from __future__ import annotations

import argparse

from executive.commands._common import fail


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("name", nargs="?", help="a node type (e.g. RecoveryNode)")
    p.add_argument("--groot", metavar="FILE", nargs="?", const="-",
                   help="write a Groot2 palette (TreeNodesModel of every node type) to FILE "
                        "(default stdout)")


def _ports(cls) -> list[tuple[str, str, object]]:
    out = []
    for direction, attr in (("in", "INPUT_PORTS"), ("out", "OUTPUT_PORTS")):
        for port, info in (getattr(cls, attr, None) or {}).items():
            out.append((direction, port, info))
    return out


def run(args: argparse.Namespace) -> int:
    import difflib
    import inspect

    from behaviors.base import node_classes
    classes = node_classes()
    if args.groot is not None:
        from executive.tree_xml import groot_palette
        text = groot_palette(classes)
        if args.groot == "-":
            print(text, end="")
            return 0
        try:
            with open(args.groot, "w", encoding="utf-8") as f:
                f.write(text)
        except OSError as e:
            return fail("nodes", f"{args.groot}: cannot write ({e.strerror or e})")
        print(args.groot)
        return 0
    if args.name is None:
        by_cat: dict[str, list[str]] = {}
        for tag, cls in sorted(classes.items()):
            by_cat.setdefault(getattr(cls, "CATEGORY", "Action"), []).append(tag)
        for cat in sorted(by_cat):
            print(f"{cat}:")
            for tag in by_cat[cat]:
                print(f"  {tag:32s} {classes[tag].describe()}")
        return 0
    cls = classes.get(args.name)
    if cls is None:
        close = difflib.get_close_matches(args.name, list(classes), n=1)
        hint = f" (did you mean '{close[0]}'?)" if close else ""
        return fail("nodes", f"unknown node type '{args.name}'{hint}")
    print(f"{args.name} ({getattr(cls, 'CATEGORY', 'Action')})")
    print(inspect.cleandoc(cls.__doc__ or ""))
    ports = _ports(cls)
    if ports:
        print("ports:")
    for direction, port, info in ports:
        default = getattr(info, "default_value", None)
        dtype = getattr(info, "data_type", None)
        tname = getattr(dtype, "__name__", str(dtype)) if dtype is not None else "any"
        desc = getattr(info, "description", "") or ""
        d = f" = {default!r}" if default is not None else ""
        print(f"  {direction:3s} {port}: {tname}{d}  {desc}".rstrip())
    return 0
