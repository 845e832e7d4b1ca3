"""The one reading path for user files: every bad input becomes the caller's error with file:line."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from executive.config import ConfigError, load_config
from executive.scenario import ScenarioError, load_scenario
from executive.tree_loader import TreeLoadError, load_tree_file
from navcore.maps import MapError, load_map
from navcore.safe_read import (MAX_TEXT_BYTES, MAX_YAML_DEPTH, ReadError, load_yaml, parse_yaml,
                               read_bytes)


def _bomb(levels: int = 6) -> str:
    lines = ["a0: &a0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]"]
    for i in range(1, levels):
        lines.append(f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("text,line,needle", [
    ("a: 1\nb: [1, \x00]\n", 2, "control character U+0000"),
    ("a: 1\n\nb: " + "9" * 400 + "\n", 3, "400 digits"),
    ("a: " + str(2 ** 63) + "\n", 1, "out of range"),
    ("x: !!float x\n", 1, "'x' is not a number"),
    ("x: !!int 1.5\n", 1, "not an integer"),
    ("a: &a [1, *a]\n", 1, "refers to a node that contains it"),
    ("a: *nowhere\n", 1, "names no anchor"),
    (_bomb(), 6, "more than 200000 nodes"),
    ("b: 1\na: " + "[" * (MAX_YAML_DEPTH + 1) + "]" * (MAX_YAML_DEPTH + 1) + "\n", 2,
     "nested more than"),
    ("x: !!python/object/apply:os.system [true]\n", 1, "not valid YAML"),
    ("a: [1, 2\n", 2, "not valid YAML"),
])
def test_bad_yaml_text_names_line_and_problem(text: str, line: int, needle: str) -> None:
    with pytest.raises(ReadError) as e:
        parse_yaml(text, "f.yaml")
    assert str(e.value).startswith(f"f.yaml:{line}: ") and needle in str(e.value)


def test_good_yaml_with_aliases_reads_as_plain_data() -> None:
    assert parse_yaml("a: &x {b: 1}\nc: *x\nd: 0x10\n", "f.yaml") == {
        "a": {"b": 1}, "c": {"b": 1}, "d": 16}
    assert parse_yaml("", "f.yaml") is None


def test_utf8_decode_error_names_line(tmp_path: Path) -> None:
    p = tmp_path / "t.yaml"
    p.write_bytes(b"a: 1\nb: caf\xe9\n")
    with pytest.raises(ReadError, match=r"t.yaml:2: file is not UTF-8 text \(byte 0xe9\)"):
        load_yaml(p)
    p.write_bytes(b"\xef\xbb\xbfa: 1\n")  # a UTF-8 byte order mark is fine
    assert load_yaml(p) == {"a": 1}


@pytest.mark.parametrize("path", ["/dev/zero", "/dev/urandom", "/tmp"])
def test_non_regular_files_are_refused_without_reading(path: str) -> None:
    if not os.path.exists(path):
        pytest.skip(f"{path} does not exist here")
    with pytest.raises(ReadError, match="not a regular file"):
        read_bytes(path)


def test_fifo_is_refused_without_blocking(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(ReadError, match="not a regular file"):
        read_bytes(fifo)


def test_size_limit(tmp_path: Path) -> None:
    p = tmp_path / "big.yaml"
    p.write_bytes(b"#" * (MAX_TEXT_BYTES + 1))
    with pytest.raises(ReadError, match="more than the limit"):
        read_bytes(p)
    assert read_bytes(p, limit=MAX_TEXT_BYTES + 1)[:1] == b"#"


def test_each_layer_raises_its_own_error_with_the_file(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("a: &a [1, *a]\n")
    with pytest.raises(ConfigError, match=r"bad.yaml:1: alias"):
        load_config(bad)
    with pytest.raises(ScenarioError, match=r"bad.yaml:1: alias"):
        load_scenario(bad)
    with pytest.raises(MapError, match=r"bad.yaml:1: alias"):
        load_map(bad)
    with pytest.raises(TreeLoadError, match=r"bad.yaml:1: alias"):
        load_tree_file(bad)


def _tree(body: str) -> str:
    return f"trees:\n  T:\n{body}"


def test_tree_include_of_a_device_is_refused(tmp_path: Path) -> None:
    p = tmp_path / "t.yaml"
    p.write_text("include: [/dev/zero]\n" + _tree("    Wait: {wait_duration: 1.0}\n"))
    with pytest.raises(TreeLoadError, match="not a regular file"):
        load_tree_file(p)


def test_deep_yaml_tree_is_a_clean_error(tmp_path: Path) -> None:
    depth = 400
    body = "".join("  " * (i + 2) + "Inverter:\n" + "  " * (i + 3) + "child:\n"
                   for i in range(0, 2 * depth, 2))
    p = tmp_path / "deep.yaml"
    p.write_text(_tree(body + "  " * (2 * depth + 2) + "AlwaysSuccess: {}\n"))
    with pytest.raises(TreeLoadError, match="deep.yaml:\\d+: nested more than"):
        load_tree_file(p)


def test_deep_tree_under_yaml_limit_hits_the_tree_depth_limit(tmp_path: Path) -> None:
    # B nests 45 Inverters then a SubTree to C holding 45 more: 91 levels expanded
    b = "".join("  " * (i + 2) + "Inverter:\n" + "  " * (i + 3) + "child:\n"
                for i in range(0, 90, 2)) + "  " * 92 + "SubTree: {id: C}\n"
    c = "".join("  " * (i + 2) + "Inverter:\n" + "  " * (i + 3) + "child:\n"
                for i in range(0, 90, 2)) + "  " * 92 + "AlwaysSuccess: {}\n"
    text = ("main_tree: B\ntrees:\n  B:\n" + b + "  C:\n" + c)
    p = tmp_path / "sub.yaml"
    p.write_text(text)
    with pytest.raises(TreeLoadError, match="larger than the limits"):
        load_tree_file(p)


def test_deep_xml_is_a_clean_error(tmp_path: Path) -> None:
    p = tmp_path / "deep.xml"
    p.write_text('<root main_tree_to_execute="T"><BehaviorTree ID="T">' + "<Inverter>" * 400
                 + "<AlwaysSuccess/>" + "</Inverter>" * 400 + "</BehaviorTree></root>")
    with pytest.raises(TreeLoadError, match="deep.xml:1: elements nested more than"):
        load_tree_file(p)


@pytest.mark.parametrize("head,needle", [
    ('<?xml version="1.0" encoding="klingon"?>', "not valid XML"),
    ('<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaa">]>', "entity declarations"),
])
def test_xml_encoding_and_entities_are_clean_errors(tmp_path: Path, head: str, needle: str
                                                    ) -> None:
    p = tmp_path / "t.xml"
    p.write_text(head + '<root><BehaviorTree ID="T"><AlwaysSuccess/></BehaviorTree></root>')
    with pytest.raises(TreeLoadError, match=needle):
        load_tree_file(p)


def test_set_parameters_alias_bomb_is_refused(tmp_path: Path) -> None:
    p = tmp_path / "t.yaml"
    p.write_text(_bomb(6).replace("a5: &a5", "x: &a5") + _tree(
        "    SetParameters:\n      namespace: DWAPlannerROS\n      values: {x: *a5}\n"
        "      child: {AlwaysSuccess: {}}\n"))
    with pytest.raises(TreeLoadError, match="more than 200000 nodes"):
        load_tree_file(p)


@pytest.mark.parametrize("text", ["x: !!timestamp 2020-99", "? !!timestamp 1\n: 2",
                                  "x: !!timestamp garbage"])
def test_malformed_timestamps_are_clean_errors(text: str) -> None:
    with pytest.raises(ReadError, match="f.yaml:1: bad value: .* is not a timestamp"):
        parse_yaml(text, "f.yaml")


# ------------------------------------------------------------------ a key written twice
def test_duplicate_key_is_an_error_naming_both_lines_in_every_navbt_format(tmp_path: Path
                                                                           ) -> None:
    """PyYAML keeps the last of two equal keys without a word; every navbt-owned format refuses
    it where it is written, with the line of the first."""
    from executive.sweeps.spec import SweepError, load_sweep
    robot = tmp_path / "robot.yaml"
    robot.write_text("robot:\n  radius: 0.2\ncostmap:\n  resolution: 0.05\n"
                     "  inflation_radius: 0.5\n  obstacle_range: 2.5\n"
                     "  inflation_radius: 0.3\n")
    with pytest.raises(ConfigError) as e:
        load_config(robot)
    assert str(e.value) == (f"{robot}:7: 'inflation_radius' appears twice in the same mapping "
                            f"(first at line 5)")
    cases = [  # file, text, loader, error, the message's line and key and first line
        ("scn.yaml", "name: s\ngoals:\n  - {x: 1.0, y: 2.0, x: 3.0}\n", load_scenario,
         ScenarioError, 3, "x", 3),
        ("map.yaml", "image: map.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nresolution: 0.1\n",
         load_map, MapError, 4, "resolution", 2),
        ("sweep.yaml", "scenarios: s/*.yaml\ngrid:\n  DWAPlannerROS.sim_time: [1.0]\n"
         "  DWAPlannerROS.vx_samples: [3]\n  DWAPlannerROS.sim_time: [2.0]\n", load_sweep,
         SweepError, 5, "DWAPlannerROS.sim_time", 3),
        ("tree.yaml", _tree("    Wait: {msec: 1,\n           msec: 2}\n"), load_tree_file,
         TreeLoadError, 4, "msec", 3),
    ]
    for name, text, load, error, line, key, first in cases:
        path = tmp_path / name
        path.write_text(text)
        with pytest.raises(error, match=rf"{re.escape(name)}:{line}: '{re.escape(key)}' appears "
                                        rf"twice in the same mapping \(first at line {first}\)$"):
            load(path)


def test_merged_keys_may_be_overridden_and_keys_compare_by_type() -> None:
    """A key merged in by ``<<`` and written again is YAML's override, not a duplicate; ``1``
    and ``"1"`` are two keys; only the mapping's own keys count (an anchor is checked once)."""
    from executive.scenarios.source import parse_source
    text = ("base: &b {speed: 0.5, radius: 0.2}\n"
            "fast:\n  <<: *b\n  speed: 1.0\n"
            "again:\n  <<: *b\n  radius: 0.3\n"
            "types: {1: int, '1': str}\n")
    want = {"base": {"speed": 0.5, "radius": 0.2}, "fast": {"speed": 1.0, "radius": 0.2},
            "again": {"speed": 0.5, "radius": 0.3}, "types": {1: "int", "1": "str"}}
    assert parse_yaml(text, "m.yaml") == want
    assert parse_source(text, "m.yaml").doc == want        # the scenario reader's own walk
    assert parse_source(text, "m.yaml").lines[("fast", "speed")] == 4
    with pytest.raises(ReadError, match=r"m.yaml:2: 'speed' appears twice in the same mapping "
                                        r"\(first at line 2\)$"):
        parse_yaml("a: &b {x: 1}\nc: {<<: *b, speed: 1, speed: 2}\n", "m.yaml")


