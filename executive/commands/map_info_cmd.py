"""``mission map-info MAP.yaml``: load a map as map_server would and describe it."""

from __future__ import annotations

import argparse
import sys


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("map", help="map_server YAML descriptor")


def run(args: argparse.Namespace) -> int:
    from navcore.maps import MapError, load_map
    try:
        grid = load_map(args.map)
    except MapError as e:
        print(f"mission map-info: {e}", file=sys.stderr)
        return 1
    c = grid.counts()
    n = grid.data.size
    print(f"{args.map}: {grid.width} x {grid.height} cells at {grid.resolution:g} m "
          f"({grid.width * grid.resolution:.2f} m x {grid.height * grid.resolution:.2f} m), "
          f"origin ({grid.origin.x:g}, {grid.origin.y:g}, {grid.origin.theta:g})")
    print(f"occupied {c['occupied']} ({100 * c['occupied'] / n:.1f} %), "
          f"free {c['free']} ({100 * c['free'] / n:.1f} %), "
          f"unknown {c['unknown']} ({100 * c['unknown'] / n:.1f} %)")
    return 0
