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
