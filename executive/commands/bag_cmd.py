"""``mission bag BAG [--map MAP.yaml]``: what a ROS bag holds; with a map, AMCL on its scans.

Reads ROS 1 bags, rosbag2 folders (sqlite3 or MCAP) and rosbag2 ``.mcap`` files through the
``rosbags`` library (``pip install 'navbt[bags]'``); no ROS install. With ``--map``, the bag's
``/scan`` and ``/odom`` drive AMCL as a CARMEN log does, from ``--start`` or the first ground
truth pose, and the tracking error against ``/base_pose_ground_truth`` is printed when the bag
has it (navbt's own recorded runs do: ``mission run --record DIR --bag ros2``).
"""

from __future__ import annotations

import argparse

from executive.commands._common import fail, parse_pose


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("bag", help="a ROS 1 .bag, a rosbag2 folder, or a rosbag2 .mcap file")
    p.add_argument("--map", help="map_server YAML: localise the bag's scans on it with AMCL")
    p.add_argument("--start", type=parse_pose, metavar="X,Y,YAW",
                   help="AMCL's initial pose (default: the first ground truth pose)")
    p.add_argument("--scan-topic", default="/scan", help="laser topic (default /scan)")
    p.add_argument("--odom-topic", default="/odom", help="odometry topic (default /odom)")
    p.add_argument("--seed", type=int, default=0, help="AMCL random seed (default 0)")


def run(args: argparse.Namespace) -> int:
    import math

    import numpy as np

    from executive.bags import BagError, BagPlayback, read_bag
    try:
        log = read_bag(args.bag, scan_topic=args.scan_topic, odom_topic=args.odom_topic)
    except BagError as e:
        return fail("bag", str(e))
    times = log.scan_times
    print(f"{args.bag}: {len(log.scans)} scans over {times[-1] - times[0]:.1f} s, "
          f"{len(log.odom_times)} odometry messages")
    for topic, n in sorted(log.topics.items()):
        print(f"  {topic}: {n}")
    if not args.map:
        return 0
    from navcore.clock import SimClock
    from navcore.localization import Amcl
    from navcore.maps import MapError, load_map
    from navcore.types import Pose2D
    try:
        grid = load_map(args.map)
    except MapError as e:
        return fail("bag", str(e))
    if not len(log.odom_times):
        return fail("bag", f"{args.bag}: no {args.odom_topic} messages to localise with")
    start = args.start
    if start is None:
        if not len(log.truth_times):
            return fail("bag", f"{args.bag}: no ground truth in the bag; give --start X,Y,YAW")
        start = Pose2D(*log.truth_poses[0])
    clock = SimClock(float(times[0]))
    pb = BagPlayback(log, clock)
    amcl = Amcl(grid, None, np.random.default_rng(args.seed))
    amcl.set_initial_pose(start, np.diag([0.01, 0.01, 0.003]))
    errors, updates, est = [], 0, start
    for stamp in times:
        clock.sleep_until(float(stamp))
        odom = pb.odometry()
        if odom is None:
            continue
        updates += amcl.update(odom.pose, pb.scan(), pb.mount)
        est = amcl.map_to_odom().compose(odom.pose)
        if len(log.truth_times):
            k = max(0, int(np.searchsorted(log.truth_times, stamp, side="right")) - 1)
            tx, ty, _ = log.truth_poses[k]
            errors.append(math.hypot(est.x - tx, est.y - ty))
    print(f"amcl: {updates} filter updates; last pose ({est.x:.2f}, {est.y:.2f}, "
          f"{est.theta:.2f})")
    if errors:
        e = np.asarray(errors)
        print(f"amcl vs ground truth: median {np.median(e):.3f} m, 95% {np.percentile(e, 95):.3f} m,"
              f" max {e.max():.3f} m")
    return 0
