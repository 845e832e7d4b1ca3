"""Number ports refuse NaN, infinity and values outside their declared range, by name."""

from __future__ import annotations

import math
from pathlib import Path

import py_trees
import pytest

from behaviors.base import Port, make, node_classes, port_problem
from executive.tree_loader import TreeLoadError, load_tree_file


def test_every_declared_default_fits_its_own_port() -> None:
    for name, cls in node_classes().items():
        for port, info in cls.input_ports().items():
            if info.has_default:
                assert port_problem(info, info.default_value) is None, (name, port)


def test_ranged_ports_are_declared() -> None:
    wait = node_classes()["Wait"].input_ports()["wait_duration"]
    assert isinstance(wait, Port) and wait.low == 0.0


def _tree(tmp_path: Path, node: str) -> Path:
    p = tmp_path / "t.yaml"
    p.write_text(f"trees:\n  T:\n    Sequence:\n      children:\n        - {node}\n")
    return p


@pytest.mark.parametrize("node,needle", [
    ("Wait: {wait_duration: .nan}", "port 'wait_duration' must be a finite number, got nan"),
    ("Wait: {wait_duration: -1.0}", "port 'wait_duration' must be >= 0"),
    ("BackUp: {backup_speed: .nan}", "port 'backup_speed' must be a finite number"),
    ("BackUp: {backup_dist: .inf}", "port 'backup_dist' must be a finite number"),
    ("Spin: {spin_dist: -.inf}", "port 'spin_dist' must be a finite number"),
    ("Spin: {sim_granularity: 0.0}", "port 'sim_granularity' must be >= 0.001"),
    ("Wait: {wait_duration: 1.0e+999}", "must be a finite number"),
])
def test_bad_number_literal_is_a_load_error_at_its_line(tmp_path: Path, node: str,
                                                        needle: str) -> None:
    with pytest.raises(TreeLoadError) as e:
        load_tree_file(_tree(tmp_path, node))
    assert "t.yaml:5" in str(e.value) and needle in str(e.value)


def test_bad_number_in_xml_is_a_load_error(tmp_path: Path) -> None:
    p = tmp_path / "t.xml"
    p.write_text('<root main_tree_to_execute="T"><BehaviorTree ID="T">\n'
                 '<Wait wait_duration="nan"/>\n</BehaviorTree></root>')
    with pytest.raises(TreeLoadError, match=r"t.xml:2: .*wait_duration' must be a finite"):
        load_tree_file(p)


def test_a_nan_on_the_blackboard_is_refused_when_read() -> None:
    node = make("Wait", namespace="/ports", wait_duration="{how_long}")
    py_trees.blackboard.Blackboard.storage["/ports/how_long"] = math.nan
    try:
        with pytest.raises(ValueError, match="port 'wait_duration' .* must be a finite number"):
            node.get_input("wait_duration")
        py_trees.blackboard.Blackboard.storage["/ports/how_long"] = 2.0
        assert node.get_input("wait_duration") == 2.0
    finally:
        py_trees.blackboard.Blackboard.storage.pop("/ports/how_long", None)


def test_infinity_only_where_declared_meaningful() -> None:
    from behaviors.base import PortInformation
    no_limit = PortInformation(float, False, "m; inf = all", math.inf)
    assert port_problem(no_limit, math.inf) is None
    assert port_problem(no_limit, math.nan) is not None
    assert port_problem(Port(float, False, "s", 1.0, finite=False), -math.inf) is None
    assert port_problem(PortInformation(float, False, "s", 1.0), math.inf) is not None
