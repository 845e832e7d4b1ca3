"""map_server format: every real map loads with the cell counts computed independently from its image."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from navcore.maps import MapError, OccupancyGrid, load_map, save_map
from navcore.types import Pose2D
from tests.conftest import REAL_MAPS


def _independent_counts(pgm: Path, occ_th: float, free_th: float) -> dict[str, int]:
    """Count cells straight from the P5 bytes with Pillow, not with our PGM reader."""
    from PIL import Image
    pix = np.asarray(Image.open(pgm), dtype=np.float64)
    occ = (255.0 - pix) / 255.0
    n_occ = int(np.count_nonzero(occ > occ_th))
    n_free = int(np.count_nonzero(occ < free_th))
    return {"occupied": n_occ, "free": n_free, "unknown": pix.size - n_occ - n_free}


@pytest.mark.parametrize("name", sorted(REAL_MAPS))
def test_real_map_loads_with_expected_counts(shared_data: Path, name: str) -> None:
    yaml_path = shared_data / "maps" / REAL_MAPS[name]
    grid = load_map(yaml_path)
    meta = yaml.safe_load(yaml_path.read_text())
    pgm = yaml_path.parent / Path(meta["image"]).name
    assert grid.counts() == _independent_counts(pgm, meta["occupied_thresh"], meta["free_thresh"])
    assert grid.resolution == pytest.approx(meta["resolution"])
    assert (grid.origin.x, grid.origin.y) == pytest.approx(tuple(meta["origin"][:2]))


def test_willow_has_many_grey_levels_that_thresholds_split(shared_data: Path) -> None:
    grid = load_map(shared_data / "maps" / REAL_MAPS["willow_garage"])
    assert (grid.width, grid.height) == (1165, 945)
    c = grid.counts()
    assert c["occupied"] + c["free"] + c["unknown"] == 1165 * 945
    assert 0.005 < c["occupied"] / grid.data.size < 0.03


def test_absolute_image_path_falls_back_beside_yaml(shared_data: Path) -> None:
    grid = load_map(shared_data / "maps" / REAL_MAPS["robotis_office"])
    assert (grid.width, grid.height) == (384, 384)


def test_rows_are_flipped_and_origin_is_lower_left(tmp_path: Path) -> None:
    img = np.full((4, 3), 254, np.uint8)
    img[0, 0] = 0  # top-left pixel: max-y row
    (tmp_path / "m.pgm").write_bytes(b"P5\n3 4\n255\n" + img.tobytes())
    (tmp_path / "m.yaml").write_text("image: m.pgm\nresolution: 0.5\norigin: [1.0, 2.0, 0.0]\n"
                                     "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n")
    g = load_map(tmp_path / "m.yaml")
    assert g.data[3, 0] == 100 and g.data[0, 0] == 0
    assert g.world_to_map(1.1, 3.9) == (0, 3)
    assert g.map_to_world(0, 3) == pytest.approx((1.25, 3.75))
    assert g.world_to_map(0.99, 2.5) is None


def test_origin_yaw_rotates_the_grid() -> None:
    g = OccupancyGrid(np.zeros((10, 10)), 1.0, Pose2D(0.0, 0.0, math.pi / 2))
    assert g.world_to_map(-2.5, 1.5) == (1, 2)
    assert g.map_to_world(1, 2) == pytest.approx((-2.5, 1.5))


@pytest.mark.parametrize("mode,expected", [("trinary", [100, -1, 0]), ("raw", [10, 128, 250]),
                                           ("scale", [100, 53, 0])])
def test_modes(tmp_path: Path, mode: str, expected: list[int]) -> None:
    (tmp_path / "m.pgm").write_text("P2\n3 1\n255\n10 128 250\n")
    (tmp_path / "m.yaml").write_text(f"image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n"
                                     f"negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
                                     f"mode: {mode}\n")
    g = load_map(tmp_path / "m.yaml")
    if mode == "scale":
        occ = (255 - 128) / 255
        expected[1] = int(1 + 98 * (occ - 0.196) / (0.65 - 0.196))
    assert g.data[0].tolist() == expected


def test_negate_inverts(tmp_path: Path) -> None:
    (tmp_path / "m.pgm").write_text("P2\n2 1\n255\n0 255\n")
    (tmp_path / "m.yaml").write_text("image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n"
                                     "negate: 1\noccupied_thresh: 0.65\nfree_thresh: 0.196\n")
    assert load_map(tmp_path / "m.yaml").data[0].tolist() == [0, 100]


@pytest.mark.parametrize("fmt", ["pgm", "pgm-ascii", "png"])
def test_save_load_round_trip(tmp_path: Path, fmt: str) -> None:
    rng = np.random.default_rng(3)
    data = rng.choice(np.array([-1, 0, 100], np.int16), size=(17, 23))
    g = OccupancyGrid(data, 0.05, Pose2D(-1.5, 2.25, 0.0))
    save_map(g, tmp_path / "out.yaml", fmt)
    back = load_map(tmp_path / "out.yaml")
    np.testing.assert_array_equal(back.data, data)
    assert back.origin == g.origin and back.resolution == 0.05


def _write_yaml(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "bad.yaml"
    p.write_text(text)
    return p


GOOD = "image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"


@pytest.mark.parametrize("text,needle", [
    (GOOD.replace("resolution: 0.1", "resolution: fast"), "'resolution'"),
    (GOOD.replace("origin: [0, 0, 0]", "origin: [0, 0]"), "'origin'"),
    (GOOD.replace("negate: 0\n", ""), "missing field 'negate'"),
    (GOOD + "mode: fuzzy\n", "'mode'"),
    (GOOD.replace("image: m.pgm", "image: nothere.pgm"), "'image'"),
    (GOOD.replace("free_thresh: 0.196", "free_thresh: 0.9"), "free_thresh"),
    ("image: [unclosed\n", "not valid YAML"),
])
def test_bad_yaml_field_is_named(tmp_path: Path, text: str, needle: str) -> None:
    (tmp_path / "m.pgm").write_text("P2\n1 1\n255\n0\n")
    p = _write_yaml(tmp_path, text)
    with pytest.raises(MapError) as e:
        load_map(p)
    assert needle in str(e.value) and str(p) in str(e.value)


@pytest.mark.parametrize("body,needle", [(b"P6\n1 1\n255\n\0\0\0", "magic"),
                                         (b"P5\n4 4\n255\n\0\0", "truncated"),
                                         (b"P5\n4 x\n255\n", "not integers")])
def test_bad_image_header_is_named(tmp_path: Path, body: bytes, needle: str) -> None:
    (tmp_path / "m.pgm").write_bytes(body)
    p = _write_yaml(tmp_path, GOOD)
    with pytest.raises(MapError) as e:
        load_map(p)
    assert needle in str(e.value) and "m.pgm" in str(e.value)


def test_missing_map_file(tmp_path: Path) -> None:
    with pytest.raises(MapError, match="not found"):
        load_map(tmp_path / "none.yaml")


# ---------------------------------------------------------------- map_server's pixel rules
# ROS map_server (image_loader.cpp over SDL_image): SDL_image strips 16-bit samples to the high
# byte (png_set_strip_16), expands grey+alpha to RGBA and keeps palette indices; map_server then
# averages the channels (alpha included only in trinary mode), negates, and thresholds
# occ = (255 - avg) / 255. The PNGs below are encoded here byte by byte, not by Pillow.

def _png(rows: list[list[int]] | list[list[tuple[int, ...]]], bit_depth: int, colour_type: int,
         palette: bytes = b"", trns: bytes = b"") -> bytes:
    import struct
    import zlib

    def chunk(tag: bytes, data: bytes) -> bytes:
        return (struct.pack(">I", len(data)) + tag + data
                + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))
    h, w = len(rows), len(rows[0])
    fmt = ">H" if bit_depth == 16 else ">B"
    raw = b""
    for row in rows:
        raw += b"\0" + b"".join(struct.pack(fmt, v) for px in row
                                for v in (px if isinstance(px, tuple) else (px,)))
    out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bit_depth,
                                                              colour_type, 0, 0, 0))
    if palette:
        out += chunk(b"PLTE", palette)
    if trns:
        out += chunk(b"tRNS", trns)
    return out + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def _map_server_cell(channels: tuple[int, ...], has_alpha: bool, mode: str, negate: bool,
                     occ_th: float = 0.65, free_th: float = 0.196) -> int:
    """image_loader.cpp's per-pixel rule on an 8-bit surface pixel (a plain transcription)."""
    n = len(channels)
    avg_channels = n if (mode == "trinary" or not has_alpha) else n - 1
    color_avg = sum(channels[:avg_channels]) / float(avg_channels)
    alpha = channels[-1] if n > 1 else 1
    if negate:
        color_avg = 255 - color_avg
    if mode == "raw":
        return int(color_avg)
    occ = (255 - color_avg) / 255.0
    if occ > occ_th:
        return 100
    if occ < free_th:
        return 0
    if mode == "trinary" or alpha < 1.0:
        return -1
    return int(1 + 98 * (occ - free_th) / (occ_th - free_th))


