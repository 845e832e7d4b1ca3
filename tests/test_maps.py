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
