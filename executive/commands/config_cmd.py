"""``mission config check [--config F] [--launch F --arg k=v] [--params F[:NS]]...
[--nav2-params F]``.

Prints the merged, resolved robot config with where each value came from (file:line), then every
error, warning, note and ignored key of the load at once. Exit status 1 when there are errors.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any, Mapping

from executive.commands._common import add_config_arguments, config_sources, fail


def add_arguments(p: argparse.ArgumentParser) -> None:
    sub = p.add_subparsers(dest="action", metavar="ACTION")
    c = sub.add_parser("check", help="print the merged config with the origin of each value, "
                                     "and every error, warning and ignored key",
                       description="print the merged config with the origin of each value, "
                                   "and every error, warning and ignored key")
    add_config_arguments(c)
    c.add_argument("--quiet", action="store_true", help="only the findings, not the config")


def _short(where: str) -> str:
    """A ``file:line`` with the file relative to the current folder when that is shorter."""
    file, sep, line = where.rpartition(":")
    if not sep or not line.isdigit():
        file, sep, line = where, "", ""
    try:
        rel = os.path.relpath(file)
    except ValueError:
        rel = file
    name = rel if len(rel) < len(file) else file
    return name + (f":{line}" if sep else "")


def _flow(value: Any) -> str:
    import yaml
    return yaml.safe_dump(value, default_flow_style=True, width=10 ** 6).strip().removesuffix(
        "\n...").strip()


def print_tree(doc: Mapping[str, Any], origins: Mapping[tuple, str], out: Any,
               path: tuple = (), indent: int = 0) -> None:
    """``doc`` as YAML, each value followed by ``# file:line`` of where it was set."""
    for key, value in doc.items():
        p = path + (key,)
        where = origins.get(p)
        comment = f"  # {_short(where)}" if where else ""
        pad = "  " * indent
        if isinstance(value, Mapping) and value:
            out.write(f"{pad}{key}:{comment}\n")
            print_tree(value, origins, out, p, indent + 1)
        else:
            out.write(f"{pad}{key}: {_flow(value)}{comment}\n")


def run(args: argparse.Namespace) -> int:
    from executive.config import ConfigError, config_from_mapping, merged_doc
    if args.action is None:
        return fail("config", "give an action: check (see mission config check --help)")
    sources = config_sources(args)
    try:
        doc, origins, notes = merged_doc(sources)
    except ConfigError as e:
        return fail("config", str(e))
    try:
        config = config_from_mapping(doc, sources.describe(), origins, notes)
        shown, shown_origins, found = config.namespaces, config.origins, config.report
    except ConfigError as e:
        shown, shown_origins, found = doc, origins, e.notes
    out = sys.stdout
    if not args.quiet:
        out.write(f"# robot config from {sources.describe()}\n")
        print_tree(shown, shown_origins, out)
    errors = [n for n in found if n.level == "error"]
    for level, title in (("error", "errors"), ("warning", "warnings"), ("note", "notes"),
                         ("ignored", "ignored")):
        group = [n for n in found if n.level == level]
        if group:
            out.write(f"# {title} ({len(group)})\n")
            for n in group:
                where = f"{_short(n.where)}: " if n.where else ""
                out.write(f"{where}{level}: {n.text}\n")
    out.write(f"{len(errors)} error(s), {sum(n.level == 'warning' for n in found)} "
              f"warning(s)\n")
    return 1 if errors else 0
