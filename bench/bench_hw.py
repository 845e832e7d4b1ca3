"""Decode throughput of the hardware codecs: whole scans (or frames) per second, bytes to message.

Each laser figure covers framing, every checksum, value decoding and the LaserScan with its
header; the devices deliver 10 (URG-04LX) and 75 (LMS 2xx) scans per second.
Usage: python bench/bench_hw.py [--json]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from hw.drivers import kobuki_codec as kc
from hw.drivers import lms2xx_codec as lc
from hw.drivers import scip
from hw.drivers import vectornav_codec as vc
from hw.drivers.lines import LineDecoder


def rate(fn, seconds: float = 1.0) -> float:
    """Calls of ``fn`` per second, after a warm-up call (numba compilation)."""
    fn()
    n, t0 = 0, time.perf_counter()
    while True:
        fn()
        n += 1
        dt = time.perf_counter() - t0
        if dt >= seconds:
            return n / dt


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print a JSON line of the figures last")
    ap.add_argument("--seconds", type=float, default=1.0, help="time per figure")
    a = ap.parse_args()
    rng = np.random.default_rng(0)

    urg = scip.frame_reply(b"MD0044072501000", b"99",
                           scip.encode_scan_lines(1234, rng.integers(20, 5600, 682), 3))
    req = scip.ScanRequest.parse("MD0044072501000")
    geom = scip.UrgGeometry()
    dec = scip.ScipDecoder()

    def urg_scan() -> None:
        (rep,) = dec.feed(urg)
        scip.to_laser_scan(scip.parse_scan(rep, req), geom, 0.0)

    lms = lc.encode_scan(rng.integers(0, 8000, 361), mm=False)
    var = lc.Variant(180, 0.5)
    ldec = lc.TelegramDecoder()

    def lms_scan() -> None:
        (t,) = ldec.feed(lms)
        lc.to_laser_scan(lc.parse_scan(t, 361), var, 0.0)

    kob = kc.Feedback(kc.BasicSensors(1, left_encoder=5, right_encoder=6), 100, 0,
                      {kc.DOCK_IR: bytes(3), kc.CLIFF: bytes(6), kc.CURRENT: bytes(2),
                       kc.GPIO: bytes(16)}).pack()
    kdec = kc.FrameDecoder()

    def kobuki_frame() -> None:
        (p,) = kdec.feed(kob)
        kc.parse_feedback(p)

    vn = vc.Ymr((1.0, 2.0, 3.0), (0.1, 0.2, 0.3), (0.0, 0.0, -9.8), (0.0, 0.0, 0.1)).line()
    vdec = LineDecoder()

    def vn_sentence() -> None:
        (line,) = vdec.feed(vn)
        vc.parse_ymr(line)

    figures = {
        "scip_scans_per_s": rate(urg_scan, a.seconds),
        "lms_scans_per_s": rate(lms_scan, a.seconds),
        "kobuki_frames_per_s": rate(kobuki_frame, a.seconds),
        "vnymr_sentences_per_s": rate(vn_sentence, a.seconds),
    }
    print(f"URG-04LX SCIP 2.0 MD scan, 682 steps, {len(urg)} bytes: "
          f"{figures['scip_scans_per_s']:.0f} scans/s (device: 10/s)")
    print(f"SICK LMS 291 0xB0 scan, 361 values, {len(lms)} bytes: "
          f"{figures['lms_scans_per_s']:.0f} scans/s (device: 75/s)")
    print(f"Kobuki feedback frame, {len(kob)} bytes: {figures['kobuki_frames_per_s']:.0f} frames/s "
          f"(device: 50/s)")
    print(f"VectorNav $VNYMR, {len(vn)} bytes: {figures['vnymr_sentences_per_s']:.0f} sentences/s")
    if a.json:
        print(json.dumps({k: round(v, 1) for k, v in figures.items()}))


if __name__ == "__main__":
    main()
