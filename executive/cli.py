"""The ``mission`` command. argparse keeps ``mission --help`` fast (about 20 ms).

Each subcommand lives in its own module under ``executive/commands/`` and registers itself in
``SUBCOMMANDS``; heavy imports happen inside the command, never at the top of this file.
"""

from __future__ import annotations

import argparse
import importlib
import sys

# name -> (module under executive.commands, one-line help)
SUBCOMMANDS: dict[str, tuple[str, str]] = {
    "map-info": ("map_info_cmd", "load a map_server map and print its size and cell counts"),
}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="mission",
        description="navbt: behaviour-tree mission executive for mobile robots.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (module, help_text) in SUBCOMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        importlib.import_module(f"executive.commands.{module}").add_arguments(p)
        p.set_defaults(_module=module)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    module = importlib.import_module(f"executive.commands.{args._module}")
    try:
        return int(module.run(args) or 0)
    except KeyboardInterrupt:
        print("mission: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
