"""The robot config: bundled default, ROS namespaces, errors that name file/namespace/parameter."""

from __future__ import annotations

import pytest

from executive.config import ConfigError, DEFAULT_CONFIG, config_from_mapping, load_config


def test_default_config_loads():
    c = load_config()
    assert c.source == str(DEFAULT_CONFIG)
    assert c.move_base.controller_frequency == 10.0
    assert c.control_period() == pytest.approx(0.1)
    assert c.local_planner_namespace() == "DWAPlannerROS"
    assert c.global_planner_namespace() == "NavfnROS"
    assert c.circumscribed_radius() == pytest.approx((0.25 ** 2 + 0.22 ** 2) ** 0.5)


def test_ros_defaults_when_absent():
    c = config_from_mapping({}, "x.yaml")
    mb = c.move_base
    assert (mb.controller_frequency, mb.planner_patience, mb.controller_patience) == (20.0, 5.0, 15.0)
    assert mb.max_planning_retries == -1 and mb.oscillation_timeout == 0.0
    assert mb.base_global_planner == "navfn/NavfnROS"
    assert mb.base_local_planner == "base_local_planner/TrajectoryPlannerROS"


def test_unknown_namespace_suggests():
    with pytest.raises(ConfigError, match=r"x.yaml: unknown namespace 'move_bas' \(did you mean "
                                          r"'move_base'\?\)"):
        config_from_mapping({"move_bas": {}}, "x.yaml")


def test_unknown_parameter_names_file_namespace_parameter():
    with pytest.raises(ConfigError, match=r"r.yaml: move_base: unknown parameter "
                                          r"'controler_frequency' \(did you mean "
                                          r"'controller_frequency'\?\)"):
        config_from_mapping({"move_base": {"controler_frequency": 5}}, "r.yaml")


def test_out_of_range_and_wrong_type():
    with pytest.raises(ConfigError, match=r"r.yaml: move_base: parameter 'controller_frequency' "
                                          r"= -1.0 is below its minimum"):
        config_from_mapping({"move_base": {"controller_frequency": -1}}, "r.yaml")
    with pytest.raises(ConfigError, match=r"r.yaml: safety: parameter 'max_vel_x' must be a number"):
        config_from_mapping({"safety": {"max_vel_x": "fast"}}, "r.yaml")
    with pytest.raises(ConfigError, match=r"base_local_planner' = 'teb' is not one of"):
        config_from_mapping({"move_base": {"base_local_planner": "teb"}}, "r.yaml")


def test_footprint_checks_and_radius():
    with pytest.raises(ConfigError, match="footprint' needs at least 3 points"):
        config_from_mapping({"robot": {"footprint": [[0, 0], [1, 1]]}}, "r.yaml")
    with pytest.raises(ConfigError, match=r"point 1 must be \[x, y\]"):
        config_from_mapping({"robot": {"footprint": [[0, 0], [1], [1, 1]]}}, "r.yaml")
    with pytest.raises(ConfigError, match="robot_radius > 0"):
        config_from_mapping({"robot": {"footprint": []}}, "r.yaml")
    c = config_from_mapping({"robot": {"footprint": [], "robot_radius": 0.2}}, "r.yaml")
    assert len(c.footprint()) == 16 and c.circumscribed_radius() == pytest.approx(0.2)


def test_devices_short_form():
    c = config_from_mapping({"robot": {"devices": {"base": "kobuki:///dev/ttyUSB0",
                                                   "laser": "urg04lx:///dev/ttyACM0"}}}, "r.yaml")
    assert c.robot.devices == "hw" and c.robot.base == "kobuki:///dev/ttyUSB0"
    with pytest.raises(ConfigError, match="unknown device 'lazer'"):
        config_from_mapping({"robot": {"devices": {"lazer": "x"}}}, "r.yaml")
    with pytest.raises(ConfigError, match="'devices' must be 'sim', 'hw'"):
        config_from_mapping({"robot": {"devices": "gazebo"}}, "r.yaml")


