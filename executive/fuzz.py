"""Mutated user files and device bytes for the robustness bench and the fuzz tests.

``AREAS`` names every loader a user file goes through; ``seed_files(area)`` gives valid examples,
``mutate(data, rng)`` breaks them the ways the issue-18 fuzz campaign did (flipped and inserted
bytes, control characters, invalid UTF-8, 400-digit numbers, NaN/inf, bad tags, aliases and
alias bombs, deep nesting, unknown encodings, entity declarations, device paths, truncation),
and ``load(area, data, folder)`` runs the loader and says ``"ok"``, ``"clean"`` (the layer's
own error) or ``"crash: <type>: <message>"``. ``CODECS`` does the same for the byte decoders
of the drivers. All randomness comes from the ``numpy.random.Generator`` passed in.
"""

from __future__ import annotations

import os
import struct
import zlib
from typing import Callable

import numpy as np

AREAS = ("tree_yaml", "tree_xml", "config", "map_yaml", "map_pgm8", "map_pgm16", "map_png8",
         "map_png16", "scenario", "set_parameters")

_HOSTILE = [b"9" * 400, b"-" + b"9" * 30, b".nan", b".inf", b"-.inf", b"1.0e+999", b"nan",
            b"inf", b"!!float x", b"!!int 1.5", b"!!binary ***", b"!!timestamp 2020-99-99",
            b"!!python/object/apply:os.system [true]", b"&a [1, *a]", b"*nowhere", b"&b x",
            b"*b", b"\x00", b"\x01", b"\x7f", b"\xff\xfe", b"\xc3", b"\xed\xa0\x80", b"\t",
            b"[" * 400, b"{" * 400, b"- " * 200, b"\n" + b"  " * 300 + b"a: 1",
            b'<?xml version="1.0" encoding="klingon"?>', b'<!DOCTYPE r [<!ENTITY a "aaaa">]>',
            b"&a;", b"<" * 300, b"/dev/zero", b"/dev/urandom", b"include: [/dev/zero]",
            b"0", b"-1", b"1e300", b"1e-300", b"0x7fffffffffffffffff", b"{}", b"[]", b"null",
            b"~", b"true", b"---", b"...", b"? ", b": ", b"'", b'"', b"#", b"%YAML 1.1",
            b"4294967296", b"2147483648", b"-2147483649"]


def _bomb() -> bytes:
    lines = [b"a0: &a0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]"]
    for i in range(1, 7):
        lines.append(f"a{i}: &a{i} [".encode() + b", ".join([f"*a{i - 1}".encode()] * 10) + b"]")
    return b"\n".join(lines) + b"\n"


def mutate(data: bytes, rng: np.random.Generator) -> bytes:
    """``data`` with one to four random damages."""
    out = bytearray(data)
    for _ in range(int(rng.integers(1, 5))):
        op = int(rng.integers(0, 9))
        pos = int(rng.integers(0, len(out) + 1))
        if op == 0 and out:                                   # flip a byte
            out[min(pos, len(out) - 1)] = int(rng.integers(0, 256))
        elif op == 1:                                         # insert random bytes
            out[pos:pos] = rng.integers(0, 256, int(rng.integers(1, 9)), dtype=np.uint8).tobytes()
        elif op in (2, 3):                                    # insert a hostile token
            out[pos:pos] = _HOSTILE[int(rng.integers(0, len(_HOSTILE)))]
        elif op == 4 and out:                                 # delete a span
            del out[pos:pos + int(rng.integers(1, 40))]
        elif op == 5 and out:                                 # duplicate a span
            end = min(len(out), pos + int(rng.integers(1, 80)))
            out[pos:pos] = out[pos:end]
        elif op == 6:                                         # replace a number by a hostile one
            digits = [i for i, b in enumerate(out) if 48 <= b <= 57]
            if digits:
                i = digits[int(rng.integers(0, len(digits)))]
                out[i:i + 1] = _HOSTILE[int(rng.integers(0, 8))]
        elif op == 7:                                         # truncate
            del out[pos:]
        elif op == 8 and rng.random() < 0.2:                  # an alias bomb at the top
            out[0:0] = _bomb()
    return bytes(out)


# ----------------------------------------------------------------------------- seed files

