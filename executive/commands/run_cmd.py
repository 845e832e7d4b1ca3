"""``mission run TREE --config ROBOT.yaml --map MAP.yaml --goal X,Y,YAW [--goal ...]``."""

from __future__ import annotations

import argparse

from executive.commands._common import (add_config_arguments, add_nav2_distro, fail,
                                        load_config_from_args, parse_pose,
                                        print_config_warnings)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("tree", help="tree file (YAML or BT.CPP XML)")
    add_config_arguments(p)
    p.add_argument("--map", required=True, help="map_server YAML")
    p.add_argument("--goal", action="append", type=parse_pose, required=True,
                   metavar="X,Y,YAW", help="a goal in map (repeat for several, visited in turn)")
    p.add_argument("--start", type=parse_pose, metavar="X,Y,YAW",
                   help="start pose in the simulator (default: the most open free cell)")
    p.add_argument("--realtime", action="store_true", help="run at wall-clock speed")
    p.add_argument("--record", metavar="DIR", help="write a run folder to DIR (tick log, "
                                                   "pictures, replay.html, run.mcap)")
    p.add_argument("--bag", choices=("ros1", "ros2", "ros2-mcap"),
                   help="--record: also write the run as a ROS bag (DIR/run.bag or DIR/run_bag; "
                        "needs navbt[bags])")
    p.add_argument("--live", action="store_true",
                   help="serve the run over Foxglove's WebSocket protocol while it runs "
                        "(needs navbt[foxglove]); open ws://HOST:PORT in Foxglove")
    p.add_argument("--host", default="127.0.0.1",
                   help="--live: address to bind (default 127.0.0.1, this machine only)")
    p.add_argument("--port", type=int, default=8765, help="--live: port (default 8765)")
    p.add_argument("--rate", type=float, default=1.0,
                   help="--live: simulated seconds per wall second (default 1: real time; "
                        "0: as fast as it runs)")
    p.add_argument("--seed", type=int, default=0, help="simulator random seed (default 0)")
    p.add_argument("--time-limit", type=float, default=600.0, help="simulated seconds (600)")
    add_nav2_distro(p)
    hw = p.add_mutually_exclusive_group()
    hw.add_argument("--hw", action="store_true",
                    help="drive the real robot of the config's robot.devices instead of the "
                         "simulator")
    hw.add_argument("--hw-emulated", action="store_true",
                    help="run through the real Kobuki and URG-04LX drivers and byte streams, "
                         "their device emulators driven by the simulator (deterministic)")


def run(args: argparse.Namespace) -> int:
    import os
    import sys

    from executive.api import ConfigError, TreeLoadError, WiringError, load_tree, open_mission
    from executive.progress import Progress, progress_callback
    from executive.recorder import Recorder
    from navcore.maps import MapError, load_map
    try:
        config = load_config_from_args(args)
    except ConfigError as e:
        return fail("run", str(e))
    print_config_warnings(config)
    try:
        grid = load_map(args.map)
    except MapError as e:
        return fail("run", str(e))
    for i, g in enumerate(args.goal):
        if grid.world_to_map(g.x, g.y) is None:
            return fail("run", f"--goal {g.x:g},{g.y:g}: outside the map {args.map}")
    live = []
    if args.live:
        from executive.foxglove_out import FoxgloveSink, FoxgloveUnavailable
        if args.rate < 0:
            return fail("run", f"--rate {args.rate:g}: must be >= 0")
        try:
            live = [FoxgloveSink(live=True, host=args.host, port=args.port,
                                 rate=args.rate or None, grid=grid)]
        except FoxgloveUnavailable as e:
            return fail("run", f"--live: {e}")
        except RuntimeError as e:   # the port is taken, the address is not ours, ...
            return fail("run", f"--live: cannot serve on {args.host}:{args.port} ({e})")
        print(f"live: ws://{args.host}:{live[0].port} (Foxglove: open a connection to it)",
              file=sys.stderr)
    recorder = Recorder(None, sinks=live)
    if args.record:
        from executive.run_folder import open_recorder
        from executive.bags import BagError
        try:
            recorder = open_recorder(args.record, grid=grid, sinks=live, bag=args.bag)
        except BagError as e:
            return fail("run", f"--bag: {e}")
    elif args.bag:
        return fail("run", "--bag needs --record DIR (the bag goes into the run folder)")
    try:
        tree = args.tree
        if args.nav2_distro:  # the semantics of that Nav2 distribution (docs/trees.md)
            tree = load_tree(args.tree, config, nav2_distro=args.nav2_distro)
        # on hardware the robot is where it is: AMCL starts from --start or amcl.initial_pose_*
        nav = open_mission(tree, config, grid, args.start, seed=args.seed,
                           realtime=args.realtime, recorder=recorder,
                           hardware="emulated" if args.hw_emulated else args.hw)
    except (TreeLoadError, WiringError) as e:
        recorder.close()
        return fail("run", str(e))
    progress = Progress()
    nav.follow_waypoints(args.goal)
    result = nav.run(args.time_limit, on_tick=progress_callback(progress, args.time_limit,
                                                                goals=args.goal))
    progress.done()
    if args.record:
        from executive.run_folder import finish
        finish(args.record, nav.executive, result, grid, config.footprint(),
               extra={"tree": args.tree, "map": os.path.abspath(args.map)})
    nav.close()
    recorder.close()
    rec = ", ".join(result.recoveries) or "none"
    print(f"{result.outcome}: {result.goals_reached}/{result.goals_total} goals in "
          f"{result.sim_time:.1f} s, {result.distance:.1f} m, recoveries: {rec}, "
          f"collisions: {result.collisions}" + (f" ({result.reason})" if result.reason else ""))
    if args.record:
        print(args.record)
    return 0 if result.succeeded else 1
