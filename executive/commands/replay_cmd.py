"""``mission replay RUN_DIR [--tick N] [-f txt|png] [--html]``: a recorded run at any tick.

Text shows the tree's statuses, the blackboard and the events; ``-f png`` draws that tick's
frame (map, costmaps, laser, path, footprint, tree statuses) from the run's replay.html;
``--html`` writes replay.html for a run folder that has none (from ticks.jsonl, and the map that
summary.json names when it exists).
"""

from __future__ import annotations

import argparse
import os

from executive.commands._common import fail


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("run_dir", help="a run folder (with ticks.jsonl) or a ticks.jsonl file")
    p.add_argument("--tick", type=int, default=None,
                   help="tick to show (default: the last); negative counts from the end")
    p.add_argument("-f", "--format", choices=("txt", "png"), default="txt",
                   help="txt (default) prints the state; png draws the frame")
    p.add_argument("-o", "--output", help="file for --html or -f png (default: in RUN_DIR)")
    p.add_argument("--html", action="store_true",
                   help="write RUN_DIR/replay.html (a self-contained page with a timeline)")


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
    folder = os.path.dirname(os.path.abspath(path))
    if args.html:
        return _write_html(folder, header, ticks, footer, args.output)
    if args.format == "png":
        return _write_frame(folder, tick, args.output)
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


def _write_html(folder: str, header: dict, ticks: list, footer: dict | None,
                output: str | None) -> int:
    import json

    from executive.replay_html import write_replay
    grid = None
    summary_path = os.path.join(folder, "summary.json")
    if os.path.exists(summary_path):
        try:
            with open(summary_path, encoding="utf-8") as f:
                map_path = json.load(f).get("map")
        except (OSError, ValueError):
            map_path = None
        if map_path and os.path.exists(map_path):
            from navcore.maps import MapError, load_map
            try:
                grid = load_map(map_path)
            except MapError as e:
                return fail("replay", str(e))
    out = output or os.path.join(folder, "replay.html")
    try:
        write_replay(out, header, ticks, footer, grid=grid)
    except OSError as e:
        return fail("replay", f"{out}: cannot write ({e.strerror or e})")
    print(out)
    return 0


def _write_frame(folder: str, tick: int, output: str | None) -> int:
    from executive.replay_html import draw_frame, read_page_data
    page = os.path.join(folder, "replay.html")
    if not os.path.exists(page):
        return fail("replay", f"{page}: no replay page to draw from; write it first with "
                              f"`mission replay {folder} --html`")
    try:
        data = read_page_data(page)
    except ValueError as e:
        return fail("replay", str(e))
    if tick not in data["ticks"]:
        return fail("replay", f"{page}: tick {tick} is not in the page")
    out = output or os.path.join(folder, f"tick-{tick}.png")
    try:
        draw_frame(data, data["ticks"].index(tick), out)
    except OSError as e:
        return fail("replay", f"{out}: cannot write ({e.strerror or e})")
    print(out)
    return 0