def _png(rows: np.ndarray, bit_depth: int, colour_type: int) -> bytes:
    def chunk(tag: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + tag + body + struct.pack(
            ">I", zlib.crc32(tag + body) & 0xFFFFFFFF)
    h, w = rows.shape[:2]
    raw = b"".join(b"\0" + r.astype(">u2" if bit_depth == 16 else np.uint8).tobytes()
                   for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bit_depth,
                                                               colour_type, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


_MAP_YAML = (b"image: m.{ext}\nresolution: 0.05\norigin: [-1.0, -2.0, 0.0]\nnegate: 0\n"
             b"occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n")


def _grey(n: int = 12, top: int = 255) -> np.ndarray:
    return (np.arange(n * n).reshape(n, n) * 7 % (top + 1)).astype(np.int64)


def seed_files(area: str) -> list[bytes]:
    """Valid examples of a user file of ``area`` (the shipped trees, the bundled config...)."""
    from executive.config import DEFAULT_CONFIG
    from executive.tree_loader import TREES_DIR
    if area == "tree_yaml":
        return [p.read_bytes() for p in sorted(TREES_DIR.glob("*.yaml"))]
    if area == "tree_xml":
        return [b'<?xml version="1.0" encoding="UTF-8"?>\n<root BTCPP_format="4" '
                b'main_tree_to_execute="T">\n  <BehaviorTree ID="T">\n    <RecoveryNode '
                b'number_of_retries="2">\n      <Sequence>\n        <Wait wait_duration="1.5"/>\n'
                b'        <Spin spin_dist="1.57"/>\n        <BackUp backup_dist="0.3" '
                b'backup_speed="0.05"/>\n      </Sequence>\n      <ClearEntireCostmap '
                b'service_name="local_costmap/clear_entirely_local_costmap"/>\n    '
                b'</RecoveryNode>\n  </BehaviorTree>\n</root>\n']
    if area == "config":
        return [DEFAULT_CONFIG.read_bytes()]
    if area in ("map_yaml", "map_pgm8"):
        return [_MAP_YAML.replace(b"{ext}", b"pgm")] if area == "map_yaml" else [
            b"P5\n# navbt\n12 12\n255\n" + _grey().astype(np.uint8).tobytes()]
    if area == "map_pgm16":
        return [b"P5\n12 12\n65535\n" + (_grey(top=65535) * 251).astype(">u2").tobytes()]
    if area == "map_png8":
        return [_png(_grey(), 8, 0), _png(np.stack([_grey(), _grey()], 2), 8, 4)]
    if area == "map_png16":
        return [_png(_grey() * 257, 16, 0)]
    if area == "scenario":
        from pathlib import Path
        folder = Path(__file__).resolve().parent.parent / "tests" / "scenarios"
        return [p.read_bytes() for p in sorted(folder.glob("*.yaml"))][:6] or [
            b"name: s\nmap: {resolution: 0.1, ascii: \"#####\\n#...#\\n#####\"}\n"
            b"start: [0.15, 0.15, 0]\ngoals: [[0.35, 0.15, 0]]\n"]
    if area == "set_parameters":
        return [b"max_vel_x: 0.3; sensor_timeout: 0.2", b"stall_speed: 0.05",
                b"max_vel_theta: 1.0; stop_on_bumper: true"]
    raise ValueError(f"fuzz: unknown area {area!r}")


# ----------------------------------------------------------------------------- loaders

def load(area: str, data: bytes, folder: str) -> str:
    """Run the loader of ``area`` on ``data`` (files written into ``folder``)."""
    from executive.config import ConfigError, SAFETY_PARAMS, load_config
    from executive.tree_loader import TreeLoadError, load_tree_file
    from executive.scenario import ScenarioError, load_scenario
    from navcore.maps import MapError, load_map
    from navcore.params import Parameters
    from behaviors.decorators.set_parameters import parse_values

    def write(name: str, body: bytes) -> str:
        path = os.path.join(folder, name)
        with open(path, "wb") as fh:
            fh.write(body)
        return path

    clean: tuple[type[BaseException], ...]
    if area in ("tree_yaml", "tree_xml"):
        path = write("t.yaml" if area == "tree_yaml" else "t.xml", data)
        call, clean = (lambda: load_tree_file(path, namespace="/fuzz")), (TreeLoadError,)
    elif area == "config":
        path = write("robot.yaml", data)
        call, clean = (lambda: load_config(path)), (ConfigError,)
    elif area == "scenario":
        path = write("s.yaml", data)
        call, clean = (lambda: load_scenario(path)), (ScenarioError,)
    elif area.startswith("map_"):
        ext = b"png" if "png" in area else b"pgm"
        if area == "map_yaml":
            write("m.pgm", seed_files("map_pgm8")[0])
            path = write("m.yaml", data)
        else:
            write(f"m.{ext.decode()}", data)
            path = write("m.yaml", _MAP_YAML.replace(b"{ext}", ext))
        call, clean = (lambda: load_map(path)), (MapError,)
    elif area == "set_parameters":
        def call() -> None:
            text = data.decode("utf-8", errors="replace")
            Parameters(SAFETY_PARAMS).set(parse_values(text))
        clean = (ValueError,)    # parse_values' and ParameterError (a ValueError)
    else:
        raise ValueError(f"fuzz: unknown area {area!r}")
    try:
        call()
    except clean:
        return "clean"
    except Exception as e:  # noqa: BLE001 - anything else is what we are looking for
        return f"crash: {type(e).__name__}: {str(e)[:200]}"
    return "ok"


# ----------------------------------------------------------------------------- codecs

_refused = [0]   # frames the codec refused during the current feed_codec call


def _codecs() -> dict[str, tuple[Callable[[], Callable[[bytes], None]], tuple, bytes]]:
    """name -> (make a decoder feeding bytes through framing and parsing, its error types,
    a valid stream to mutate)."""
    from hw.drivers import arduino_codec as ac
    from hw.drivers import kobuki_codec as kc
    from hw.drivers import lms2xx_codec as lc
    from hw.drivers import razor_codec as rc
    from hw.drivers import scip
    from hw.drivers import vectornav_codec as vc
    from hw.drivers.lines import LineDecoder

    def lines(sep: bytes, parse: Callable[[str], object]) -> Callable[[], Callable[[bytes], None]]:
        def make() -> Callable[[bytes], None]:
            dec = LineDecoder(sep)

            def feed(chunk: bytes) -> None:
                before = dec.errors
                lines_ = dec.feed(chunk)
                _refused[0] += dec.errors - before     # frames the framing itself dropped
                for line in lines_:
                    try:
                        parse(line)
                    except ValueError:
                        _refused[0] += 1
            return feed
        return make

    def kobuki() -> Callable[[bytes], None]:
        dec = kc.FrameDecoder()

        def feed(chunk: bytes) -> None:
            before = dec.errors
            payloads = dec.feed(chunk)
            _refused[0] += dec.errors - before
            for payload in payloads:
                try:
                    kc.parse_feedback(payload)
                except kc.KobukiError:
                    _refused[0] += 1
        return feed

    def lms() -> Callable[[bytes], None]:
        dec = lc.TelegramDecoder()

        def feed(chunk: bytes) -> None:
            before = dec.errors + dec.crc_failures
            items = dec.feed(chunk)
            _refused[0] += dec.errors + dec.crc_failures - before
            for t in items:
                if isinstance(t, lc.Telegram):
                    try:
                        lc.parse_scan(t)
                    except lc.LmsError:
                        _refused[0] += 1
        return feed

    def urg() -> Callable[[bytes], None]:
        dec = scip.ScipDecoder()

        def feed(chunk: bytes) -> None:
            before = getattr(dec, "errors", 0)
            replies = dec.feed(chunk)
            _refused[0] += getattr(dec, "errors", 0) - before
            for reply in replies:
                try:
                    scip.parse_scan(reply)
                except scip.ScipError:
                    _refused[0] += 1
        return feed

    def razor_parse(line: str) -> object:
        return rc.to_imu(rc.parse_line(line), 0.0)

    kobuki_seed = kc.frame(kc.sub_payload(1, bytes(range(15))))
    lms_seed = lc.encode_scan(np.arange(181, dtype=np.int64) * 10, mm=True)
    return {
        "arduino": (lines(b"\r", ac.parse_encoders), (ac.ArduinoError,), b"1024 -2048\r" * 4),
        "razor": (lines(b"\n", razor_parse), (rc.RazorError,),
                  b"#YPRAG=10.0,-2.5,3.1,0.10,0.20,9.80,0.01,0.02,0.03\r\n" * 4),
        "vectornav": (lines(b"\n", vc.parse_ymr), (vc.VnError,),
                      vc.sentence("VNYMR,+010.0,-002.5,+003.1,+0.1,+0.2,+0.3,+00.1,+00.2,"
                                  "-09.8,+0.01,+0.02,+0.03") * 4),
        "kobuki": (kobuki, (kc.KobukiError,), kobuki_seed * 4),
        "lms2xx": (lms, (lc.LmsError,), lms_seed * 2),
        "urg04lx": (urg, (scip.ScipError,), scip.request("MD", "0000076801000") * 4),
    }


CODECS = ("arduino", "razor", "vectornav", "kobuki", "lms2xx", "urg04lx")


def feed_codec(name: str, total_bytes: int, rng: np.random.Generator
               ) -> tuple[int, int, int, str]:
    """Feed ``total_bytes`` of random and mutated bytes through codec ``name`` in random chunks;
    returns (bytes fed, chunks fed, frames the codec refused with its own error, ``"clean"`` or
    ``"crash: ..."``)."""
    make, errors, seed = _codecs()[name]
    feed = make()
    fed = chunks = 0
    _refused[0] = 0
    try:
        while fed < total_bytes:
            if rng.random() < 0.5:
                chunk = mutate(seed, rng)
            else:
                chunk = rng.integers(0, 256, int(rng.integers(1, 256)), dtype=np.uint8).tobytes()
            for i in range(0, len(chunk), 61):
                feed(chunk[i:i + 61])
            fed += len(chunk)
            chunks += 1
    except errors:
        return fed, chunks, _refused[0] + 1, "clean"
    except Exception as e:  # noqa: BLE001
        return fed, chunks, _refused[0], f"crash: {type(e).__name__}: {str(e)[:200]}"
    return fed, chunks, _refused[0], "clean"
