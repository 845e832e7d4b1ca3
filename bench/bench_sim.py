"""Benchmark of the simulator: simulated seconds per second.

One diff-drive robot with a 720-beam laser (270 deg, 30 m) at 10 Hz and odometry at 50 Hz
wanders the Willow Garage map, unknown space solid (a synthetic office map when the shared data
is absent), commanded at 20 Hz by a small reactive wanderer the way the executive would drive
it; the wanderer's own time is not counted (its commands are recorded, then replayed to a fresh
simulator with the same seed under the timers). Also reported: the same with the IMU at 50 Hz, and
the cost of one 720-beam scan. Factors are simulated seconds per second of this process's CPU
time (equal to wall time on an idle machine); the wall figure is printed too, lower whenever
other jobs share the cores. Each figure pools ``--runs`` wanderers (seeds 0, 1, ...): the laser
noise steers a wanderer, and one path alone can be up to 25 % faster or slower than another.

    python bench/bench_sim.py [--seconds 60] [--runs 8] [--json]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from hw.sim import Simulator, SimWorld  # noqa: E402
from navcore.clock import SimClock  # noqa: E402
from navcore.maps import load_map  # noqa: E402
from navcore.synthetic_maps import office_map  # noqa: E402
from navcore.types import Pose2D, Twist  # noqa: E402

DATA = Path(os.environ.get("NAVBT_DATA")
            or Path(__file__).resolve().parent.parent.parent / "shared" / "data")
WILLOW = DATA / "maps" / "willow_garage" / "willow-full-0.05.yaml"

LASER = {"preset": "urg04lx", "angle_min": -2.35619449, "angle_max": 2.35619449, "beams": 720,
         "range_max": 30.0, "scan_time": 0.1, "range_noise_stddev": 0.01,
         "mount": [0.15, 0.0, 0.0]}


def load_world() -> tuple[SimWorld, str]:
    if WILLOW.exists():
        # unknown space is outside the building: solid, so the wanderer stays inside
        return SimWorld(load_map(WILLOW), unknown_is_obstacle=True), "willow_garage"
    return SimWorld(office_map(1000), unknown_is_obstacle=True), "office_1000"


def start_pose(world: SimWorld) -> Pose2D:
    """The free cell with the most clearance: room to wander."""
    clear = world.clearance.astype(np.float64)
    clear[world.grid.data != 0] = 0
    r, c = np.unravel_index(int(np.argmax(clear)), clear.shape)
    return Pose2D(world.origin_x + (c + 0.5) * world.resolution,
                  world.origin_y + (r + 0.5) * world.resolution, 0.3)


def wander(scan_ranges: np.ndarray, n: int) -> Twist:
    """Drive ahead, turn towards the more open side when something is close in front."""
    r = np.nan_to_num(scan_ranges, posinf=30.0)
    front = float(np.min(r[n // 2 - n // 8:n // 2 + n // 8]))
    if front < 0.8:
        left = float(np.mean(r[n // 2:]))
        right = float(np.mean(r[:n // 2]))
        return Twist(0.0, 0.0, 1.0 if left > right else -1.0)
    return Twist(min(0.6, 0.4 * front), 0.0, 0.0)


def _simulator(world: SimWorld, imu: bool, seed: int) -> tuple[Simulator, SimClock]:
    clock = SimClock()
    robot = {"laser": LASER, "imu": {"enabled": imu}, "odom_rate": 50.0}
    return Simulator(world, robot, clock, np.random.default_rng(seed), start=start_pose(world)), \
        clock


def run(world: SimWorld, seconds: float, imu: bool, seed: int = 0
        ) -> tuple[float, float, Simulator]:
    """(CPU factor, wall factor, the simulator) of one wanderer. The wanderer drives a first run
    and its commands are recorded; a second simulator with the same seed then replays them under
    the timers (one seed, one trace: checked), so the figure holds the simulator's work only:
    not the wanderer's, nor two timer reads a step (system calls, which on a host with
    page-table isolation slowed the steps after them by 15-20 %)."""
    period = 0.05
    steps = int(round(seconds / period))
    sim, clock = _simulator(world, imu, seed)
    n = len(sim.config.laser.angles)
    commands = []
    cmd = Twist()
    last_stamp = -1.0
    for _ in range(steps):
        scan = sim.laser.scan()
        if scan.stamp != last_stamp:
            cmd, last_stamp = wander(scan.ranges, n), scan.stamp
        commands.append(cmd)
        clock.advance(period)
        sim.base.send(cmd)
        sim.step()
    driven = sim.true_pose()
    sim, clock = _simulator(world, imu, seed)
    # what the executive does every cycle: command, step, read odometry and the laser
    send, step, odometry, scan, advance = sim.base.send, sim.step, sim.base.odometry, \
        sim.laser.scan, clock.advance
    t0, c0 = time.perf_counter(), time.process_time()
    for cmd in commands:
        advance(period)
        send(cmd)
        step()
        odometry()
        scan()
    cpu = time.process_time() - c0
    wall = time.perf_counter() - t0
    if sim.true_pose() != driven:
        raise RuntimeError(f"seed {seed}: the replay left the recorded path ({sim.true_pose()} "
                           f"vs {driven})")
    return seconds / cpu, seconds / wall, sim


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=60.0, help="simulated seconds per run")
    ap.add_argument("--runs", type=int, default=8, help="wanderers (seeds 0, 1, ...) pooled")
    ap.add_argument("--json", action="store_true", help="print a JSON line of figures last")
    args = ap.parse_args()
    world, name = load_world()
    run(world, 2.0, True)  # compile and warm the caches
    seeds = range(max(1, args.runs))
    plain = [run(world, args.seconds, False, seed) for seed in seeds]
    with_imu = [run(world, args.seconds, True, seed) for seed in seeds]
    total = args.seconds * len(seeds)
    factor = total / sum(args.seconds / f for f, _, _ in plain)
    factor_wall = total / sum(args.seconds / fw for _, fw, _ in plain)
    factor_imu = total / sum(args.seconds / f for f, _, _ in with_imu)
    sim = plain[0][2]
    # one scan alone
    p = sim.true_pose()
    reps = 300
    t0 = time.process_time()
    for _ in range(reps):
        sim._publish_scan()
    scan_ms = (time.process_time() - t0) / reps * 1e3
    travelled = sim.travelled
    print(f"map {name} {world.grid.width}x{world.grid.height} @ {world.resolution} m, "
          f"{len(seeds)} x {args.seconds:.0f} s simulated, laser 720 beams @ 10 Hz, "
          f"odometry @ 50 Hz")
    print(f"  realtime factor          {factor:8.0f} x   (goal > 500; per CPU second)")
    print("  per wanderer             " + " ".join(f"{f:.0f}" for f, _, _ in plain))
    print(f"  realtime factor, wall    {factor_wall:8.0f} x   (lower when the cores are shared)")
    print(f"  realtime factor with IMU {factor_imu:8.0f} x")
    print(f"  one 720-beam scan        {scan_ms:8.3f} ms")
    print(f"  seed 0 wandered {travelled:.1f} m, {len(sim.contacts)} contacts, ends at "
          f"({p.x:.2f}, {p.y:.2f})")
    if args.json:
        print(json.dumps({"sim_realtime_factor": round(factor, 1),
                          "sim_realtime_factor_wall": round(factor_wall, 1),
                          "sim_realtime_factor_with_imu": round(factor_imu, 1),
                          "sim_scan_720_ms": round(scan_ms, 4)}))


if __name__ == "__main__":
    main()
