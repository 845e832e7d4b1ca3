"""A recorded run's pictures: run.png's panels, its capture, and the annotated tree."""

from __future__ import annotations

import json
import math

import numpy as np
from PIL import Image

from executive.draw_run import _PALETTE, _TRAJ_COLOUR, _place_badges
from executive.recorder import read_log


def _colours(img: Image.Image, box: tuple[int, int, int, int]) -> set[tuple[int, int, int]]:
    crop = np.asarray(img.crop(box).convert("RGB")).reshape(-1, 3).astype(np.int64)
    keys = np.unique((crop[:, 0] << 16) | (crop[:, 1] << 8) | crop[:, 2])
    return {(int(k >> 16), int(k >> 8 & 255), int(k & 255)) for k in keys}


def test_run_png_has_map_side_panel_and_plots(demo_run):
    header, ticks, footer = read_log(str(demo_run / "ticks.jsonl"))
    img = Image.open(demo_run / "run.png")
    assert img.mode == "RGB"
    w, h = img.size
    # three plot rows (speed, distance, recovery; no estimator in the demo) under the map
    plots_top = h - 3 * 92 - 30
    assert plots_top > 300 and w > 900
    map_colours = _colours(img, (40, 0, w - 340, plots_top))
    assert _TRAJ_COLOUR in map_colours                          # trajectory
    assert (230, 120, 0) in map_colours                         # recovery markers
    assert sum(c in map_colours for c in _PALETTE[:3]) >= 2     # laser hits at recoveries
    plot_colours = _colours(img, (0, plots_top, w, h))
    assert (20, 110, 200) in plot_colours and (160, 0, 200) in plot_colours  # speed, distance
    # the plotted speed is the recorded odometry's: its top label is the maximum
    summary = json.loads((demo_run / "summary.json").read_text())
    assert summary["recoveries"] == ["ClearGlobalCostmap-Context", "ClearCostmapExceptRegion",
                                     "ClearEntireCostmap"]
    assert len(ticks) == footer["ticks"]


def test_recovery_badges_never_overlap_or_leave_the_picture():
    r = 8.0
    spots = [(5.0, 5.0)] * 12 + [(300.0, 200.0)] * 3 + [(299.0, 2.0)]
    placed = _place_badges(spots, 300, 200, r)
    assert len(placed) == len(spots)
    for i, (x, y) in enumerate(placed):
        assert r <= x <= 300 - r and r <= y <= 200 - r
        for qx, qy in placed[:i]:
            assert math.hypot(x - qx, y - qy) >= 2 * r
        for sx, sy in spots:   # never hides a marker
            assert math.hypot(x - sx, y - sy) >= r + 5 - 1e-9


def test_capture_matches_tick_log(demo_run):
    header, ticks, footer = read_log(str(demo_run / "ticks.jsonl"))
    stats = footer["node_stats"]
    assert len(stats) == len(header["nodes"])
    names = [n[0] for n in header["nodes"]]
    # every recovery that fired ticked at least once and succeeded in the demo
    for rec in ("ClearCostmapExceptRegion",):
        assert stats[names.index(rec)][0] >= 1 and stats[names.index(rec)][1] >= 1
    assert footer["last_failure"] and names[footer["last_failure"][-1]] == "FollowPath"
    svg = (demo_run / "tree.svg").read_text()
    assert "ticks, " in svg and "SmachRecovery" in svg and "#d62728" in svg  # main_tree as title


def test_amcl_run_shows_particles_and_localisation_error(tmp_path):
    """With AMCL estimating the pose: a fourth plot row (localisation error), particles in the
    replay page, and /particlecloud in run.mcap."""
    import os

    from executive.tree_loader import shipped_tree
    from executive.replay_html import read_page_data
    from executive.scenario import load_scenario, run_scenario
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    s = load_scenario(os.path.join(root, "executive", "data", "demo.yaml"))
    s.params = {"amcl": {"min_particles": 200, "max_particles": 500}}
    out = tmp_path / "amcl"
    run_scenario(s, shipped_tree("smach_recovery"), record_dir=str(out))
    header, ticks, footer = read_log(str(out / "ticks.jsonl"))
    data = read_page_data(str(out / "replay.html"))
    # particles sampled every 0.5 s simulated
    assert len(data["particles"]) >= int(ticks[-1]["t"] / 0.5)
    assert "truth" in data and len(data["truth"]) == len(ticks)
    summary = json.loads((out / "summary.json").read_text())
    if "mcap_messages" in summary:
        assert summary["mcap_messages"]["/particlecloud"] == len(data["particles"])
    img = Image.open(out / "run.png")
    plots_top = img.height - 4 * 92 - 30
    colours = _colours(img, (0, plots_top, img.width, img.height))
    assert (200, 60, 40) in colours      # the localisation error line
