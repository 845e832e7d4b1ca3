"""Picture and recording costs against the run they show.

    python bench/bench_render.py [--json] [--willow-seconds 600] [--no-willow]

For the demo scenario and a long run on the Willow Garage map (goals across the building, the
run cut at ``--willow-seconds`` simulated), each run three times: unrecorded, recorded (tick
log, capture and run.mcap), and recorded again for the sink timings. Figures, per run
(``demo_`` / ``willow_``):

``render_tree_svg_ms``: the annotated tree.svg; ``render_run_png_ms``: run.png;
``replay_html_ms``: replay.html (``replay_html_kb`` its size); ``mcap_write_ms_per_s``: wall ms
the Foxglove sink spends per simulated second; ``capture_ms_per_s`` the same for RunCapture;
``record_overhead_ratio``: CPU time of the recorded run over the unrecorded one (the run only;
the pictures at the end are the figures above; CPU time of this process, all its threads, so
that other programs on a shared machine move it less than wall time), the median over
``--repeats`` unrecorded/recorded pairs run in turn, after one warm-up run of each (imports and
first uses are paid once per process, not per tick); ``record_ms_per_tick`` the median extra CPU
time per tick. Compare A/B in one minute.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import sys
import tempfile
import time
from typing import Any

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))


class TimedSink:
    """Delegates to a recorder sink and adds up the wall time its calls take (bench only)."""

    def __init__(self, sink: Any) -> None:
        self.sink = sink
        self.seconds = 0.0

    def __getattr__(self, name: str) -> Any:
        return getattr(self.sink, name)

    def _timed(self, name: str, *args: Any) -> None:
        t0 = time.perf_counter()
        getattr(self.sink, name)(*args)
        self.seconds += time.perf_counter() - t0

    def start(self, header: dict, executive: Any) -> None:
        self._timed("start", header, executive)

    def tick(self, line: dict, executive: Any) -> None:
        self._timed("tick", line, executive)

    def finish(self, footer: dict) -> None:
        self._timed("finish", footer)


def willow_case(seconds: float) -> dict[str, Any] | None:
    """Start and alternating far goals on the Willow Garage map (None without the data)."""
    import numpy as np

    from navcore.maps import load_map
    from navcore.raycast import distance_field
    from navcore.types import Pose2D
    sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))
    from conftest import data_root
    root = data_root()
    if root is None:
        return None
    grid = load_map(root / "maps" / "willow_garage" / "willow-full-0.05.yaml")
    clear = np.asarray(distance_field((grid.data != 0).astype(np.uint8)), float) * grid.resolution
    cells = np.argwhere(clear >= 0.9)
    # two open spots far apart, both in the largest free area (reachable from each other)
    start_cell = cells[np.argmin(cells[:, 0] + cells[:, 1])]
    far = cells[np.argmax((cells[:, 0] - start_cell[0]) ** 2 + (cells[:, 1] - start_cell[1]) ** 2)]
    to_pose = lambda c: Pose2D(*grid.map_to_world(c[1] + 0.5, c[0] + 0.5), 0.0)  # noqa: E731
    a, b = to_pose(start_cell), to_pose(far)
    return {"name": "willow", "grid": grid, "start": a, "goals": [b, a] * 20,
            "time_limit": seconds}


def demo_case() -> dict[str, Any]:
    from executive.scenario import load_scenario
    s = load_scenario(os.path.join(os.path.dirname(HERE), "executive", "data", "demo.yaml"))
    return {"name": "demo", "grid": s.grid, "start": s.start, "goals": s.goals,
            "time_limit": s.time_limit, "scenario": s}


def run_once(case: dict[str, Any], record_dir: str | None) -> dict[str, Any]:
    from executive.config import load_config
    from executive.tree_loader import shipped_tree
    from executive.mission import World, build_mission, run_mission
    from executive.recorder import Recorder
    from executive.run_folder import open_recorder
    from executive.scenario import scenario_config
    s = case.get("scenario")
    config = scenario_config(s) if s is not None else load_config(None)
    world = World(s.objects, s.moving, s.phantoms, s.faults) if s is not None else World()
    recorder = Recorder(None)
    timed: list[TimedSink] = []
    if record_dir is not None:
        recorder = open_recorder(record_dir, grid=case["grid"])
        timed = [TimedSink(k) for k in recorder.sinks]
        recorder.sinks = timed
    mission = build_mission(shipped_tree("smach_recovery"), config, case["grid"], case["start"],
                            world=world, seed=0, recorder=recorder)
    t0, c0 = time.perf_counter(), time.process_time()
    result = run_mission(mission, list(case["goals"]), case["time_limit"])
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    out: dict[str, Any] = {"wall_s": wall, "cpu_s": cpu, "sim_s": result.sim_time,
                           "ticks": result.ticks}
    if record_dir is not None:
        for t in timed:
            out[type(t.sink).__name__ + "_s"] = t.seconds
        recorder.sinks = [t.sink for t in timed]
        out.update(picture_costs(record_dir, mission, result, case, config))
    recorder.close()
    mission.executive.shutdown()
    return out


def picture_costs(record_dir: str, mission: Any, result: Any, case: dict[str, Any],
                  config: Any) -> dict[str, float]:
    """Milliseconds of each picture of the finished run, drawn one by one as finish does."""
    from executive.draw_run import draw_run
    from executive.replay_html import write_replay
    from executive.run_folder import _distinct_paths, capture_of, tree_picture
    ex = mission.executive
    cap = capture_of(ex)
    out = {}
    t0 = time.perf_counter()
    svg = tree_picture(ex, "smach_recovery", "svg")
    out["render_tree_svg_ms"] = 1e3 * (time.perf_counter() - t0)
    with open(os.path.join(record_dir, "tree.svg"), "wb") as f:
        f.write(svg)
    t = ex.trace
    t0 = time.perf_counter()
    draw_run(case["grid"], t.poses, _distinct_paths(t.paths), t.recoveries,
             [c["pose"] for c in t.contacts], t.goals, config.footprint(),
             os.path.join(record_dir, "run.png"), title=case["name"], capture=cap)
    out["render_run_png_ms"] = 1e3 * (time.perf_counter() - t0)
    t0 = time.perf_counter()
    size = write_replay(os.path.join(record_dir, "replay.html"), cap.header, cap.lines,
                        cap.footer, grid=case["grid"], capture=cap,
                        footprint=config.footprint(), title=case["name"])
    out["replay_html_ms"] = 1e3 * (time.perf_counter() - t0)
    out["replay_html_kb"] = size / 1024
    return out


def measure(case: dict[str, Any], repeats: int = 3) -> dict[str, float]:
    name = case["name"]
    ratios, extra = [], []
    with tempfile.TemporaryDirectory() as d:
        for i in range(max(1, repeats)):  # in turn, so that the machine's drift hits both
            plain = run_once(case, None)
            rec = run_once(case, os.path.join(d, f"run{i}"))
            ratios.append(rec["cpu_s"] / plain["cpu_s"])
            extra.append((rec["cpu_s"] - plain["cpu_s"]) / max(rec["ticks"], 1))
    sim = max(rec["sim_s"], 1e-9)
    fig = {
        f"{name}_sim_s": round(rec["sim_s"], 1),
        f"{name}_ticks": rec["ticks"],
        f"{name}_unrecorded_wall_s": round(plain["wall_s"], 3),
        f"{name}_recorded_wall_s": round(rec["wall_s"], 3),
        f"{name}_unrecorded_cpu_s": round(plain["cpu_s"], 3),
        f"{name}_recorded_cpu_s": round(rec["cpu_s"], 3),
        f"{name}_record_overhead_ratio": round(statistics.median(ratios), 3),
        f"{name}_record_ms_per_tick": round(1e3 * statistics.median(extra), 4),
        f"{name}_mcap_write_ms_per_s": round(1e3 * rec.get("FoxgloveSink_s", math.nan) / sim, 3),
        f"{name}_capture_ms_per_s": round(1e3 * rec.get("RunCapture_s", math.nan) / sim, 3),
        f"{name}_render_tree_svg_ms": round(rec["render_tree_svg_ms"], 2),
        f"{name}_render_run_png_ms": round(rec["render_run_png_ms"], 2),
        f"{name}_replay_html_ms": round(rec["replay_html_ms"], 2),
        f"{name}_replay_html_kb": round(rec["replay_html_kb"], 1),
    }
    return fig


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print a JSON object as the last line")
    ap.add_argument("--willow-seconds", type=float, default=600.0,
                    help="simulated seconds of the Willow Garage run (default 600)")
    ap.add_argument("--no-willow", action="store_true", help="only the demo run")
    ap.add_argument("--repeats", type=int, default=3,
                    help="unrecorded/recorded pairs per case; the ratio is their median")
    args = ap.parse_args(argv)
    cases = [demo_case()]
    if not args.no_willow:
        w = willow_case(args.willow_seconds)
        if w is None:
            print("willow: shared data not found (set NAVBT_DATA); skipped", file=sys.stderr)
        else:
            cases.append(w)
    figures: dict[str, float] = {}
    run_once(cases[0], None)  # warm-up: numba caches, imports
    with tempfile.TemporaryDirectory() as d:
        run_once(cases[0], os.path.join(d, "warm"))  # and the recording's imports, first uses
    for case in cases:
        fig = measure(case, args.repeats)
        figures.update(fig)
        for k, v in fig.items():
            print(f"{k:40s} {v}")
    figures["record_overhead_ratio"] = max(v for k, v in figures.items()
                                           if k.endswith("_record_overhead_ratio"))
    print(f"{'record_overhead_ratio (worst)':40s} {figures['record_overhead_ratio']}")
    if args.json:
        print(json.dumps(figures))
    return 0


if __name__ == "__main__":
    sys.exit(main())
