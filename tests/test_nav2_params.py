"""Nav2 parameter files (ros__parameters) of each distribution load unchanged; names with a navbt
counterpart are mapped, the rest is reported once, grouped, as ignored."""

from __future__ import annotations

import textwrap

import pytest

from executive.config import ConfigSources, load_config_sources
from executive.nav2_params import read_nav2_params
from executive.param_files import ParamsError

DISTROS = ("humble", "jazzy", "kilted", "main")


@pytest.fixture(scope="module")
def nav2_dir(shared_data):
    d = shared_data / "ros_params" / "nav2"
    if not d.is_dir():
        pytest.skip(f"Nav2 parameter files not found under {d}")
    return d


@pytest.mark.parametrize("distro", DISTROS)
def test_nav2_params_load_unchanged(nav2_dir, distro):
    path = str(nav2_dir / f"nav2_params_{distro}.yaml")
    c = load_config_sources(ConfigSources(nav2_params=[path]))
    assert not [n for n in c.report if n.level == "error"]
    # robot_radius 0.22 in both costmaps: the robot's body and footprint
    assert c.circumscribed_radius() == pytest.approx(0.22)
    assert c.ns("sim")["robot_radius"] == 0.22 and c.ns("sim")["footprint"] == []
    amcl = c.parameters["amcl"]
    assert (amcl.odom_alpha1, amcl.laser_z_hit, amcl.laser_max_beams) == (0.2, 0.5, 60)
    assert amcl.odom_model_type == "diff-corrected"
    assert amcl.kld_err == 0.05 and amcl.laser_model_type == "likelihood_field"
    line = next(i for i, t in enumerate(open(path), 1) if t.strip().startswith("alpha1:"))
    assert c.origins[("amcl", "odom_alpha1")] == f"{path}:{line}"
    assert c.move_base.base_global_planner == "navfn/NavfnROS"
    assert c.parameters["NavfnROS"].default_tolerance == 0.5
    assert c.move_base.base_local_planner == "dwa_local_planner/DWAPlannerROS"
    assert c.move_base.controller_frequency == 20.0
    dwa = c.parameters["DWAPlannerROS"]
    assert (dwa.xy_goal_tolerance, dwa.yaw_goal_tolerance) == (0.25, 0.25)  # goal checker
    assert dwa.latch_xy_goal_tolerance is True                            # stateful
    assert dwa.max_vel_y == 0.0 and dwa.vy_samples == (5 if distro == "humble" else 1)
    local = c.ns("local_costmap")
    assert local["plugins"] == ["voxel_layer", "inflation_layer"]
    src = local["voxel_layer"]["scan"]
    assert (src["raytrace_range"], src["obstacle_range"]) == (3.0, 2.5)   # Nav2's *_max_range
    assert "static_layer" not in local                     # not in plugins: noted, left out
    ignored = [n for n in c.report if n.level == "ignored" and n.where == path]
    assert len(ignored) == 1                               # once, grouped
    text = ignored[0].text
    assert text.startswith("no counterpart in navbt: ")
    assert "amcl: " in text and "scan_topic" in text and "bt_navigator: " in text
    assert "servers navbt does not run: " in text and "map_saver" in text
    warnings = " ".join(n.text for n in c.report if n.level == "warning")
    if distro == "humble":          # DWB: kinematics and the critics that mean the same
        assert (dwa.max_vel_x, dwa.max_vel_trans, dwa.vth_samples) == (0.26, 0.26, 20)
        assert (dwa.path_distance_bias, dwa.goal_distance_bias, dwa.occdist_scale) == \
            (32.0, 24.0, 0.02)
        assert dwa.forward_point_distance == 0.1
        assert (c.safety.max_vel_x, c.safety.min_vel_x, c.safety.max_vel_theta) == \
            (0.26, -0.26, 1.0)
        assert "MPPI" not in warnings
        assert any("RotateToGoal have no DWA counterpart" in n.text for n in c.report)
    else:                           # MPPI: not available, its limits drive the DWA
        assert "MPPIController is not available in navbt" in warnings
        assert (dwa.max_vel_x, dwa.min_vel_x, dwa.max_vel_theta, dwa.acc_lim_theta) == \
            (0.5, -0.35, 1.9, 3.5)
        assert (c.safety.max_vel_x, c.safety.min_vel_x, c.safety.max_vel_theta) == \
            (0.5, -0.5, 2.0)                   # velocity_smoother
        assert c.safety.sensor_timeout == 1.0  # collision_monitor source_timeout