def _write_png_map(tmp_path: Path, png: bytes, mode: str, negate: bool) -> Path:
    (tmp_path / "m.png").write_bytes(png)
    p = tmp_path / "m.yaml"
    p.write_text(f"image: m.png\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: {int(negate)}\n"
                 f"occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: {mode}\n")
    return p


# every high byte, with low bytes that would round differently under scaling
_GREY16 = [[v * 256 + lo for v in range(0, 256, 5)] for lo in (0, 128, 255)]


@pytest.mark.parametrize("mode", ["trinary", "scale", "raw"])
@pytest.mark.parametrize("negate", [False, True])
def test_16_bit_grey_png_reads_as_map_server(tmp_path: Path, mode: str, negate: bool) -> None:
    grid = load_map(_write_png_map(tmp_path, _png(_GREY16, 16, 0), mode, negate))
    want = [[_map_server_cell((v >> 8,), False, mode, negate) for v in row] for row in _GREY16]
    assert grid.data[::-1].tolist() == want
    if mode == "trinary" and not negate:  # 0xffff is free, 0x0000 occupied: nothing vanishes
        assert grid.data[-1, 0] == 100 and grid.data[-1, -1] == 0


@pytest.mark.parametrize("mode", ["trinary", "scale", "raw"])
def test_grey_alpha_png_averages_as_map_server(tmp_path: Path, mode: str) -> None:
    rows = [[(g, a) for g in (0, 60, 120, 180, 254)] for a in (0, 128, 255)]
    for depth in (8, 16):
        px = rows if depth == 8 else [[(g * 257, a * 257) for g, a in r] for r in rows]
        grid = load_map(_write_png_map(tmp_path, _png(px, depth, 4), mode, False))
        want = [[_map_server_cell((g, g, g, a), True, mode, False) for g, a in r] for r in rows]
        assert grid.data[::-1].tolist() == want, depth


