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
    "demo": ("demo_cmd", "run the recovery tree on a bundled map with a stuck robot; write a run "
                         "folder"),
    "run": ("run_cmd", "run a tree to one or more goals on the simulator (or hardware)"),
    "validate": ("validate_cmd", "load trees (YAML or BT.CPP XML) and report every error"),
    "render": ("render_cmd", "draw a tree as text, DOT, SVG or PNG"),
    "nodes": ("nodes_cmd", "list node types, or show one node's ports and documentation"),
    "convert": ("convert_cmd", "convert a tree between YAML and BT.CPP XML"),
    "replay": ("replay_cmd", "show the tree's state at any tick of a recorded run"),
    "scenario": ("scenario_cmd", "run stuck-robot scenarios against trees"),
    "sweep": ("sweep_cmd", "run a parameter / tree sweep over scenarios (resumable), or report "
                           "one"),
    "tune": ("tune_cmd", "search parameters with Optuna for the best success rate over "
                         "scenarios"),
    "config": ("config_cmd", "check a robot config (navbt YAML, roslaunch, rosparam or Nav2 "
                             "files): merged values with their origin, every error at once"),
    "bag": ("bag_cmd", "show a ROS 1 / ROS 2 bag's topics; with --map, run AMCL on its scans"),
    "warmup": ("warmup_cmd", "compile the numba kernels a mission uses into the cache (once "
                             "after installing)"),
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
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