def test_file_errors(tmp_path):
    with pytest.raises(ConfigError, match=r"nope.yaml: cannot read robot config"):
        load_config(tmp_path / "nope.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("robot:\n  footprint: [1, 2\n")
    with pytest.raises(ConfigError, match=r"bad.yaml:\d+: not valid YAML"):
        load_config(bad)
    lst = tmp_path / "list.yaml"
    lst.write_text("- 1\n- 2\n")
    with pytest.raises(ConfigError, match="must be a mapping of namespaces"):
        load_config(lst)
    unsafe = tmp_path / "unsafe.yaml"
    unsafe.write_text("robot: !!python/object/apply:os.system ['true']\n")
    with pytest.raises(ConfigError, match="not valid YAML"):
        load_config(unsafe)


def test_component_namespace_checked_by_its_own_table():
    pytest.importorskip("navcore.planners.navfn")
    c = config_from_mapping({"NavfnROS": {"default_tolerance": 0.5}}, "r.yaml")
    assert c.parameters["NavfnROS"].default_tolerance == 0.5
    assert "NavfnROS" in c.all_parameters()
    with pytest.raises(ConfigError, match=r"r.yaml: NavfnROS: unknown parameter 'alow_unknown' "
                                          r"\(did you mean 'allow_unknown'\?\)"):
        config_from_mapping({"NavfnROS": {"alow_unknown": True}}, "r.yaml")


def test_sim_namespace_checked_by_simulator():
    pytest.importorskip("hw.sim.config")
    c = load_config()
    assert c.ns("sim")["footprint"] == c.robot.footprint
    with pytest.raises(ConfigError, match=r"r.yaml: sim: unknown parameter 'max_vel_xx'"):
        config_from_mapping({"sim": {"max_vel_xx": 1.0}}, "r.yaml")
    with pytest.raises(ConfigError, match=r"r.yaml: sim.laser: unknown parameter 'beam'"):
        config_from_mapping({"sim": {"laser": {"beam": 10}}}, "r.yaml")


def test_costmap_namespaces_checked_by_building_them():
    pytest.importorskip("navcore.costmap.layered")
    with pytest.raises(ConfigError, match=r"r.yaml: local_costmap.*unknown parameter 'widht'"):
        config_from_mapping({"local_costmap": {"widht": 3.0}}, "r.yaml")
    with pytest.raises(ConfigError, match=r"r.yaml: global_costmap/inflation_layer: .*"
                                          r"'inflation_radius'"):
        config_from_mapping({"global_costmap": {"plugins": ["inflation_layer"],
                                                "inflation_layer": {"inflation_radius": -1}}},
                            "r.yaml")


@pytest.mark.parametrize("doc,needle", [
    ({"amcl": {"min_particles": 500, "max_particles": 100}}, "must not exceed max_particles"),
    ({"amcl": {"max_particles": 100_000_000}}, "'max_particles' = 100000000 is above"),
    ({"CarrotPlanner": {"step_size": -1.0}}, "CarrotPlanner: parameter 'step_size'"),
    ({"TrajectoryPlannerROS": {"sim_time": -1.0}}, "TrajectoryPlannerROS: parameter 'sim_time'"),
    ({"robot": {"devices": {"base": 5}}}, "devices: base must be a URL"),
    ({"local_costmap": {"rolling_window": True, "width": 1000.0, "height": 1000.0}},
     "4e+08 cells, more than the limit"),
    ({"safety": {"sensor_timeout": float("inf")}}, "'sensor_timeout' must be finite"),
])
def test_what_building_would_refuse_is_refused_at_load(doc, needle):
    import tracemalloc
    tracemalloc.start()
    try:
        with pytest.raises(ConfigError, match=needle.replace("(", r"\(").replace("+", r"\+")):
            config_from_mapping(doc, "r.yaml")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50e6  # the 1000 m costmap is refused by arithmetic, not by building it


def test_frames_and_topics_of_a_costmap_are_one_ignored_note_at_the_first(tmp_path):
    path = tmp_path / "robot.yaml"
    path.write_text(
        "global_costmap:\n"
        "  rolling_window: false\n"
        "  global_frame: map\n"
        "  plugins:\n"
        "    - {name: obstacles, type: 'costmap_2d::ObstacleLayer'}\n"
        "  obstacles:\n"
        "    observation_sources: scan\n"
        "    scan: {sensor_frame: laser, topic: /scan, data_type: LaserScan}\n"
        "local_costmap:\n"
        "  rolling_window: true\n"
        "  observation_sources: scan\n"   # pre-Hydro: the sources at the costmap's top level
        "  scan: {topic: /scan, data_type: LaserScan}\n")
    notes = [str(n) for n in load_config(path).report if "frames, topics" in n.text]
    assert notes == [
        f"{path}:3: ignored: global_costmap: frames, topics and publishing have no effect here "
        "(components are wired directly, in one frame): global_frame, obstacles/scan/sensor_frame, "
        "obstacles/scan/topic",
        f"{path}:12: ignored: local_costmap: frames, topics and publishing have no effect here "
        "(components are wired directly, in one frame): scan/topic"]