def test_nav2_smac_footprint_string_and_unknown_layer(tmp_path):
    p = tmp_path / "p.yaml"
    p.write_text(textwrap.dedent("""\
        planner_server:
          ros__parameters:
            planner_plugins: ["GridBased"]
            GridBased:
              plugin: "nav2_smac_planner::SmacPlannerHybrid"
              tolerance: 0.3
        local_costmap:
          local_costmap:
            ros__parameters:
              footprint: "[[0.3, 0.25], [0.3, -0.25], [-0.3, -0.25], [-0.3, 0.25]]"
              rolling_window: true
              plugins: ["stvl_layer", "inflation_layer"]
              stvl_layer: {plugin: "spatio_temporal_voxel_layer/SpatioTemporalVoxelLayer"}
              inflation_layer: {plugin: "nav2_costmap_2d::InflationLayer", inflation_radius: 0.5}
        """))
    c = load_config_sources(ConfigSources(nav2_params=[str(p)]))
    assert [list(q) for q in c.footprint()] == [[0.3, 0.25], [0.3, -0.25], [-0.3, -0.25],
                                                [-0.3, 0.25]]
    assert c.parameters["NavfnROS"].default_tolerance == 0.3
    warnings = [str(n) for n in c.report if n.level == "warning"]
    assert any(f"{p}:4: warning: planner_server: 'GridBased' (nav2_smac_planner::"
               "SmacPlannerHybrid) is not available" in w for w in warnings)
    assert any(f"{p}:13: warning: local_costmap: layer 'stvl_layer'" in w for w in warnings)
    assert c.ns("local_costmap")["plugins"] == ["inflation_layer"]
    ros1 = tmp_path / "ros1.yaml"
    ros1.write_text("DWAPlannerROS: {max_vel_x: 0.3}\n")
    with pytest.raises(ParamsError, match="no 'ros__parameters' found"):
        read_nav2_params(ros1)


def test_nav2_behavior_server_limits_become_recovery_ports(tmp_path):
    from executive.tree_loader import load_tree_file
    p = tmp_path / "p.yaml"
    p.write_text(textwrap.dedent("""\
        behavior_server:
          ros__parameters:
            cycle_frequency: 10.0
            simulate_ahead_time: 1.5
            max_rotational_vel: 0.5
        """))
    c = load_config_sources(ConfigSources(nav2_params=[str(p)]))
    assert c.origins[("behavior_server", "max_rotational_vel")] == f"{p}:5"
    defaults = c.port_defaults()
    assert defaults["Spin"] == {"simulate_ahead_time": 1.5, "max_rotational_vel": 0.5}
    assert defaults["BackUp"] == {"simulate_ahead_time": 1.5}
    assert any("behavior_server: cycle_frequency" in n.text for n in c.report
               if n.level == "ignored")
    tree = tmp_path / "t.yaml"
    tree.write_text(textwrap.dedent("""\
        main_tree: T
        trees:
          T:
            Sequence:
              children:
                - Spin: {name: own, spin_dist: 1.0}
                - Spin: {name: set, spin_dist: 1.0, max_rotational_vel: 0.8}
                - BackUp: {backup_dist: 0.1, backup_speed: 0.05}
        """))
    root = load_tree_file(tree, namespace="/bs_test", port_defaults=defaults).root
    nodes = {n.name: n for n in root.iterate()}
    assert nodes["own"].get_input("max_rotational_vel") == 0.5      # from behavior_server
    assert nodes["own"].get_input("simulate_ahead_time") == 1.5
    assert nodes["set"].get_input("max_rotational_vel") == 0.8      # the tree's own value wins
    assert nodes["BackUp"].get_input("simulate_ahead_time") == 1.5
    plain = load_tree_file(tree, namespace="/bs_test2").root
    assert {n.name: n for n in plain.iterate()}["own"].get_input("max_rotational_vel") == 1.0
