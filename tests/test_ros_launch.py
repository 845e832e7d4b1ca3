"""roslaunch files: TurtleBot3's move_base.launch unchanged, and the roslaunch subset on files
written here (args, substitutions, groups, includes, params, rosparam, ignored tags, errors)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest
import yaml

from executive.config import ConfigError, ConfigSources, load_config_sources
from executive.ros_launch import read_launch
from executive.param_files import ParamsError

MODELS = ("burger", "waffle", "waffle_pi")


@pytest.fixture(scope="module")
def tb3(shared_data) -> Path:
    root = shared_data / "ros_params" / "turtlebot3_navigation"
    if not (root / "launch" / "move_base.launch").exists():
        pytest.skip(f"TurtleBot3 files not found under {root}")
    return root


@pytest.mark.parametrize("model", MODELS)
def test_turtlebot3_launch_loads_unchanged(tb3, model, monkeypatch):
    monkeypatch.delenv("TURTLEBOT3_MODEL", raising=False)
    launch = tb3 / "launch" / "move_base.launch"
    c = load_config_sources(ConfigSources(launch=str(launch), args={"model": model}))
    declared = yaml.safe_load((tb3 / "param" / f"costmap_common_params_{model}.yaml")
                              .read_text())["footprint"]
    assert [list(p) for p in c.footprint()] == declared
    assert c.ns("sim")["footprint"] == declared          # the simulated body
    assert c.ns("local_costmap")["footprint"] == declared
    assert c.move_base.base_local_planner == "dwa_local_planner/DWAPlannerROS"
    assert c.move_base.controller_frequency == 10.0 and c.move_base.planner_frequency == 5.0
    dwa = c.parameters["DWAPlannerROS"]
    assert dwa.vy_samples == 1            # 0 in the file: clamped as dynamic_reconfigure does
    assert dwa.min_vel_x == pytest.approx(-0.22 if model == "burger" else -0.26)
    assert not [n for n in c.report if n.level == "error"]
    warnings = [str(n) for n in c.report if n.level == "warning"]
    assert len(warnings) == 1 and f"dwa_local_planner_params_{model}.yaml:29" in warnings[0]
    assert "'vy_samples' = 0 is clamped to 1" in warnings[0]
    ignored = " ".join(n.text for n in c.report if n.level == "ignored")
    assert "publish_traj_pc" in ignored and "publish_cost_grid_pc" in ignored
    assert "<remap> (move_base.launch:17, 18)" in ignored
    # move_base_params.yaml values the tree decides here, listed (trees/move_base.yaml has
    # move_base's defaults): planner_frequency 5.0, oscillation_timeout 10.0, ...
    assert "move_base: planner_frequency = 5.0 is not applied: in navbt the tree decides it" \
        in ignored and "move_base: oscillation_distance = 0.2 is not applied" in ignored
    # origins: each value names the file and line it came from
    assert c.origins[("DWAPlannerROS", "max_vel_x")].endswith(
        f"dwa_local_planner_params_{model}.yaml:4")
    assert c.origins[("move_base", "base_local_planner")].endswith("move_base.launch:10")
    assert c.origins[("global_costmap", "update_frequency")].endswith(
        "global_costmap_params.yaml:5")


def test_turtlebot3_launch_model_from_env_or_error(tb3, monkeypatch):
    launch = str(tb3 / "launch" / "move_base.launch")
    monkeypatch.delenv("TURTLEBOT3_MODEL", raising=False)
    with pytest.raises(ConfigError) as e:
        load_config_sources(ConfigSources(launch=launch))
    lines = str(e.value).splitlines()
    assert len(lines) == 1, lines                 # no cascade of $(arg model) errors
    assert lines[0].startswith(f"{launch}:3: $(env TURTLEBOT3_MODEL): environment variable")
    assert "--arg model=VALUE" in lines[0]
    monkeypatch.setenv("TURTLEBOT3_MODEL", "waffle")
    c = load_config_sources(ConfigSources(launch=launch))
    assert c.footprint()[0] == (-0.205, -0.155)


def test_turtlebot3_move_forward_only(tb3):
    launch = str(tb3 / "launch" / "move_base.launch")
    c = load_config_sources(ConfigSources(launch=launch, args={"model": "burger",
                                                               "move_forward_only": "true"}))
    assert c.parameters["DWAPlannerROS"].min_vel_x == 0.0
    assert c.origins[("DWAPlannerROS", "min_vel_x")] == f"{launch}:19"


def _write(root: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        p = root / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(textwrap.dedent(text))


def test_roslaunch_subset(tmp_path, monkeypatch):
    monkeypatch.setenv("NAVBT_TEST_RATE", "7.0")
    monkeypatch.delenv("NAVBT_UNSET", raising=False)
    _write(tmp_path, {
        "robot_nav/launch/nav.launch": """\
            <launch>
              <arg name="fast" default="false"/>
              <arg name="planner" value="navfn/NavfnROS"/>
              <arg name="radius"/>
              <include file="$(find robot_nav)/launch/move_base.launch">
                <arg name="rate" value="$(optenv NAVBT_TEST_RATE 5.0)"/>
                <arg name="radius" value="$(arg radius)"/>
              </include>
              <group ns="move_base" if="$(arg fast)">
                <param name="DWAPlannerROS/max_vel_x" value="0.9"/>
              </group>
              <group ns="move_base" unless="$(arg fast)">
                <param name="DWAPlannerROS/max_vel_x" value="0.4"/>
              </group>
              <param name="/use_sim_time" value="true"/>
              <node pkg="map_server" type="map_server" name="map_server" args="map.yaml"/>
              <machine name="m" address="localhost"/>
            </launch>
            """,
        "robot_nav/launch/move_base.launch": """\
            <launch>
              <arg name="rate"/>
              <arg name="radius" default="0.3"/>
              <node pkg="move_base" type="move_base" name="move_base">
                <param name="controller_frequency" value="$(arg rate)" type="double"/>
                <param name="base_global_planner" value="navfn/NavfnROS"/>
                <param name="base_local_planner" value="dwa_local_planner/DWAPlannerROS"/>
                <param name="planner_patience" value="4"/>
                <param name="recovery_behavior_enabled" value="True"/>
                <rosparam file="$(find robot_nav)/config/common.yaml" command="load" ns="local_costmap"/>
                <rosparam ns="local_costmap" subst_value="true">
                  robot_radius: $(arg radius)
                  rolling_window: true
                </rosparam>
                <rosparam subst_value="true" param="DWAPlannerROS/acc_lim_x">$(arg radius)</rosparam>
                <rosparam command="delete" param="local_costmap/obsolete"/>
                <remap from="cmd_vel" to="base/cmd_vel"/>
              </node>
              <node pkg="amcl" type="amcl" name="localizer">
                <param name="min_particles" value="123"/>
              </node>
            </launch>
            """,
        "robot_nav/config/common.yaml": """\
            obstacle_range: 2.0
            obsolete: 1
            """,
    })
    launch = tmp_path / "robot_nav" / "launch" / "nav.launch"
    got = read_launch(launch, {"radius": "0.25"})
    assert got.move_base_ns == ("move_base",) and got.amcl_ns == ("localizer",)
    mb = got.tree.get(("move_base",))
    assert mb["controller_frequency"] == 7.0          # optenv, passed as an include arg
    assert mb["planner_patience"] == 4 and mb["recovery_behavior_enabled"] is True
    assert mb["DWAPlannerROS"] == {"max_vel_x": 0.4, "acc_lim_x": 0.25}
    assert mb["local_costmap"]["robot_radius"] == 0.25   # inline YAML with subst_value
    assert "obsolete" not in mb["local_costmap"]
    assert got.tree.origin(("move_base", "local_costmap", "obstacle_range")) == \
        f"{tmp_path / 'robot_nav' / 'config' / 'common.yaml'}:1"
    assert got.tree.origin(("move_base", "local_costmap", "rolling_window")).endswith(
        "move_base.launch:13")
    ignored = [n.text for n in got.notes if n.level == "ignored"]
    assert len(ignored) == 1
    for what in ("<remap> (move_base.launch:17)", "<machine>",
                 "node 'map_server' (map_server/map_server, args 'map.yaml')",
                 "parameter '/use_sim_time'"):
        assert what in ignored[0]
    assert not [n for n in got.notes if n.level == "error"]
    c = load_config_sources(ConfigSources(launch=str(launch), args={"radius": "0.25",
                                                                   "fast": "true"}))
    assert c.parameters["DWAPlannerROS"].max_vel_x == 0.9
    assert c.parameters["amcl"].min_particles == 123


def test_roslaunch_errors_name_file_and_line(tmp_path):
    _write(tmp_path, {"bad.launch": """\
        <launch>
          <arg name="need"/>
          <arg name="x" default="$(eval 1 + 1)"/>
          <param name="a" value="$(nope b)"/>
          <param name="n" value="abc" type="int"/>
          <group if="maybe"><param name="q" value="1"/></group>
          <rosparam file="missing.yaml"/>
          <arg name="twice" default="1"/>
          <arg name="twice" default="2"/>
          <group><arg name="inner" default="1"/></group>
          <arg name="inner" default="2"/>
          <param name="p" value="1" if="true" unless="false"/>
        </launch>
        """})
    f = tmp_path / "bad.launch"
    got = read_launch(f, {"nedd": "1"})
    errors = [str(n) for n in got.notes if n.level == "error"]
    assert f"{f}:2: arg 'need' has no value: give --arg need=VALUE" in errors
    assert any(e.startswith(f"{f}:3: $(eval ...) is not supported") for e in errors)
    assert any(e.startswith(f"{f}:4: $(nope b): unknown or unsupported substitution")
               for e in errors)
    assert any(e.startswith(f"{f}:5: <param value=\"abc\" type=\"int\">") for e in errors)
    assert any(e.startswith(f"{f}:6: <group if=...>: 'maybe' is not a boolean") for e in errors)
    assert f"{f}:7: <rosparam file=...>: missing.yaml: cannot read rosparam file: not found" \
        in errors
    assert f"{f}:9: arg 'twice' is declared twice (first at {f}:8); roslaunch refuses that" \
        in errors
    assert not any("'inner'" in e for e in errors)   # a group's args end with the group
    assert f"{f}:12: <param>: give 'if' or 'unless', not both (roslaunch refuses that)" \
        in errors
    assert any("arg 'nedd' is given but" in e and "(did you mean 'need'?)" in e for e in errors)
    (tmp_path / "broken.launch").write_text("<launch>\n  <param name='a'\n</launch>\n")
    with pytest.raises(ParamsError, match=r"broken.launch:3: not valid XML"):
        read_launch(tmp_path / "broken.launch")
    (tmp_path / "bomb.launch").write_text('<?xml version="1.0"?>\n<!DOCTYPE l [<!ENTITY a '
                                          '"aaaa">]>\n<launch>&a;</launch>\n')
    with pytest.raises(ParamsError, match=r"bomb.launch:2: XML entity declarations are not "
                                          r"allowed"):
        read_launch(tmp_path / "bomb.launch")
    (tmp_path / "inline.launch").write_text("<launch>\n  <rosparam>\n    a: 1\n    b: [1,\n"
                                            "  </rosparam>\n</launch>\n")
    got = read_launch(tmp_path / "inline.launch")
    errors = [str(n) for n in got.notes if n.level == "error"]
    assert len(errors) == 1 and errors[0].startswith(
        f"{tmp_path / 'inline.launch'}:5: <rosparam>: not valid YAML")
