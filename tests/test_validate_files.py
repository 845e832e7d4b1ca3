"""``mission validate`` checks every file it is given (trees, maps, scenarios, robot configs) and
reports every problem of each, not only the first."""

from __future__ import annotations

from pathlib import Path

from executive.cli import main

SCENARIOS = Path(__file__).resolve().parent / "scenarios"


def test_every_file_and_every_map_field_is_reported(tmp_path: Path, capsys) -> None:
    (tmp_path / "m.pgm").write_bytes(b"P5\n2 2\n255\n\0\0\0\0")
    good_map = tmp_path / "good.yaml"
    good_map.write_text("image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
                        "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    bad_map = tmp_path / "bad_map.yaml"
    bad_map.write_text("image: m.pgm\nresolution: .inf\norigin: [.nan, 0, 0]\nnegate: 0\n"
                       "occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: fuzzy\n")
    bad_config = tmp_path / "robot.yaml"
    bad_config.write_text("amcl:\n  min_particles: 900\n  max_particles: 100\n"
                          "safety:\n  sensor_timeout: .inf\n")
    bad_tree = tmp_path / "tree.yaml"
    bad_tree.write_text("trees:\n  T:\n    Wait: {wait_duration: .nan}\n")
    code = main(["validate", str(bad_map), str(good_map), str(bad_config), str(bad_tree),
                 str(SCENARIOS / "laser_dropout.yaml")])
    out, err = capsys.readouterr()
    assert code == 1
    assert f"{good_map}: ok (map)" in out and "laser_dropout.yaml: ok (scenario)" in out
    assert f"{bad_map}:2: field 'resolution'" in err  # each field, at its line
    assert f"{bad_map}:3: field 'origin'" in err
    assert f"{bad_map}:7: field 'mode'" in err
    assert "min_particles (900) must not exceed max_particles" in err
    assert "'sensor_timeout' must be finite" in err
    assert "tree.yaml:3" in err and "wait_duration" in err
