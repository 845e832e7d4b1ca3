"""AMCL on the real Intel and ACES CARMEN logs, played through hw.logplayback.

Two kinds of map. The registered map_server maps (SOURCES.md) came from a *different* SLAM run:
with our loader, frames and beam convention the reference poses fit them as SOURCES.md says
(median end point 0.07 / 0.08 m from an occupied cell), but scan by scan the map is best fitted
0.2 m (ACES) / 0.16 m (Intel) away from the reference pose, in coherent patches (the map is
locally shifted, by up to 0.5 m and 8 degrees on Intel from scan ~760 on). That bounds what any
map-based localiser can show against the reference, so on these maps the filter is also measured
against those per-scan best fits. Maps drawn from the log's own reference poses (``map_from_log``)
measure the filter itself. The bounds sit just above what was measured (bench/bench_amcl.py
--accuracy prints the whole-log figures).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from hw.logplayback import LogPlayback, map_from_log, read_carmen
from navcore.clock import SimClock
from navcore.localization import Amcl
from navcore.localization.evaluation import tracking_errors
from navcore.localization.map_agreement import best_fit_poses, endpoint_distances
from navcore.maps import FREE, load_map
from navcore.types import Pose2D

LOGS = {"aces": ("aces-corrected.log.gz", "aces/aces.yaml", 269.5),
        "intel": ("intel-corrected.log.gz", "intel_lab/intel.yaml", 12.7)}
# a sharper setting than amcl's defaults: the product likelihood over 90 beams, a floor of 500
# particles, no random injection. amcl's default likelihood_field (p = 1 + sum pz^3 over 30 beams)
# is so flat that the cloud keeps all 5000 particles and the median error is 0.18 m (1.4 deg) on
# ACES even on the map drawn from the log itself
SHARP = {"laser_model_type": "likelihood_field_prob", "laser_max_beams": 90,
         "min_particles": 500, "recovery_alpha_slow": 0.0, "recovery_alpha_fast": 0.0}
# what a user would set for these logs: scans are ~3 s and ~0.8 m apart, so resample after every
# update (resample_interval 1; with 2 the median error on ACES is twice as large), and keep at
# least 2000 particles for the odometry spread over such steps
TUNED = dict(SHARP, min_particles=2000, resample_interval=1)
BEARINGS = -math.pi / 2 + math.pi / 180 * np.arange(180)  # CARMEN: 180 beams from -90 deg, 1 deg
_cache: dict = {}


def _load(data: Path, name: str, selfmap: bool):
    key = (name, selfmap)
    if key not in _cache:
        logfile, mapfile, angle = LOGS[name]
        log = read_carmen(data / "logs" / logfile)
        if selfmap:
            _cache[key] = (log, map_from_log(log, 0.05), log.reference)
        else:
            _cache[key] = (log, load_map(data / "maps" / mapfile),
                           log.reference_in_map(math.radians(angle)))
    return _cache[key]


def track(data: Path, name: str, params: dict, selfmap: bool = False, n_scans: int | None = None,
          seed: int = 1, against_fit_every: int = 0) -> dict[str, float]:
    """Replay a log from the known first pose; compare map -> odom (+) odometry with the
    reference at every scan, as a robot's tf tree would give the pose. With
    ``against_fit_every`` k, also against the per-scan best fit on the map of every k-th scan
    (keys ``fit_*``)."""
    log, grid, ref = _load(data, name, selfmap)
    n = len(log) if n_scans is None else min(n_scans, len(log))
    clock = SimClock(float(log.scan_times[0]))
    pb = LogPlayback(log, clock)
    amcl = Amcl(grid, params, np.random.default_rng(seed))
    amcl.set_initial_pose(Pose2D(*ref[0]), np.diag([0.01, 0.01, 0.003]))
    est = np.empty((n, 3))
    updates = 0
    for k in range(n):
        clock.sleep_until(float(log.scan_times[k]))
        odom = pb.odometry().pose
        updates += amcl.update(odom, pb.scan(), pb.mount)
        p = amcl.map_to_odom().compose(odom)
        est[k] = (p.x, p.y, p.theta)
    out = tracking_errors(est, ref[:n], log.scan_times[:n])
    out["updates"] = float(updates)
    if against_fit_every:
        sub = slice(0, n, against_fit_every)
        fits = best_fit_poses(grid, ref[sub], log.scan_ranges[sub], BEARINGS, 50.0)
        fit = tracking_errors(est[sub], fits, log.scan_times[sub])
        # every k-th scan only: the lost-stretch figures would not mean the same here
        out.update({f"fit_{k}": fit[k] for k in ("median_m", "p95_m", "median_deg", "p95_deg",
                                                 "max_m")})
    return out


def global_aces(data: Path, params: dict, seed: int = 1, n_scans: int | None = None
                ) -> dict[str, float]:
    """Global localisation on ACES: filter updates until the estimate is within 0.5 m for 10
    consecutive scans, and until it stays within 0.5 m (and 1.0 m) for the rest of the run."""
    log, grid, ref = _load(data, "aces", False)
    n = len(log) if n_scans is None else n_scans
    amcl = Amcl(grid, params, np.random.default_rng(seed))
    amcl.global_localization()
    err = np.empty(n)
    upd = np.empty(n, np.int64)
    count = 0
    for k in range(n):
        odom = Pose2D(*log.scan_odom[k])
        count += amcl.update(odom, log.scan(k, 50.0), Pose2D(log.laser_offset, 0, 0))
        p = amcl.map_to_odom().compose(odom)
        err[k] = math.hypot(p.x - ref[k, 0], p.y - ref[k, 1])
        upd[k] = count
    ok = err < 0.5
    run = np.convolve(ok.astype(int), np.ones(10, int), "valid")
    first10 = int(np.argmax(run == 10)) if (run == 10).any() else n

    def stays(th: float) -> int:
        bad = np.flatnonzero(err >= th)
        return 0 if len(bad) == 0 else int(bad[-1]) + 1
    s05, s10 = stays(0.5), stays(1.0)
    return {"updates_to_10_within_0_5m": float(upd[first10]) if first10 < n else math.inf,
            "updates_until_stays_0_5m": float(upd[s05]) if s05 < n else math.inf,
            "updates_until_stays_1_0m": float(upd[s10]) if s10 < n else math.inf,
            "fraction_within_0_5m": float(ok.mean())}


@pytest.mark.parametrize("name, median, within, on_free", [("aces", 0.08, 0.82, 1.0),
                                                            ("intel", 0.09, 0.88, 0.985)])
def test_our_frames_reproduce_the_registration_statistic(shared_data, name, median, within,
                                                         on_free) -> None:
    log, grid, ref = _load(shared_data, name, False)
    assert log.laser_offset == 0.0  # so the reference poses are the laser poses
    d = endpoint_distances(grid, ref, log.scan_ranges, BEARINGS, 50.0)
    # measured (to the nearest occupied cell centre): ACES median 0.071 m, 84 % within 0.2 m;
    # Intel 0.083 m, 90 % (SOURCES.md: 0.05 / 0.07 m, 83 / 87 %; to the nearest cell's edge
    # ours are 0.042 / 0.053 m). A half-cell shift of the map changes the median by < 0.01 m.
    assert np.median(d) < median and (d < 0.2).mean() > within
    cells = [grid.world_to_map(x, y) for x, y, _ in ref]
    free = np.mean([c is not None and grid.data[c[1], c[0]] == FREE for c in cells])
    assert free >= on_free  # measured: 100 % / 98.8 % (SOURCES.md: 100 / 98.7 %)
    # the statistic tells a wrong convention: beams clockwise put it at 0.38 / 0.30 m
    assert np.median(endpoint_distances(grid, ref, log.scan_ranges, -BEARINGS, 50.0)) > 0.25


@pytest.mark.parametrize("name, offset", [("aces", 0.18), ("intel", 0.14)])
def test_the_registered_maps_fit_each_scan_away_from_the_reference(shared_data, name,
                                                                   offset) -> None:
    """Why no localiser on these maps meets 0.10 m against the reference: each scan fits its map
    best about 0.2 m away from the reference pose, and fits it there far better."""
    log, grid, ref = _load(shared_data, name, False)
    sub = slice(None, None, 10)
    fits = best_fit_poses(grid, ref[sub], log.scan_ranges[sub], BEARINGS, 50.0)
    off = np.hypot(*(fits[:, :2] - ref[sub, :2]).T)
    # measured on every 10th scan: ACES median 0.21 m (p95 0.58), Intel 0.16 m (p95 0.42)
    assert np.median(off) > offset
    # ... where the median end point is 0.024 m from the map, against 0.07-0.08 m at the reference
    at_fit = endpoint_distances(grid, fits, log.scan_ranges[sub], BEARINGS, 50.0)
    assert np.median(at_fit) < 0.03


def test_aces_tracking_with_amcl_defaults(shared_data) -> None:
    r = track(shared_data, "aces", {})
    # measured: median 0.21 m, p95 0.58 m, 1.6 deg, max 0.80 m, longest above 0.5 m: 14 updates
    assert r["median_m"] < 0.25 and r["p95_m"] < 0.75
    assert r["median_deg"] < 2.5 and r["max_m"] < 1.2
    assert r["longest_lost_updates"] <= 22
    assert r["updates"] >= 400  # nearly every scan moved the robot beyond update_min_d / a


def test_aces_tracking_on_the_registered_map_follows_the_map(shared_data) -> None:
    r = track(shared_data, "aces", TUNED, against_fit_every=10)
    # against the reference, measured: median 0.20 m, p95 0.53 m, 0.60 deg, 15 updates above
    # 0.5 m where the map is shifted by 0.45 m or more (scans 210-240): the map's disagreement
    assert r["median_m"] < 0.22 and r["median_deg"] < 0.8 and r["p95_m"] < 0.6
    # against the scans' best fits on the map, measured: median 0.029 m, p95 0.13 m, 0.19 deg,
    # at most 0.17 m: the goal (0.10 m, 2 deg, never above 0.5 m) met with respect to the map
    assert r["fit_median_m"] < 0.05 and r["fit_median_deg"] < 0.4
    assert r["fit_p95_m"] < 0.2 and r["fit_max_m"] < 0.3


def test_aces_tracking_on_a_map_from_the_log_meets_the_goal(shared_data) -> None:
    r = track(shared_data, "aces", TUNED, selfmap=True)
    # measured: median 0.031 m, p95 0.093 m, 0.21 deg, at most 0.14 m (SHARP, i.e. resampling
    # every 2nd update with 500 particles: 0.078 m, 0.44 deg, 2 updates above 0.5 m)
    assert r["median_m"] < 0.05 and r["median_deg"] < 0.4
    assert r["p95_m"] < 0.15 and r["longest_lost_updates"] == 0


def test_intel_tracking_on_a_map_from_the_log(shared_data) -> None:
    r = track(shared_data, "intel", TUNED, selfmap=True, n_scans=450)
    # measured: median 0.035 m, 0.32 deg, at most 0.13 m (whole log: 0.036 m, 0.38 deg, at
    # most 0.16 m, never above 0.5 m)
    assert r["median_m"] < 0.05 and r["median_deg"] < 0.5
    assert r["max_m"] < 0.25


def test_intel_tracking_on_the_registered_map_until_the_maps_disagree(shared_data) -> None:
    # from scan ~760 on the registered map is shifted against the reference by up to 0.5 m and
    # 8 degrees, and the filter follows neither (bench --accuracy shows the whole log)
    r = track(shared_data, "intel", TUNED, n_scans=700, against_fit_every=10)
    # measured: against the reference median 0.154 m, 0.58 deg, at most 0.53 m (one update);
    # against the best fits median 0.032 m, 0.34 deg, p95 0.17 m, at most 0.27 m
    assert r["median_m"] < 0.18 and r["median_deg"] < 0.8 and r["longest_lost_updates"] <= 2
    assert r["fit_median_m"] < 0.05 and r["fit_p95_m"] < 0.22 and r["fit_max_m"] < 0.4


def test_aces_global_localisation_with_amcl_defaults(shared_data) -> None:
    r = global_aces(shared_data, {}, n_scans=120)
    # measured (seeds 1, 2, 3): within 1.0 m for good after 28 updates, within 0.5 m for the
    # rest of the first 120 scans after 44-45 updates
    assert r["updates_until_stays_1_0m"] <= 35
    assert r["updates_until_stays_0_5m"] <= 55
    assert r["fraction_within_0_5m"] > 0.55