def test_palette_png_reads_the_index_as_map_server(tmp_path: Path) -> None:
    palette = bytes([255, 0, 0, 0, 255, 0, 0, 0, 255])  # red, green, blue: averages all 85
    rows = [[0, 1, 2]]
    grid = load_map(_write_png_map(tmp_path, _png(rows, 8, 3, palette), "raw", False))
    assert grid.data.tolist() == [[0, 1, 2]]


def test_16_bit_rgba_png_strips_to_high_byte(tmp_path: Path) -> None:
    rows = [[(0xFF00, 0x0000, 0x1234, 0xFFFF), (0x0101, 0x0202, 0x0303, 0x0000)]]
    grid = load_map(_write_png_map(tmp_path, _png(rows, 16, 6), "raw", False))
    want = [[_map_server_cell((0xFF, 0x00, 0x12, 0xFF), True, "raw", False),
             _map_server_cell((1, 2, 3, 0), True, "raw", False)]]
    assert grid.data.tolist() == want


def test_16_bit_pgm_scales_by_maxval(tmp_path: Path) -> None:
    import struct
    vals = [0, 1000, 30000, 65535]
    (tmp_path / "m.pgm").write_bytes(b"P5\n4 1\n65535\n" + b"".join(struct.pack(">H", v)
                                                                    for v in vals))
    p = tmp_path / "m.yaml"
    p.write_text("image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
                 "occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: raw\n")
    assert load_map(p).data.tolist() == [[int(v * 255 / 65535) for v in vals]]


@pytest.mark.parametrize("field,value,needle", [
    ("origin", "[.nan, 0, 0]", "'origin' must be finite"),
    ("origin", "[0, .inf, 0]", "'origin' must be finite"),
    ("origin", "[0, 0, -.inf]", "'origin' must be finite"),
    ("resolution", ".inf", "'resolution'"),
    ("resolution", "1e-300", "'resolution' must be in"),
    ("resolution", ".nan", "'resolution'"),
    ("occupied_thresh", ".nan", "'occupied_thresh'"),
])
def test_non_finite_and_absurd_fields_are_refused(tmp_path: Path, field: str, value: str,
                                                  needle: str) -> None:
    (tmp_path / "m.pgm").write_text("P2\n1 1\n255\n0\n")
    text = GOOD.replace("resolution: 0.1", "resolution: 0.1").splitlines()
    text = [f"{field}: {value}" if line.startswith(field + ":") else line for line in text]
    p = _write_yaml(tmp_path, "\n".join(text) + "\n")
    with pytest.raises(MapError, match=needle):
        load_map(p)


def test_png_bomb_is_refused_before_decoding(tmp_path: Path) -> None:
    import struct
    import zlib
    # IHDR claims 8000 x 8000 grey pixels (below Pillow's own bomb limit); a few bytes of IDAT
    png = (b"\x89PNG\r\n\x1a\n" + struct.pack(">I", 13) + b"IHDR"
           + struct.pack(">IIBBBBB", 8000, 8000, 8, 0, 0, 0, 0))
    png += struct.pack(">I", zlib.crc32(png[12:]) & 0xFFFFFFFF)
    idat = zlib.compress(b"\0" * 1000)
    png += struct.pack(">I", len(idat)) + b"IDAT" + idat + struct.pack(
        ">I", zlib.crc32(b"IDAT" + idat) & 0xFFFFFFFF)
    with pytest.raises(MapError, match="larger than the limit"):
        load_map(_write_png_map(tmp_path, png, "trinary", False))
    (tmp_path / "m.pgm").write_bytes(b"P5\n100000 100000\n255\n\0")
    p = _write_yaml(tmp_path, GOOD)
    with pytest.raises(MapError, match="larger than the limit"):
        load_map(p)
