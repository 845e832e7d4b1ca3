"""A public robot's move_base setup loads unchanged: Clearpath's Husky (github husky/husky,
husky_navigation on noetic-devel, commit dff7c81: launch/move_base.launch, config/planner.yaml,
costmap_common.yaml, costmap_local.yaml, costmap_global_static.yaml, costmap_global_laser.yaml).

The files are rebuilt here, in a temporary package folder, with the same layout, keys and values
(written out below, not copied): its launch file passes args, loads the common costmap file into
both costmaps, names its layers in separate files, sets the local size with <param>, selects the
global costmap with if/unless; planner.yaml carries a move_base misspelling, deprecated DWA names
(acc_lim_th, max_vel_rot, min_vel_rot) and TrajectoryPlannerROS's pdist_scale/gdist_scale.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from executive.config import ConfigSources, load_config_sources

HUSKY = {
    "launch/move_base.launch": """\
        <?xml version="1.0"?>
        <launch>

          <arg name="no_static_map" default="false"/>

          <arg name="base_global_planner" default="navfn/NavfnROS"/>
          <arg name="base_local_planner" default="dwa_local_planner/DWAPlannerROS"/>
          <!-- <arg name="base_local_planner" default="base_local_planner/TrajectoryPlannerROS"/> -->

          <node pkg="move_base" type="move_base" respawn="false" name="move_base" output="screen">

            <param name="base_global_planner" value="$(arg base_global_planner)"/>
            <param name="base_local_planner" value="$(arg base_local_planner)"/>
            <rosparam file="$(find husky_navigation)/config/planner.yaml" command="load"/>

            <!-- observation sources located in costmap_common.yaml -->
            <rosparam file="$(find husky_navigation)/config/costmap_common.yaml" command="load" ns="global_costmap" />
            <rosparam file="$(find husky_navigation)/config/costmap_common.yaml" command="load" ns="local_costmap" />

            <!-- local costmap, needs size -->
            <rosparam file="$(find husky_navigation)/config/costmap_local.yaml" command="load" ns="local_costmap" />
            <param name="local_costmap/width" value="10.0"/>
            <param name="local_costmap/height" value="10.0"/>

            <!-- static global costmap, static map provides size -->
            <rosparam file="$(find husky_navigation)/config/costmap_global_static.yaml" command="load" ns="global_costmap" unless="$(arg no_static_map)"/>

            <!-- global costmap with laser, for odom_navigation_demo -->
            <rosparam file="$(find husky_navigation)/config/costmap_global_laser.yaml" command="load" ns="global_costmap" if="$(arg no_static_map)"/>
            <param name="global_costmap/width" value="100.0" if="$(arg no_static_map)"/>
            <param name="global_costmap/height" value="100.0" if="$(arg no_static_map)"/>
          </node>

        </launch>
        """,
    "config/planner.yaml": """\
        controller_frequency: 5.0
        recovery_behaviour_enabled: true

        NavfnROS:
          allow_unknown: true
          default_tolerance: 0.1

        TrajectoryPlannerROS:
          acc_lim_x: 2.5
          acc_lim_theta:  3.2
          max_vel_x: 1.0
          min_vel_x: 0.0
          max_vel_theta: 1.0
          min_vel_theta: -1.0
          min_in_place_vel_theta: 0.2
          holonomic_robot: false
          escape_vel: -0.1
          yaw_goal_tolerance: 0.1
          xy_goal_tolerance: 0.2
          latch_xy_goal_tolerance: false
          sim_time: 2.0
          sim_granularity: 0.02
          angular_sim_granularity: 0.02
          vx_samples: 6
          vtheta_samples: 20
          controller_frequency: 20.0
          meter_scoring: true
          occdist_scale:  0.1
          pdist_scale: 0.75
          gdist_scale: 1.0
          heading_lookahead: 0.325
          heading_scoring: false
          heading_scoring_timestep: 0.8
          dwa: true
          simple_attractor: false
          publish_cost_grid_pc: true
          oscillation_reset_dist: 0.25
          escape_reset_dist: 0.1
          escape_reset_theta: 0.1

        DWAPlannerROS:
          acc_lim_x: 2.5
          acc_lim_y: 0
          acc_lim_th: 3.2
          max_vel_x: 0.5
          min_vel_x: 0.0
          max_vel_y: 0
          min_vel_y: 0
          max_vel_trans: 0.5
          min_vel_trans: 0.1
          max_vel_rot: 1.0
          min_vel_rot: 0.2
          yaw_goal_tolerance: 0.1
          xy_goal_tolerance: 0.2
          latch_xy_goal_tolerance: false
        """,
    "config/costmap_common.yaml": """\
        footprint: [[-0.5, -0.33], [-0.5, 0.33], [0.5, 0.33], [0.5, -0.33]]
        footprint_padding: 0.01

        robot_base_frame: base_link
        update_frequency: 4.0
        publish_frequency: 3.0
        transform_tolerance: 0.5

        resolution: 0.05

        obstacle_range: 5.5
        raytrace_range: 6.0

        #layer definitions
        static:
            map_topic: /map
            subscribe_to_updates: true

        obstacles_laser:
            observation_sources: laser
            laser: {data_type: LaserScan, clearing: true, marking: true, topic: front/scan, inf_is_valid: true}

        inflation:
            inflation_radius: 1.0
        """,
    "config/costmap_local.yaml": """\
        global_frame: odom
        rolling_window: true

        plugins:
          - {name: obstacles_laser,           type: "costmap_2d::ObstacleLayer"}
          - {name: inflation,                 type: "costmap_2d::InflationLayer"}
        """,
    "config/costmap_global_static.yaml": """\
        global_frame: map
        rolling_window: false
        track_unknown_space: true

        plugins:
          - {name: static,                  type: "costmap_2d::StaticLayer"}
          - {name: inflation,               type: "costmap_2d::InflationLayer"}
        """,
    "config/costmap_global_laser.yaml": """\
        global_frame: odom
        rolling_window: true
        track_unknown_space: true

        plugins:
          - {name: obstacles_laser,           type: "costmap_2d::ObstacleLayer"}
          - {name: inflation,                 type: "costmap_2d::InflationLayer"}
        """,
}


@pytest.fixture()
def husky(tmp_path) -> Path:
    root = tmp_path / "husky_navigation"
    for name, text in HUSKY.items():
        p = root / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(textwrap.dedent(text))
    return root / "launch" / "move_base.launch"


@pytest.mark.parametrize("no_static_map", ("false", "true"))
def test_husky_move_base_loads_unchanged(husky, no_static_map):
    c = load_config_sources(ConfigSources(launch=str(husky),
                                          args={"no_static_map": no_static_map}))
    config = husky.parent.parent / "config"
    assert not [n for n in c.report if n.level == "error"]
    body = [[-0.5, -0.33], [-0.5, 0.33], [0.5, 0.33], [0.5, -0.33]]
    assert [list(p) for p in c.footprint()] == body and c.ns("sim")["footprint"] == body
    assert c.move_base.controller_frequency == 5.0
    assert c.move_base.base_local_planner == "dwa_local_planner/DWAPlannerROS"
    dwa = c.parameters["DWAPlannerROS"]
    assert (dwa.acc_lim_theta, dwa.max_vel_theta, dwa.min_vel_theta) == (3.2, 1.0, 0.2)
    tr = c.parameters["TrajectoryPlannerROS"]      # validated although not selected
    assert (tr.path_distance_bias, tr.goal_distance_bias) == (0.75, 1.0)
    assert c.parameters["NavfnROS"].default_tolerance == 0.1
    local = c.ns("local_costmap")
    assert (local["width"], local["height"], local["rolling_window"]) == (10.0, 10.0, True)
    assert "static" not in local                    # not in its plugins: noted, left out
    glob = c.ns("global_costmap")
    names = [p["name"] for p in glob["plugins"]]
    if no_static_map == "true":
        assert names == ["obstacles_laser", "inflation"] and glob["width"] == 100.0
    else:
        assert names == ["static", "inflation"] and glob["track_unknown_space"] is True
    warnings = {n.text for n in c.report if n.level == "warning"}
    planner = f"{config / 'planner.yaml'}"
    assert any("'recovery_behaviour_enabled' is not read" in w for w in warnings)
    for old, new in (("acc_lim_th", "acc_lim_theta"), ("max_vel_rot", "max_vel_theta"),
                     ("min_vel_rot", "min_vel_theta")):
        assert f"DWAPlannerROS: '{old}' is deprecated: use '{new}' (the value is used as " \
               f"'{new}')" in warnings
    assert any(n.where == f"{planner}:2" for n in c.report if n.level == "warning")
    notes = [n for n in c.report if n.level == "note"]
    assert any("layer namespace 'static' is not in 'plugins'" in n.text
               and n.where == f"{config / 'costmap_common.yaml'}:15" for n in notes)
    ignored = " ".join(n.text for n in c.report if n.level == "ignored")
    assert "publish_cost_grid_pc" in ignored


# Willow Garage's PR2 (github PR2/pr2_navigation, kinetic-devel, commit 5be4914):
# pr2_navigation_global/move_base.xml with pr2_navigation_config/move_base/*.yaml and
# pr2_navigation_global/config/*_costmap_params.yaml, rebuilt the same way. The footprint (a
# pentagon) and footprint_padding sit at the move_base level; the DWA file is loaded with
# ns="DWAPlannerROS" and uses old names; the costmaps are the pre-Hydro voxel kind.
PR2 = {
    "pr2_machine/pr2.machine": """\
        <launch>
          <machine name="c1" address="c1" />
          <machine name="c2" address="c2" />
        </launch>
        """,
    "pr2_navigation_global/move_base.xml": """\
        <launch>
          <include file="$(find pr2_machine)/$(env ROBOT).machine" />

          <!-- Bring up the tilt_laser aware version of move_base -->
          <node pkg="pr2_move_base" name="pr2_move_base_node" type="pr2_move_base.py" machine="c2" />

          <!-- Trajectory generator -->
          <node pkg="joint_trajectory_generator" type="joint_trajectory_generator" output="screen"
                name="joint_trajectory_generator" ns="r_arm_controller" >
            <param name="max_acc" value="2.0" />
            <param name="max_vel" value="2.5" />
          </node>

          <node ns="move_base_node/local_costmap" name="voxel_grid_throttle" pkg="topic_tools" type="throttle" machine="c2" args="messages voxel_grid 3.0 voxel_grid_throttled" />

          <node pkg="move_base" type="move_base" name="move_base_node" machine="c2">
            <remap from="odom" to="base_odometry/odom" />
            <remap from="cmd_vel" to="navigation/cmd_vel" />

            <!-- Use the dwa local planner for the PR2 -->
            <param name="base_local_planner" value="dwa_local_planner/DWAPlannerROS" />

            <!-- Load common configuration files -->
            <rosparam file="$(find pr2_navigation_config)/move_base/move_base_params.yaml" command="load" />
            <rosparam file="$(find pr2_navigation_config)/move_base/costmap_common_params.yaml" command="load" ns="global_costmap" />
            <rosparam file="$(find pr2_navigation_config)/move_base/costmap_common_params.yaml" command="load" ns="local_costmap" />
            <rosparam file="$(find pr2_navigation_config)/move_base/dwa_local_planner.yaml" command="load" ns="DWAPlannerROS" />
            <rosparam file="$(find pr2_navigation_config)/move_base/recovery_behaviors.yaml" command="load" />

            <!-- Load global navigation specific parameters -->
            <rosparam file="$(find pr2_navigation_global)/config/local_costmap_params.yaml" command="load" />
            <rosparam file="$(find pr2_navigation_global)/config/global_costmap_params.yaml" command="load" />
          </node>
        </launch>
        """,
    "pr2_navigation_config/move_base/move_base_params.yaml": """\
        footprint: [[-0.325, -0.325], [-0.325, 0.325], [0.325, 0.325], [0.46, 0.0], [0.325, -0.325]]
        controller_frequency: 10.0
        controller_patience: 15.0
        clearing_radius: 0.59
        footprint_padding: 0.015
        oscillation_timeout: 10.0
        oscillation_distance: 0.5
        """,
    "pr2_navigation_config/move_base/costmap_common_params.yaml": """\
        map_type: voxel
        origin_z: 0.0
        z_voxels: 16
        z_resolution: 0.1125
        unknown_cost_value: 0
        unknown_threshold: 8
        mark_threshold: 0
        transform_tolerance: 0.2
        obstacle_range: 2.5
        raytrace_range: 3.0
        inflation_radius: 0.55
        observation_sources: base_scan_marking base_scan tilt_scan ground_object_cloud
        base_scan_marking: {sensor_frame: base_laser_link, topic: /base_scan_marking, data_type: PointCloud2, expected_update_rate: 0.2,
          observation_persistence: 0.0, marking: true, clearing: false, min_obstacle_height: 0.08, max_obstacle_height: 2.0}
        base_scan: {sensor_frame: base_laser_link, topic: /base_scan, data_type: LaserScan, expected_update_rate: 0.2,
                     observation_persistence: 0.0, marking: false, clearing: true, min_obstacle_height: -0.10, max_obstacle_height: 2.0}
        tilt_scan: {sensor_frame: laser_tilt_link, topic: /tilt_scan_interpolated, data_type: LaserScan, expected_update_rate: 0.2,
                     observation_persistence: 0.2, marking: false, clearing: true, min_obstacle_height: -20.00, max_obstacle_height: 40.0}
        ground_object_cloud: {sensor_frame: laser_tilt_link, topic: /ground_object_cloud, data_type: PointCloud2, expected_update_rate: 0.2,
                               observation_persistence: 4.6, marking: true, clearing: false, min_obstacle_height: -0.10, max_obstacle_height: 2.0}
        """,
    "pr2_navigation_config/move_base/dwa_local_planner.yaml": """\
        acc_lim_th: 3.2
        acc_lim_x: 2.5
        acc_lim_y: 2.5
        max_vel_x: 0.55
        min_vel_x: 0.0
        max_vel_y: 0.1
        min_vel_y: -0.1
        max_trans_vel: 0.55
        min_trans_vel: 0.1
        max_rot_vel: 1.0
        min_rot_vel: 0.3
        sim_time: 1.7
        sim_granularity: 0.025
        goal_distance_bias: 32.0
        path_distance_bias: 24.0
        occdist_scale: 0.01
        stop_time_buffer: 0.2
        oscillation_reset_dist: 0.05
        forward_point_distance: 0.325
        scaling_speed: 0.25
        max_scaling_factor: 0.2
        vx_samples: 3
        vy_samples: 10
        vtheta_samples: 20
        xy_goal_tolerance: 0.2
        yaw_goal_tolerance: 0.17
        rot_stopped_vel: 0.01
        trans_stopped_vel: 0.01
        """,
    "pr2_navigation_config/move_base/recovery_behaviors.yaml": """\
        recovery_behaviors:
          - name: 'super_conservative_reset'
            type: 'clear_costmap_recovery/ClearCostmapRecovery'
          - name: 'conservative_reset'
            type: 'clear_costmap_recovery/ClearCostmapRecovery'
          - name: 'aggressive_reset'
            type: 'clear_costmap_recovery/ClearCostmapRecovery'
          - name: 'move_slow_and_clear'
            type: 'move_slow_and_clear/MoveSlowAndClear'

        super_conservative_reset:
          reset_distance: 5.0
        conservative_reset:
          reset_distance: 3.0
        aggressive_reset:
          reset_distance: 1.84
        move_slow_and_clear:
          clearing_distance: 0.5
          limited_trans_speed: 0.25
          limited_rot_speed: 0.45
          limited_distance: 0.3
        """,
    "pr2_navigation_global/config/global_costmap_params.yaml": """\
        global_costmap:
          global_frame: map
          robot_base_frame: base_footprint
          update_frequency: 5.0
          publish_frequency: 0.0
          static_map: true
          rolling_window: false
        """,
    "pr2_navigation_global/config/local_costmap_params.yaml": """\
        local_costmap:
          publish_voxel_map: false
          global_frame: odom_combined
          robot_base_frame: base_footprint
          update_frequency: 5.0
          publish_frequency: 2.0
          static_map: false
          rolling_window: true
          width: 6.0
          height: 6.0
          resolution: 0.025
          origin_x: 0.0
          origin_y: 0.0
        """,
}


def test_pr2_move_base_loads_unchanged(tmp_path, monkeypatch):
    for name, text in PR2.items():
        p = tmp_path / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(textwrap.dedent(text))
    monkeypatch.setenv("ROBOT", "pr2")
    launch = tmp_path / "pr2_navigation_global" / "move_base.xml"
    c = load_config_sources(ConfigSources(launch=str(launch), package_path=[str(tmp_path)]))
    assert not [n for n in c.report if n.level == "error"]
    pentagon = [[-0.325, -0.325], [-0.325, 0.325], [0.325, 0.325], [0.46, 0.0], [0.325, -0.325]]
    # the move_base-level footprint: found by both costmaps (searchParam), the robot's body
    assert [list(p) for p in c.footprint()] == pentagon and c.ns("sim")["footprint"] == pentagon
    assert c.ns("local_costmap")["footprint"] == pentagon
    assert c.move_base.clearing_radius == 0.59 and c.move_base.controller_frequency == 10.0
    dwa = c.parameters["DWAPlannerROS"]
    assert (dwa.max_vel_trans, dwa.max_vel_theta, dwa.min_vel_theta, dwa.acc_lim_theta,
            dwa.theta_stopped_vel, dwa.vth_samples) == (0.55, 1.0, 0.3, 3.2, 0.01, 20)
    warnings = "\n".join(str(n) for n in c.report if n.level == "warning")
    params = tmp_path / "pr2_navigation_config" / "move_base"
    # footprint_padding at the move_base level: costmap_2d reads it only in the costmaps
    assert f"{params / 'move_base_params.yaml'}:5: warning: 'footprint_padding' is a costmap " \
           "parameter" in warnings
    # the DWA does not read base_local_planner's vtheta_samples (vth_samples keeps 20 anyway)
    assert f"{params / 'dwa_local_planner.yaml'}:24: warning: DWAPlannerROS: 'vtheta_samples' " \
           "is not read" in warnings
    assert "'max_rot_vel' is deprecated: use 'max_vel_theta'" in warnings
    local = c.ns("local_costmap")
    assert (local["resolution"], local["z_voxels"], local["map_type"]) == (0.025, 16, "voxel")
    notes = " ".join(n.text for n in c.report if n.level == "note")
    assert "move_slow_and_clear (move_slow_and_clear/MoveSlowAndClear -> (none))" in notes
    ignored = " ".join(n.text for n in c.report if n.level == "ignored")
    assert "node 'pr2_move_base_node' (pr2_move_base/pr2_move_base.py)" in ignored
    assert "<machine>" in ignored and "'move_slow_and_clear'" in ignored
