"""Run one emulated device on a pty or a TCP port until interrupted, for manual tests:

    python -m hw.emulators urg04lx --pty           # prints /dev/pts/N
    python -m hw.emulators kobuki --tcp 5000 --corrupt 0.001
"""

from __future__ import annotations

import argparse
import sys
import threading

from hw.emulators import emulator_types
from hw.emulators.link import Faults, Link
from navcore.clock import WallClock


def main(argv: list[str] | None = None) -> int:
    types = emulator_types()
    ap = argparse.ArgumentParser(prog="python -m hw.emulators", description=__doc__.splitlines()[0])
    ap.add_argument("device", choices=sorted(types))
    where = ap.add_mutually_exclusive_group()
    where.add_argument("--pty", action="store_true", help="serve on a pty pair (default)")
    where.add_argument("--tcp", type=int, metavar="PORT", help="serve on 127.0.0.1:PORT")
    for name in ("corrupt", "drop", "garbage", "delay", "host_corrupt", "host_drop"):
        ap.add_argument(f"--{name}", type=float, default=0.0)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args(argv)
    faults = Faults(a.corrupt, a.drop, a.garbage, a.delay, a.host_corrupt, a.host_drop)
    link = Link(types[a.device](WallClock()), faults, a.seed)
    if a.tcp is not None:
        from hw.emulators.tcp_port import TcpDevice
        server = TcpDevice(link, port=a.tcp)
        name = server.url
    else:
        from hw.emulators.pty_port import PtyDevice
        server = PtyDevice(link)
        name = server.port_name
    with server:
        print(f"{a.device} emulator on {name} (Ctrl-C to stop)", flush=True)
        try:
            threading.Event().wait()
        except KeyboardInterrupt:
            pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
