"""The move_base namespace drives trees/move_base.yaml as it drives move_base: each parameter
set to another value than move_base's default reaches the node named after it, in its units."""

from __future__ import annotations

import textwrap
from pathlib import Path

from executive.config import ConfigSources, load_config_sources
from executive.tree_loader import load_tree_file

TREE = Path(__file__).resolve().parent.parent / "trees" / "move_base.yaml"


def nodes(tmp_path, text: str | None, ns: str):
    sources = ConfigSources()
    if text is not None:
        p = tmp_path / "move_base_params.yaml"
        p.write_text(textwrap.dedent(text))
        sources = ConfigSources(params=[str(p)])
    config = load_config_sources(sources)
    root = load_tree_file(TREE, namespace=ns, port_defaults=config.port_defaults()).root
    return {n.name: n for n in root.iterate()}


def test_move_base_defaults_leave_the_tree_as_written(tmp_path):
    n = nodes(tmp_path, """\
        controller_patience: 15.0
        oscillation_timeout: 0.0
        oscillation_distance: 0.5
        """, "/mbp_default")                 # the bundled robot's values back to ROS's
    assert n["ControllerPatience"].get_input("failure_tolerance") == 15.0
    assert n["PlannerPatience"].get_input("msec") == 5000
    assert n["MaxPlanningRetries"].get_input("num_attempts") == -1
    assert n["OscillationCheck"].get_input("oscillation_timeout") == 0.0
    assert n["OscillationCheck"].get_input("oscillation_distance") == 0.5
    assert n["conservative_reset"].get_input("reset_distance") == 3.0
    assert n["MoveBase"].get_input("number_of_retries") == 4
    assert n["MoveBase"].get_input("reset_after") == 20.0


def test_the_bundled_robot_config_drives_the_tree(tmp_path):
    n = nodes(tmp_path, None, "/mbp_bundled")  # executive/data/robot.yaml's move_base values
    assert n["ControllerPatience"].get_input("failure_tolerance") == 5.0
    assert n["OscillationCheck"].get_input("oscillation_timeout") == 10.0
    assert n["OscillationCheck"].get_input("oscillation_distance") == 0.2
    assert n["PlannerPatience"].get_input("msec") == 5000
    assert n["MoveBase"].get_input("reset_after") == 10.0           # patience + 5 s


def test_move_base_parameters_reach_their_nodes_in_the_ports_units(tmp_path):
    n = nodes(tmp_path, """\
        controller_patience: 3.5
        planner_patience: 2.25
        max_planning_retries: 2
        oscillation_timeout: 10.0
        oscillation_distance: 0.2
        conservative_reset_dist: 1.5
        recovery_behavior_enabled: false
        """, "/mbp_set")
    assert n["ControllerPatience"].get_input("failure_tolerance") == 3.5
    assert n["PlannerPatience"].get_input("msec") == 2250
    assert n["MaxPlanningRetries"].get_input("num_attempts") == 3     # one plan + 2 retries
    assert n["OscillationCheck"].get_input("oscillation_timeout") == 10.0
    assert n["OscillationCheck"].get_input("oscillation_distance") == 0.2
    assert n["conservative_reset"].get_input("reset_distance") == 1.5
    assert n["aggressive_reset"].get_input("reset_distance") == 1.84  # not a move_base parameter
    assert n["MoveBase"].get_input("number_of_retries") == 0         # abort at once
    assert n["MoveBase"].get_input("reset_after") == 8.5
