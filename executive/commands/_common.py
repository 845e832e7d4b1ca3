"""Helpers shared by the subcommands: one-line errors and argument parsing."""

from __future__ import annotations

import argparse
import math
import sys
from typing import Any


def fail(command: str, message: str) -> int:
    """Print one clear error line (``mission <command>: <message>``) and return exit status 1."""
    print(f"mission {command}: {message}", file=sys.stderr)
    return 1


def parse_pose(text: str) -> Any:
    """``X,Y`` or ``X,Y,YAW`` (metres, radians) for argparse ``type=``; a navcore Pose2D."""
    from navcore.types import Pose2D  # numpy: only when a pose is actually parsed
    parts = text.replace(" ", "").split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not X,Y[,YAW] (numbers)") from None
    if len(values) not in (2, 3) or not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"{text!r} is not X,Y[,YAW]")
    return Pose2D(values[0], values[1], values[2] if len(values) == 3 else 0.0)


def add_nav2_distro(p: argparse.ArgumentParser) -> None:
    """``--nav2-distro``: the Nav2 distribution whose node semantics a tree follows."""
    p.add_argument("--nav2-distro", choices=("humble", "jazzy", "kilted", "main", "navbt"),
                   help="Nav2 distribution whose semantics apply (default: the file's "
                        "nav2_distro, else jazzy for BT.CPP 4 XML, humble for BT.CPP 3 XML, "
                        "navbt's own for YAML)")


def add_config_arguments(p: argparse.ArgumentParser, config_help: str | None = None) -> None:
    """The robot config options every command that takes a config shares: a navbt robot YAML
    and/or ROS files (a roslaunch file with args, rosparam files into namespaces, a Nav2
    parameter file)."""
    g = p.add_argument_group("robot config (a navbt robot YAML and/or ROS files, merged in "
                             "this order)")
    g.add_argument("--config", metavar="ROBOT.yaml",
                   help=config_help or "navbt robot config YAML (default: the bundled robot, "
                                       "unless ROS files are given)")
    g.add_argument("--launch", metavar="FILE.launch",
                   help="roslaunch file that loads the move_base (and amcl) parameters")
    g.add_argument("--arg", action="append", default=[], metavar="NAME=VALUE", type=_launch_arg,
                   help="a launch <arg> value (repeatable), as NAME:=VALUE on roslaunch's "
                        "command line")
    g.add_argument("--params", action="append", default=[], metavar="FILE[:NAMESPACE]",
                   help="rosparam file loaded into NAMESPACE of the move_base node (repeatable, "
                        "merged in order; no namespace: the node's own; /NAME: a global name)")
    g.add_argument("--nav2-params", action="append", default=[], metavar="FILE",
                   help="Nav2 parameter file (ros__parameters layout), repeatable")
    g.add_argument("--package-path", action="append", default=[], metavar="DIR",
                   help="where $(find PKG) looks first (then the launch file's folder and its "
                        "parents, then ROS_PACKAGE_PATH)")


def _launch_arg(text: str) -> tuple[str, str]:
    name, sep, value = text.partition(":=") if ":=" in text else text.partition("=")
    if not sep or not name.strip():
        raise argparse.ArgumentTypeError(f"{text!r} is not NAME=VALUE")
    return name.strip(), value


def config_sources(args: argparse.Namespace) -> Any:
    """The ``ConfigSources`` the options of ``add_config_arguments`` name."""
    from executive.config import ConfigSources
    return ConfigSources(config=getattr(args, "config", None),
                         launch=getattr(args, "launch", None),
                         args=dict(getattr(args, "arg", None) or []),
                         params=list(getattr(args, "params", None) or []),
                         nav2_params=list(getattr(args, "nav2_params", None) or []),
                         package_path=list(getattr(args, "package_path", None) or []))


def load_config_from_args(args: argparse.Namespace) -> Any:
    """The validated RobotConfig of the config options (ConfigError lists every error)."""
    from executive.config import load_config_sources
    return load_config_sources(config_sources(args))


def print_config_warnings(config: Any, out: Any = None) -> None:
    """The warnings of a loaded config, one line each on stderr (notes and ignored keys are
    for ``mission config check``)."""
    out = out or sys.stderr
    for n in getattr(config, "report", []):
        if n.level == "warning":
            print(str(n), file=out)
