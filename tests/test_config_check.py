"""``mission config check``: the merged config with the origin of each value, and every error,
warning, note and ignored key at once."""

from __future__ import annotations

from executive.cli import main


def _run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_config_check_lists_values_with_origins_and_all_findings(tmp_path, capsys):
    mb = tmp_path / "move_base.yaml"
    mb.write_text("controller_frequency: 8.0\n"
                  "DWAPlannerROS:\n"
                  "  max_rot_vel: 1.1\n"
                  "  vy_samples: 0\n"
                  "  publish_traj_pc: true\n")
    common = tmp_path / "common.yaml"
    common.write_text("robot_radius: 0.2\ninflation_radius: 0.4\n")
    code, out, _ = _run(capsys, "config", "check", "--params", str(mb),
                        "--params", f"{common}:local_costmap")
    assert code == 0
    assert f"controller_frequency: 8.0  # {mb}:1" in out
    assert f"max_vel_theta: 1.1  # {mb}:3" in out            # renamed, same origin
    assert f"vy_samples: 1  # {mb}:4" in out                 # clamped
    assert f"robot_radius: 0.2  # {common}:1" in out
    assert f"{mb}:3: warning: DWAPlannerROS: 'max_rot_vel' is deprecated: use " \
           "'max_vel_theta'" in out
    assert f"{mb}:5: ignored: DWAPlannerROS: 'publish_traj_pc'" in out
    assert out.rstrip().endswith("0 error(s), 2 warning(s)")
    # errors: all of them, each with file:line, exit status 1
    bad = tmp_path / "bad.yaml"
    bad.write_text("controler_frequency: 5\nDWAPlannerROS:\n  sim_time: -1\n  vx_smaples: 3\n")
    code, out, _ = _run(capsys, "config", "check", "--params", str(bad))
    assert code == 1
    assert f"{bad}:1: error: move_base: unknown parameter 'controler_frequency' (did you " \
           "mean 'controller_frequency'?)" in out
    assert f"{bad}:3: warning: DWAPlannerROS: 'sim_time' = -1 is clamped to 0, as ROS " \
           "does" in out
    assert f"{bad}:4: error: DWAPlannerROS: unknown parameter 'vx_smaples' (did you mean " \
           "'vx_samples'?)" in out
    assert "# errors (2)" in out and out.rstrip().endswith("2 error(s), 1 warning(s)")
    # the navbt robot YAML has lines too
    code, out, _ = _run(capsys, "config", "check", "--quiet")
    assert code == 0 and out.strip().endswith("0 error(s), 0 warning(s)")


def test_run_and_validate_take_ros_options(tmp_path, capsys):
    mb = tmp_path / "mb.yaml"
    mb.write_text("DWAPlannerROS: {max_vel_xx: 1.0}\n")
    code, _, err = _run(capsys, "run", "trees/move_base.yaml", "--params", str(mb),
                        "--map", "nowhere.yaml", "--goal", "1,1,0")
    assert code == 1
    assert err.strip() == (f"mission run: {mb}:1: DWAPlannerROS: unknown parameter "
                           "'max_vel_xx' (did you mean 'max_vel_x'?)")
    code, out, err = _run(capsys, "validate", "trees/move_base.yaml", "--params", str(mb))
    assert code == 1 and "max_vel_xx" in err
    mb.write_text("DWAPlannerROS: {max_vel_x: 0.4}\n")
    code, out, err = _run(capsys, "validate", "trees/move_base.yaml", "--params", str(mb))
    assert code == 0 and f"{mb}: ok" in out
