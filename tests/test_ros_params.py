"""rosparam files into namespaces (--params FILE[:NS]) and ROS's leniency: deprecated names,
clamps, keys ROS ignores, unused layer namespaces, one footprint, every error at once."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from executive.config import ConfigError, ConfigSources, config_from_mapping, load_config_sources
from navcore.controllers.dwa import DWA_PARAMS
from navcore.params import suggest


def _files(tmp_path: Path, **files: str) -> dict[str, str]:
    out = {}
    for name, text in files.items():
        p = tmp_path / f"{name}.yaml"
        p.write_text(textwrap.dedent(text))
        out[name] = str(p)
    return out


def _load(*params: str) -> object:
    return load_config_sources(ConfigSources(params=list(params)))


def test_params_files_merge_in_order_into_namespaces(tmp_path):
    f = _files(tmp_path,
               common="""\
                   footprint: [[0.3, 0.2], [0.3, -0.2], [-0.3, -0.2], [-0.3, 0.2]]
                   obstacle_range: 2.0
                   inflation_radius: 0.6
                   observation_sources: scan
                   scan: {data_type: LaserScan, marking: true, clearing: true}
                   """,
               local="""\
                   local_costmap:
                     rolling_window: true
                     width: 4
                     height: 4
                   """,
               move_base="""\
                   controller_frequency: 8.0
                   base_local_planner: dwa_local_planner/DWAPlannerROS
                   DWAPlannerROS: {max_vel_x: 0.3, vy_samples: 1}
                   """,
               later="""\
                   DWAPlannerROS:
                     max_vel_x: 0.25
                   """)
    c = _load(f"{f['common']}:global_costmap", f"{f['common']}:local_costmap", f["local"],
              f["move_base"], f["later"])
    assert c.move_base.controller_frequency == 8.0
    dwa = c.parameters["DWAPlannerROS"]
    assert dwa.max_vel_x == 0.25 and dwa.vy_samples == 1   # merged key by key, later wins
    assert c.origins[("DWAPlannerROS", "max_vel_x")] == f"{f['later']}:2"
    assert c.origins[("DWAPlannerROS", "vy_samples")] == f"{f['move_base']}:3"
    assert c.ns("local_costmap")["width"] == 4 and c.ns("global_costmap")["obstacle_range"] == 2.0
    assert c.footprint() == [(0.3, 0.2), (0.3, -0.2), (-0.3, -0.2), (-0.3, 0.2)]
    # a costmap file without its namespace: ROS does not read it there; a warning per key says
    # where it belongs (the footprint is found by searching up, as costmap_2d does)
    c = _load(f["common"])
    text = "\n".join(str(n) for n in c.report if n.level == "warning")
    assert f"{f['common']}:3: warning: 'inflation_radius' is a costmap parameter" in text
    assert "--params FILE:local_costmap" in text
    assert f"{f['common']}:4: warning: 'observation_sources' is a costmap parameter" in text
    assert c.footprint()[0] == (0.3, 0.2)


def test_footprint_at_move_base_level_reaches_costmaps_body_and_checks(tmp_path):
    """PR2 style: footprint at the move_base level (costmap_2d searches up the namespace),
    as a string."""
    f = _files(tmp_path, mb="""\
        footprint: "[[0.33, 0.33], [0.33, -0.33], [-0.33, -0.33], [-0.33, 0.33]]"
        local_costmap: {rolling_window: true, width: 3, height: 3}
        global_costmap: {robot_radius: 0.5}
        """)
    c = _load(f["mb"])
    square = [[0.33, 0.33], [0.33, -0.33], [-0.33, -0.33], [-0.33, 0.33]]
    assert [list(p) for p in c.footprint()] == square
    assert c.ns("sim")["footprint"] == square
    assert c.ns("local_costmap")["footprint"].startswith("[[0.33")
    # found by searchParam, the move_base-level footprint wins over the costmap's robot_radius
    assert c.ns("global_costmap")["footprint"].startswith("[[0.33")
    notes = [str(n) for n in c.report if n.level == "note"]
    assert any("'footprint' at the move_base level" in n and f"{f['mb']}:1" in n for n in notes)
    # robot.footprint as a string too, and it wins over the costmaps'
    c = config_from_mapping({"robot": {"footprint": "[[0.1, 0.1], [0.1, -0.1], [-0.1, 0]]"},
                             "local_costmap": {"robot_radius": 0.4}}, "r.yaml")
    assert c.footprint() == [(0.1, 0.1), (0.1, -0.1), (-0.1, 0.0)]
    c = config_from_mapping({"local_costmap": {"robot_radius": 0.4}}, "r.yaml")
    assert c.circumscribed_radius() == pytest.approx(0.4)
    assert c.ns("sim")["robot_radius"] == 0.4


def test_deprecated_names_warn_and_name_the_new_one():
    c = config_from_mapping({"DWAPlannerROS": {"max_rot_vel": 1.2, "min_rot_vel": 0.3,
                                               "max_trans_vel": 0.4, "min_vel_rot": 0.35,
                                               "rot_stopped_vel": 0.05, "acc_lim_th": 2.0}},
                            "r.yaml")
    dwa = c.parameters["DWAPlannerROS"]
    assert (dwa.max_vel_theta, dwa.max_vel_trans, dwa.theta_stopped_vel, dwa.acc_lim_theta) == \
        (1.2, 0.4, 0.05, 2.0)
    warnings = [n.text for n in c.report if n.level == "warning"]
    assert "DWAPlannerROS: 'max_rot_vel' is deprecated: use 'max_vel_theta' (the value is used " \
           "as 'max_vel_theta')" in warnings
    # min_rot_vel and min_vel_rot both mean min_vel_theta: the first wins, the other is reported
    assert dwa.min_vel_theta == 0.3
    assert "DWAPlannerROS: 'min_vel_rot' is a deprecated name of 'min_vel_theta', which is " \
           "also given: 'min_vel_rot' is ignored" in warnings
    assert len(warnings) == 6
    c = config_from_mapping({"TrajectoryPlannerROS": {"pdist_scale": 0.75, "gdist_scale": 1.0,
                                                      "backup_vel": -0.2}}, "r.yaml")
    tr = c.parameters["TrajectoryPlannerROS"]
    assert (tr.path_distance_bias, tr.goal_distance_bias, tr.escape_vel) == (0.75, 1.0, -0.2)


def test_typo_of_a_real_parameter_is_an_error_with_the_right_suggestion():
    names = [p.name for p in DWA_PARAMS]
    assert suggest("max_rot_vel", names) == " (did you mean 'max_vel_theta'?)"
    assert suggest("min_rotational_vel", names) == " (did you mean 'min_vel_theta'?)"
    with pytest.raises(ConfigError, match=r"r.yaml: DWAPlannerROS: unknown parameter "
                                          r"'max_rot_vell' \(did you mean 'max_rot_vel'\?\)"):
        config_from_mapping({"DWAPlannerROS": {"max_rot_vell": 1.0}}, "r.yaml")


def test_clamps_ignored_keys_and_every_error_at_once(tmp_path):
    f = _files(tmp_path, mb="""\
        controler_frequency: 5.0
        recovery_behaviors:
          - {name: conservative_reset, type: clear_costmap_recovery/ClearCostmapRecovery}
          - {name: rotate_recovery, type: rotate_recovery/RotateRecovery}
        conservative_reset: {reset_distance: 3.0}
        DWAPlannerROS:
          vx_samples: 0
          vth_samples: -3
          publish_traj_pc: true
          sim_time: fast
        TrajectoryPlannerROS:
          max_vel_x: 0.5
          vtheta_sampels: 10
        local_costmap:
          plugins: [{name: obstacles, type: "costmap_2d::ObstacleLayer"}]
          static: {map_topic: /map}
          widht: 3
        """)
    with pytest.raises(ConfigError) as e:
        _load(f["mb"])
    errors = str(e.value).splitlines()
    assert errors == [
        f"{f['mb']}:1: move_base: unknown parameter 'controler_frequency' (did you mean "
        "'controller_frequency'?)",
        f"{f['mb']}:10: DWAPlannerROS: parameter 'sim_time' must be a number, got 'fast'",
        f"{f['mb']}:13: TrajectoryPlannerROS: unknown parameter 'vtheta_sampels' (did you mean "
        "'vtheta_samples'?)",
        f"{f['mb']}:17: local_costmap: unknown parameter 'widht' (did you mean 'width'?)",
    ]
    notes = {n.level: [] for n in e.value.notes}
    for n in e.value.notes:
        notes[n.level].append(str(n))
    assert any("'vx_samples' = 0 is clamped to 1" in w and f"{f['mb']}:7" in w
               for w in notes["warning"])
    assert any("'vth_samples' = -3 is clamped to 1" in w for w in notes["warning"])
    assert any(f"{f['mb']}:9: ignored: DWAPlannerROS: 'publish_traj_pc'" in w
               for w in notes["ignored"])
    assert any(f"{f['mb']}:2: note: 'recovery_behaviors'" in w and "trees" in w
               and "rotate_recovery (rotate_recovery/RotateRecovery -> Spin)" in w
               and "children: [{ClearCostmapExceptRegion: {name: conservative_reset, costmap: "
                   "both, reset_distance: 3.0}}, {Spin: {name: rotate_recovery, spin_dist: "
                   "6.28}}]}" in w
               for w in notes["note"])
    assert any(f"{f['mb']}:5: ignored: 'conservative_reset'" in w for w in notes["ignored"])
    assert any(f"{f['mb']}:16: note: local_costmap: layer namespace 'static' is not in "
               "'plugins'" in w for w in notes["note"])


def test_own_range_errors_keep_the_value_written():
    with pytest.raises(ConfigError, match=r"r.yaml: move_base: parameter 'controller_frequency' "
                                          r"= -1.0 is below its minimum"):
        config_from_mapping({"move_base": {"controller_frequency": -1}}, "r.yaml")
    c = config_from_mapping({"move_base": {"controller_frequency": 250.0}}, "r.yaml")
    assert c.move_base.controller_frequency == 100.0    # MoveBase.cfg's range
    assert any("clamped to 100.0" in n.text for n in c.report)


def test_misspelling_ros_ignores_is_a_warning(tmp_path):
    f = _files(tmp_path, mb="recovery_behaviour_enabled: false\n")
    c = _load(f["mb"])
    assert c.move_base.recovery_behavior_enabled is True   # not read, as by move_base
    assert any(n.level == "warning" and "'recovery_behaviour_enabled' is not read" in n.text
               for n in c.report)


def test_misplaced_ros_parameter_in_a_robot_yaml_says_where_it_belongs():
    with pytest.raises(ConfigError) as e:
        config_from_mapping({"obstacle_range": 2.5, "controller_frequency": 5.0,
                             "move_bas": {}}, "r.yaml")
    lines = str(e.value).splitlines()
    assert lines[0] == ("r.yaml: unknown namespace 'obstacle_range': 'obstacle_range' is a "
                        "costmap parameter; put it under global_costmap: / local_costmap: (or "
                        "load the ROS file with --params FILE:local_costmap)")
    assert lines[1].startswith("r.yaml: unknown namespace 'controller_frequency': "
                               "'controller_frequency' is a move_base parameter")
    assert lines[2] == "r.yaml: unknown namespace 'move_bas' (did you mean 'move_base'?)"


def test_scenario_config_over_ros_files(shared_data, monkeypatch):
    from executive.scenario import load_scenario, scenario_config
    root = shared_data / "ros_params" / "turtlebot3_navigation"
    if not root.is_dir():
        pytest.skip(f"TurtleBot3 files not found under {root}")
    monkeypatch.delenv("TURTLEBOT3_MODEL", raising=False)
    scenario = load_scenario(Path(__file__).parent.parent / "executive" / "data" / "demo.yaml")
    sources = ConfigSources(launch=str(root / "launch" / "move_base.launch"),
                            args={"model": "waffle"})
    c = scenario_config(scenario, sources)
    assert c.parameters["DWAPlannerROS"].max_vel_x == 0.26
    assert c.source.endswith("model:=waffle)")


def test_params_namespaces_amcl_and_global_names(tmp_path):
    f = _files(tmp_path, amcl="min_particles: 321\nodom_alpha1: 0.1\n",
               local="rolling_window: true\nwidth: 2\nheight: 2\n")
    c = _load(f"{f['amcl']}:amcl", f"{f['local']}:/move_base/local_costmap")
    assert c.parameters["amcl"].min_particles == 321
    assert c.origins[("amcl", "odom_alpha1")] == f"{f['amcl']}:2"
    assert c.ns("local_costmap")["width"] == 2
    c = _load(f"{f['amcl']}:/amcl")
    assert c.parameters["amcl"].odom_alpha1 == 0.1
    with pytest.raises(ConfigError, match=r"nothere.yaml: cannot read parameter file"):
        _load(str(tmp_path / "nothere.yaml"))


def test_amcl_block_in_a_move_base_file_says_how_to_load_it(tmp_path):
    f = _files(tmp_path, all="controller_frequency: 5.0\namcl: {min_particles: 200}\n")
    with pytest.raises(ConfigError, match=r"all.yaml:2: 'amcl' is its own node, not a namespace "
                                          r"of move_base: put its parameters in a file"):
        _load(f["all"])
    # loaded at the top, move_base's key is a global name nobody reads: listed, not dropped
    c = _load(f"{f['all']}:/")
    assert c.parameters["amcl"].min_particles == 200
    assert c.move_base.controller_frequency == 20.0
    ignored = [str(n) for n in c.report if n.level == "ignored"]
    assert any(f"{f['all']}:1: ignored: parameters outside the move_base and amcl nodes "
               "(no node here reads them): /controller_frequency (all.yaml:1)" in n
               for n in ignored)


def test_recovery_list_as_a_tree_loads(tmp_path):
    from executive.tree_loader import load_tree_file
    f = _files(tmp_path, mb="""\
        recovery_behaviors:
          - {name: reset, type: clear_costmap_recovery/ClearCostmapRecovery}
          - {name: turn, type: rotate_recovery/RotateRecovery}
        reset: {reset_distance: 2.0}
        """)
    c = _load(f["mb"])
    note = next(n.text for n in c.report if "'recovery_behaviors'" in n.text)
    subtree = note.split("(MoveBaseRecoveries): ", 1)[1]
    tree = tmp_path / "recoveries.yaml"
    tree.write_text(f"main_tree: R\ntrees:\n  R:\n    {subtree}\n")
    root = load_tree_file(tree, namespace="/recovery_list").root
    kids = {n.name: n for n in root.iterate()}
    assert type(kids["reset"]).__name__ == "ClearCostmapExceptRegion"
    assert kids["reset"].get_input("reset_distance") == 2.0
    assert type(kids["turn"]).__name__ == "Spin"
    # a type with no node: no subtree offered
    f = _files(tmp_path, mb2="recovery_behaviors: [{name: slow, type: "
                             "move_slow_and_clear/MoveSlowAndClear}]\n")
    c = _load(f["mb2"])
    note = next(n.text for n in c.report if "'recovery_behaviors'" in n.text)
    assert "MoveBaseRecoveries" not in note and "slow (move_slow_and_clear/MoveSlowAndClear" in note
