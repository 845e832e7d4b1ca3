"""AMCL figures against the original C++ (ros_navigation_internals.md 8.4), on this machine.

Speed: one likelihood-field sensor update with 2000 particles x 30 beams and 5000 x 60 (C++:
1.85 ms and ~9 ms), one resample + cluster statistics of 5000 spread particles (C++: 8.7 ms with
its O(N^2) sampler), the likelihood-field set-up on a 2000 x 2000 map (C++: 1.65 s), the odometry
motion model for 5000 particles, the beam model at 2000 x 30, and log playback speed (ACES log,
amcl defaults, full update pipeline). Maps: our synthetic office floors at 0.05 m.

With ``--accuracy`` it also replays the Intel and ACES logs (registered maps and maps built from
the logs; on the registered maps also against the scans' best fits on the map, ``*_fit_*``) and
global localisation on ACES, printing the accuracy figures the tests bound.

    python bench/bench_amcl.py [--json] [--accuracy]
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from hw.logplayback import read_carmen
from navcore.localization import Amcl
from navcore.localization.distance_field import distance_field
from navcore.localization.motion_models import MODEL_CODES, sample_motion
from navcore.raycast import cast_rays
from navcore.synthetic_maps import office_map
from navcore.types import LaserScan, Pose2D

DATA = Path(__file__).resolve().parent.parent.parent / "shared" / "data"


def median_ms(fn: Callable[[], Any], repeat: int) -> float:
    fn()  # compile / warm caches
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t) * 1e3)
    return statistics.median(times)


def synthetic_scan(grid, pose: Pose2D) -> LaserScan:
    """360 beams over 2 pi, range_max 30 m, like the C++ baseline's synthesised scan."""
    angles = np.linspace(-math.pi, math.pi, 360, endpoint=False)
    occ = np.ascontiguousarray(grid.data == 100).astype(np.uint8)
    r = cast_rays(occ, 0.0, 0.0, grid.resolution, pose.x, pose.y, angles + pose.theta, 30.0)
    return LaserScan(0.0, angles[0], angles[-1], angles[1] - angles[0], 0.0, 0.0, 0.0, 30.0, r)


def speed() -> dict[str, float]:
    grid = office_map(1000)
    rng = np.random.default_rng(0)
    pose = Pose2D(3.0, 3.0, 0.3)
    scan = synthetic_scan(grid, pose)
    out: dict[str, float] = {}
    for n, beams, key in ((2000, 30, "amcl_lf_2000x30_ms"), (5000, 60, "amcl_lf_5000x60_ms")):
        a = Amcl(grid, {"max_particles": n, "min_particles": n, "laser_max_beams": beams}, rng)
        a.set_initial_pose(pose, np.diag([0.5, 0.5, 0.2]))
        out[key] = median_ms(lambda: a._sensor_update(scan, Pose2D()), 50)
    a = Amcl(grid, {"max_particles": 2000, "min_particles": 2000, "laser_max_beams": 30,
                    "laser_model_type": "beam"}, rng)
    a.set_initial_pose(pose, np.diag([0.5, 0.5, 0.2]))
    out["amcl_beam_2000x30_ms"] = median_ms(lambda: a._sensor_update(scan, Pose2D()), 10)

    a = Amcl(grid, {"max_particles": 5000, "min_particles": 100}, rng)
    a.global_localization()
    parts0 = a.particles.copy()

    times = []
    for i in range(21):  # resample + cluster statistics, as the C++ figure; set-up not timed
        a.particles = parts0.copy()
        a.weights = rng.random(len(parts0))
        a.weights /= a.weights.sum()
        t = time.perf_counter()
        a._resample()
        a._refresh_clusters()
        if i:  # the first one compiles
            times.append((time.perf_counter() - t) * 1e3)
    out["amcl_resample_5000_ms"] = statistics.median(times)
    noise = rng.standard_normal((5000, 3))
    alphas = np.full(5, 0.2)
    out["amcl_odom_5000_ms"] = median_ms(
        lambda: sample_motion(parts0, 0.1, 0.2, 0.01, 0.05, alphas, MODEL_CODES["diff"], noise), 50)

    big = office_map(2000)
    out["amcl_lf_setup_2000_ms"] = median_ms(lambda: distance_field(big.data, 0.05, 2.0), 3)

    log = read_carmen(DATA / "logs" / "aces-corrected.log.gz")
    from navcore.maps import load_map
    amap = load_map(DATA / "maps" / "aces" / "aces.yaml")
    ref = log.reference_in_map(math.radians(269.5))
    a = Amcl(amap, None, np.random.default_rng(1))
    a.set_initial_pose(Pose2D(*ref[0]), np.diag([0.01, 0.01, 0.003]))
    scans = [log.scan(k, 50.0) for k in range(len(log))]
    t = time.perf_counter()
    for k in range(len(log)):
        a.update(Pose2D(*log.scan_odom[k]), scans[k], Pose2D())
    out["amcl_log_scans_per_s"] = len(log) / (time.perf_counter() - t)
    return out


def accuracy() -> dict[str, float]:
    """Replay figures (the same runs as tests/test_amcl_logs.py, on whole logs)."""
    import importlib.util
    spec = importlib.util.spec_from_file_location(
        "replay", Path(__file__).resolve().parent.parent / "tests" / "test_amcl_logs.py")
    replay = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(replay)
    out: dict[str, float] = {}
    for name in ("aces", "intel"):
        for mapkind, params in (("registered", {}), ("registered", replay.TUNED),
                                ("selfmap", replay.TUNED)):
            tag = f"{name}_{mapkind}_{'tuned' if params else 'defaults'}"
            # on the registered maps also against each 10th scan's best fit on the map
            r = replay.track(DATA, name, params, selfmap=mapkind == "selfmap",
                             against_fit_every=10 if mapkind == "registered" else 0)
            for k, v in r.items():
                out[f"{tag}_{k}"] = round(v, 3)
    g = replay.global_aces(DATA, {}, seed=1)
    out.update({f"aces_global_{k}": v for k, v in g.items()})
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--accuracy", action="store_true", help="also replay the logs (slow)")
    args = ap.parse_args()
    figures = speed()
    baseline = {"amcl_lf_2000x30_ms": 1.85, "amcl_resample_5000_ms": 8.7,
                "amcl_lf_setup_2000_ms": 1650.0, "amcl_beam_2000x30_ms": 11.1,
                "amcl_odom_5000_ms": 0.81}
    for k, v in figures.items():
        c = f"   (C++ {baseline[k]}, {baseline[k] / v:.1f}x)" if k in baseline else ""
        print(f"{k:28s} {v:10.3f}{c}")
    if args.accuracy:
        acc = accuracy()
        for k, v in acc.items():
            print(f"{k:44s} {v}")
        figures.update({k: v for k, v in acc.items()})
    if args.json:
        print(json.dumps({k: round(v, 4) for k, v in figures.items()}))


if __name__ == "__main__":
    main()
