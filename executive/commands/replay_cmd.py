"""``mission replay RUN_DIR [--tick N]``: the tree's state at any tick of a recorded run."""

from __future__ import annotations

import argparse
import os

from executive.commands._common import fail


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("run_dir", help="a run folder (with ticks.jsonl) or a ticks.jsonl file")
    p.add_argument("--tick", type=int, default=None,
                   help="tick to show (default: the last); negative counts from the end")


def run(args: argparse.Namespace) -> int:
    from executive.recorder import read_log, statuses_at
    from executive.render import table_text
    path = args.run_dir
    if os.path.isdir(path):
        path = os.path.join(path, "ticks.jsonl")
    if not os.path.exists(path):
        return fail("replay", f"{path}: no such tick log (expected a run folder with ticks.jsonl)")
    try:
        header, ticks, footer = read_log(path)
    except (ValueError, KeyError) as e:
        return fail("replay", str(e))
    if not ticks:
        return fail("replay", f"{path}: the run recorded no ticks")
    last = ticks[-1]["tick"]
    tick = last if args.tick is None else (args.tick if args.tick >= 0 else last + 1 + args.tick)
    if not 0 <= tick <= last:
        return fail("replay", f"{path}: tick {args.tick} out of range 0..{last}")
    line = next(t for t in ticks if t["tick"] >= tick)
    statuses = statuses_at(header, ticks, tick)
    pose = line.get("pose")
    print(f"tick {tick}/{last}  t={line['t']:.2f} s  root={line.get('root', '?')}"
          + (f"  pose=({pose[0]:.2f}, {pose[1]:.2f}, {pose[2]:.2f})" if pose else "")
          + f"  cmd={line.get('cmd')}")
    print(table_text(header["nodes"], statuses))
    bb: dict = {}
    for t in ticks:
        if t["tick"] > tick:
            break
        bb.update(t.get("bb", {}))
    shown = {k: v for k, v in bb.items() if not (isinstance(v, dict) and "path" in v)}
    if shown:
        print("blackboard: " + ", ".join(f"{k}={v}" for k, v in sorted(shown.items())))
    for e in line.get("events", []):
        print(f"event: {e}")
    if footer and tick == last:
        print(f"outcome: {footer.get('outcome')} {footer.get('reason', '')}".rstrip())
    return 0
