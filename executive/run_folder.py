"""The run folder: ``tree.svg``, ``ticks.jsonl``, ``timing.jsonl``, ``run.png``, ``summary.json``.

``ticks.jsonl`` and ``summary.json`` are byte-identical for the same scenario, tree, config and
seed; ``timing.jsonl`` (wall-clock overruns and their count) holds the measurements of this
machine, which are not.

``ticks.jsonl`` is streamed by the Recorder while the mission runs (``open_recorder``, or
``open_log`` for the tick log alone); the rest is written once at the end (``finish``) from the
Executive's in-memory trace and the recorder's ``RunCapture`` (costmaps, scans, time series).
"""

from __future__ import annotations

import json
import os
from pathlib import Path as FsPath
from typing import Any, Sequence, TextIO

from navcore.maps import OccupancyGrid

from executive.capture import RunCapture
from executive.draw_run import draw_run
from executive.executive import Executive, MissionResult
from executive.recorder import Recorder, read_log
from executive.replay_html import write_replay
from executive.render import NodeStats, RenderError, render_tree


def open_log(run_dir: str | os.PathLike) -> TextIO:
    """Create the folder and open its ``ticks.jsonl`` for the Recorder."""
    d = FsPath(run_dir)
    d.mkdir(parents=True, exist_ok=True)
    return open(d / "ticks.jsonl", "w", encoding="utf-8")


def open_timing(run_dir: str | os.PathLike) -> TextIO:
    """Open the folder's ``timing.jsonl``: the wall-clock figures kept out of the tick log."""
    d = FsPath(run_dir)
    d.mkdir(parents=True, exist_ok=True)
    return open(d / "timing.jsonl", "w", encoding="utf-8")


def open_recorder(run_dir: str | os.PathLike, grid: OccupancyGrid | None = None,
                  mcap: bool = True, sinks: Sequence[Any] = (), bag: str | None = None
                  ) -> Recorder:
    """A Recorder writing ``run_dir/ticks.jsonl`` (and ``timing.jsonl``), capturing what the
    pictures need and, when foxglove-sdk is installed and ``mcap``, writing ``run_dir/run.mcap``
    (with ``grid`` as /map); ``bag`` (``ros1``, ``ros2``, ``ros2-mcap``) also writes a ROS bag
    (``run.bag`` or the folder ``run_bag``); ``sinks`` are added too (the live server). Close it
    with ``recorder.close()``."""
    stream = open_log(run_dir)
    kept: list[Any] = [RunCapture()]
    if mcap:
        try:
            from executive.foxglove_out import FoxgloveSink
            kept.append(FoxgloveSink(mcap_path=FsPath(run_dir) / "run.mcap", grid=grid))
        except ImportError:
            pass  # foxglove-sdk is an optional extra: summary.json says the file is missing
    if bag is not None:
        from executive.bags import BagSink, bag_path
        kept.append(BagSink(bag_path(run_dir, bag), bag, grid=grid))
    return Recorder(stream, sinks=kept + list(sinks), timing=open_timing(run_dir))


def capture_of(ex: Executive) -> RunCapture | None:
    """The RunCapture among the executive's recorder sinks, if any."""
    for sink in ex.recorder.sinks:
        if isinstance(sink, RunCapture):
            return sink
    return None


def finish(run_dir: str | os.PathLike, ex: Executive, result: MissionResult,
           grid: OccupancyGrid, footprint: Sequence[Sequence[float]],
           extra: dict[str, Any] | None = None,
           obstacles: Sequence[Sequence[Sequence[float]]] = (),
           phantoms: Sequence[Sequence[Sequence[float]]] = ()) -> dict[str, Any]:
    """Write tree.svg, run.png and summary.json; returns the summary."""
    d = FsPath(run_dir)
    d.mkdir(parents=True, exist_ok=True)
    summary = result.as_dict()
    summary["recovery_events"] = ex.trace.recoveries
    summary["faults"] = ex.trace.faults
    summary["errors"] = ex.trace.errors
    diagnostics = getattr(ex.io, "diagnostics", None)   # real drivers: frames dropped and why
    if callable(diagnostics):
        summary["devices"] = diagnostics()
    summary["goals"] = [list(g) for g in ex.trace.goals]
    summary.update(extra or {})
    try:
        (d / "tree.svg").write_bytes(tree_picture(ex, summary.get("tree", ""), "svg"))
    except RenderError as e:
        summary["tree_svg_error"] = str(e)
    t = ex.trace
    contacts = [c["pose"] for c in t.contacts]
    # one footprint per contact episode is enough to see where it happened
    episodes, last = [], -1e9
    for c, pose in zip(t.contacts, contacts):
        if c["t"] - last > 1.0:
            episodes.append(pose)
        last = c["t"]
    paths = _distinct_paths(t.paths)
    title = f"{summary.get('name', '')} {result.outcome} in {result.sim_time:.1f} s".strip()
    draw_run(grid, t.poses, paths, t.recoveries, episodes, t.goals, footprint,
             str(d / "run.png"), obstacles=obstacles, phantoms=phantoms, title=title,
             capture=capture_of(ex))
    if ex.recorder.sink_errors:
        summary["recording_errors"] = list(ex.recorder.sink_errors)
    fox = [s for s in ex.recorder.sinks if type(s).__name__ == "FoxgloveSink"
           and s.writer is not None]
    if fox:
        summary["mcap_messages"] = dict(fox[0].counts)
    elif ex.recorder.sinks:
        summary["mcap_missing"] = "foxglove-sdk is not installed: pip install 'navbt[foxglove]'"
    cap = capture_of(ex)
    if cap is not None and cap.header:
        header, lines, footer = cap.header, cap.lines, cap.footer
    else:  # recorded without a capture: the tick log has the rest
        if ex.recorder.stream is not None and not ex.recorder.stream.closed:
            ex.recorder.stream.flush()
        header, lines, footer = read_log(str(d / "ticks.jsonl"))
    write_replay(str(d / "replay.html"), header, lines, footer, grid=grid, capture=cap,
                 footprint=footprint,
                 title=str(summary.get("name") or os.path.splitext(os.path.basename(
                     str(summary.get("tree", ""))))[0] or "run"))
    (d / "summary.json").write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    return summary


def tree_picture(ex: Executive, tree_path: str, fmt: str) -> bytes:
    """The run's tree annotated with what each node did (ticks, results, time RUNNING), the
    final statuses and the path to the last failed leaf."""
    stats_visitor = ex.recorder.node_stats
    stats = last = None
    if stats_visitor is not None:
        stats = [NodeStats(a, b, c, d) for a, b, c, d in stats_visitor.as_lists()]
        last = stats_visitor.last_failure
    handle = getattr(ex, "handle", None)   # the loaded tree: its main_tree is its name
    title = getattr(handle, "main_tree", "") or \
        os.path.splitext(os.path.basename(str(tree_path)))[0] or ex.tree.root.name
    return render_tree(ex.tree.root, fmt, with_status=True, title=title, stats=stats,
                       last_failure=last)


def _distinct_paths(paths: list[tuple[float, list[list[float]]]], limit: int = 30
                    ) -> list[list[list[float]]]:
    """Drop consecutive near-identical replans and keep at most ``limit`` (evenly chosen)."""
    out: list[list[list[float]]] = []
    for _, p in paths:
        if out and len(out[-1]) == len(p) and out[-1][-1] == p[-1] and out[-1][0] == p[0]:
            continue
        out.append(p)
    if len(out) > limit:
        step = len(out) / limit
        out = [out[int(i * step)] for i in range(limit)] + [out[-1]]
    return out