def test_ros_parameter_files_keep_the_last_of_two_keys_with_a_note(tmp_path: Path) -> None:
    """rosparam reads with PyYAML (the last key wins) and real files must load unedited: a
    duplicate in a ROS 1 params file, a Nav2 params file or an inline <rosparam> is a note."""
    from executive.config import ConfigSources, load_config_sources
    from executive.nav2_params import read_nav2_params
    from executive.ros_launch import read_launch
    ros1 = tmp_path / "dwa.yaml"
    ros1.write_text("DWAPlannerROS:\n  max_vel_x: 0.4\n  sim_time: 1.5\n  max_vel_x: 0.3\n")
    cfg = load_config_sources(ConfigSources(params=[str(ros1)]))
    assert cfg.namespaces["DWAPlannerROS"]["max_vel_x"] == 0.3
    want = (f"{ros1}:4: note: 'max_vel_x' appears twice in the same mapping (first at line 2); "
            f"the last one is used, as rosparam does")
    assert [str(n) for n in cfg.report if "twice" in n.text] == [want]
    nav2 = tmp_path / "nav2.yaml"
    nav2.write_text("controller_server:\n  ros__parameters:\n    controller_frequency: 20.0\n"
                    "    controller_frequency: 10.0\n")
    notes = [n for n in read_nav2_params(nav2).notes if "twice" in n.text]
    assert [(n.level, n.where) for n in notes] == [("note", f"{nav2}:4")]
    assert "(first at line 3)" in notes[0].text
    launch = tmp_path / "move_base.launch"
    launch.write_text('<launch>\n  <node pkg="move_base" type="move_base" name="move_base">\n'
                      '    <rosparam>\n      a: 1\n      a: 2\n    </rosparam>\n'
                      '  </node>\n</launch>\n')
    got = read_launch(launch, {})
    assert got.tree.values["move_base"]["a"] == 2
    notes = [n for n in got.notes if "twice" in n.text]
    assert [(n.level, n.where) for n in notes] == [("note", f"{launch}:5")]
    assert "'a' appears twice in the same mapping (first at line 4)" in notes[0].text
