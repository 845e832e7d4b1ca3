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
