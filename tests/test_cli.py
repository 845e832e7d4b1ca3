"""The ``mission`` CLI: every subcommand's help, its output, and its one-line errors."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import py_trees
import pytest

from executive.cli import SUBCOMMANDS, main
from navcore.clock import SimClock
from navcore.types import Pose2D

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def run_cli(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("name", sorted(SUBCOMMANDS))
def test_every_subcommand_has_help(name, capsys):
    with pytest.raises(SystemExit) as e:
        main([name, "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith(f"usage: mission {name}")


def test_no_command_prints_help(capsys):
    code, out, _ = run_cli(capsys)
    assert code == 2 and "demo" in out and "scenario" in out


def test_help_does_not_import_heavy_modules():
    code = ("import sys, executive.cli as c; c.build_parser(); "
            "heavy = [m for m in ('numpy', 'numba', 'py_trees', 'PIL') if m in sys.modules]; "
            "print(','.join(heavy))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == ""


# ------------------------------------------------------------------ replay
def _record_run(tmp_path) -> str:
    from tests.test_executive import DriveToGoal, Spin, wall_ahead_robot
    from executive.executive import Executive
    from executive.recorder import Recorder
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    with open(run_dir / "ticks.jsonl", "w") as f:
        root = py_trees.composites.Sequence("seq", memory=True,
                                            children=[Spin("spin"), DriveToGoal("drive")])
        ex = Executive(py_trees.trees.BehaviourTree(root), wall_ahead_robot(), SimClock(), 0.1,
                       recorder=Recorder(f))
        result = ex.run([Pose2D(1.0, 0.0)], time_limit=30)
    assert result.succeeded
    return str(run_dir)


def test_replay_shows_state_at_tick(tmp_path, capsys):
    run_dir = _record_run(tmp_path)
    code, out, err = run_cli(capsys, "replay", run_dir, "--tick", "1")
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0].startswith("tick 1/") and "root=RUNNING" in lines[0]
    assert "seq" in lines[1] and "RUNNING" in lines[1]
    assert "spin" in lines[2] and "RUNNING" in lines[2]
    assert "drive" in lines[3] and "[-]" in lines[3]
    code, out, _ = run_cli(capsys, "replay", run_dir)
    assert code == 0 and "outcome: succeeded" in out
    assert "drive" in out and "SUCCESS" in out


def test_replay_errors(tmp_path, capsys):
    code, _, err = run_cli(capsys, "replay", str(tmp_path / "missing"))
    assert code == 1 and err.startswith("mission replay: ") and "no such tick log" in err
    run_dir = _record_run(tmp_path)
    code, _, err = run_cli(capsys, "replay", run_dir, "--tick", "99999")
    assert code == 1 and "out of range" in err and len(err.strip().splitlines()) == 1
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"header": {"nodes": []}}\n{oops\n')
    code, _, err = run_cli(capsys, "replay", str(bad))
    assert code == 1 and "bad.jsonl:2: not a JSON line" in err


# ------------------------------------------------------------------ scenario (no run)
def test_scenario_check_and_broken_scenario(tmp_path, capsys):
    good = tmp_path / "good.yaml"
    good.write_text("map:\n  resolution: 0.1\n  ascii: |\n    #######\n    #S...G#\n    #######\n")
    code, out, err = run_cli(capsys, "scenario", "check", str(good))
    assert code == 0, err
    assert "good.yaml: ok (good, 1 goal(s)" in out
    bad = tmp_path / "bad.yaml"
    bad.write_text("map:\n  resolution: 0.1\n  ascii: |\n    #####\n    #S..#\n    #####\n"
                   "expect: {outcom: failed}\n")
    code, _, err = run_cli(capsys, "scenario", "check", str(bad), str(good))
    assert code == 1
    # every problem of the file, each with its line
    assert f"{bad}:7: expect.outcom: unknown key 'outcom' (did you mean 'outcome'?)" in err
    assert f"{bad}:1: goals: not given, and the map has 0 'G' markers (need exactly one)" in err
    bad.write_text("map:\n  resolution: 0.1\n  ascii: |\n    #####\n    #S.G#\n    #####\n"
                   "expect: {outcom: failed}\n")
    # a broken scenario is that scenario's error outcome; the other one still runs
    code, out, _ = run_cli(capsys, "scenario", "run", str(bad), str(good))
    assert code == 1 and "expect.outcom: unknown key 'outcom' (did you mean 'outcome'?)" in out
    assert "good          solved" in out or "good  " in out
    code, out, _ = run_cli(capsys, "scenario", "run", str(tmp_path / "empty_dir_none"))
    assert code == 1 and "cannot read scenario" in out


# ------------------------------------------------------------------ run: errors before moving
def test_run_broken_map_and_config(tmp_path, capsys):
    bad_map = tmp_path / "m.yaml"
    bad_map.write_text("image: nothere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n")
    code, _, err = run_cli(capsys, "run", "trees/x.yaml", "--map", str(bad_map),
                           "--goal", "1,1,0")
    assert code == 1 and err.startswith("mission run: ") and "m.yaml" in err
    # every bad field of the map, one line each (missing negate and thresholds, the image)
    lines = err.strip().splitlines()
    assert len(lines) == 4 and all("m.yaml" in ln for ln in lines) and "Traceback" not in err
    cfg = tmp_path / "robot.yaml"
    cfg.write_text("move_base: {controller_frequency: 0}\n")
    code, _, err = run_cli(capsys, "run", "trees/x.yaml", "--config", str(cfg),
                           "--map", str(bad_map), "--goal", "1,1,0")
    assert code == 1
    assert err.strip() == (f"mission run: {cfg}:1: move_base: parameter 'controller_frequency' = "
                           "0.0 is below its minimum 0.1")


def test_run_bad_goal_syntax(capsys):
    with pytest.raises(SystemExit) as e:
        main(["run", "t.yaml", "--map", "m.yaml", "--goal", "1,x"])
    assert e.value.code == 2
    assert "is not X,Y[,YAW]" in capsys.readouterr().err


def test_map_info_bundled(capsys):
    code, out, _ = run_cli(capsys, "map-info", os.path.join(ROOT, "executive", "data", "maps",
                                                             "office.yaml"))
    assert code == 0 and "cells at 0.05 m" in out


# ------------------------------------------------------------------ tree commands
def test_validate_render_broken_tree(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("main_tree: T\ntrees:\n  T:\n    RateControler: {hz: 1.0, child: {Wait: {}}}\n")
    code, _, err = run_cli(capsys, "validate", str(bad))
    assert code == 1 and err.startswith("mission validate: ") and "bad.yaml" in err
    assert "RateControler" in err
    code, _, err = run_cli(capsys, "render", str(bad))
    assert code == 1 and err.startswith("mission render: ") and "bad.yaml" in err
    code, _, err = run_cli(capsys, "validate", str(tmp_path / "none.yaml"))
    assert code == 1 and "none.yaml: no such tree file" in err


def test_validate_render_convert_shipped_trees(tmp_path, capsys):
    trees_dir = os.path.join(ROOT, "trees")
    files = sorted(os.path.join(trees_dir, f) for f in os.listdir(trees_dir)
                   if f.endswith(".yaml"))
    if not files:
        pytest.skip("no shipped trees yet")
    code, out, err = run_cli(capsys, "validate", *files)
    assert code == 0, err
    assert out.count(": ok (") == len(files)
    code, out, _ = run_cli(capsys, "render", files[0], "-f", "txt")
    assert code == 0 and len(out.splitlines()) > 3
    code, out, _ = run_cli(capsys, "render", files[0], "-f", "dot")
    assert code == 0 and out.startswith("digraph")
    svg = tmp_path / "t.svg"
    code, _, err = run_cli(capsys, "render", files[0], "-f", "svg", "-o", str(svg))
    assert code == 0, err
    assert svg.read_bytes().lstrip().startswith(b"<?xml") and b"<svg" in svg.read_bytes()
    png = tmp_path / "t.png"
    code, _, err = run_cli(capsys, "render", files[0], "-f", "png", "-o", str(png))
    assert code == 0, err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    xml = tmp_path / "t.xml"
    code, _, err = run_cli(capsys, "convert", files[0], "-o", str(xml))
    assert code == 0, err
    assert "<root" in xml.read_text()
    code, out, err = run_cli(capsys, "validate", str(xml))
    assert code == 0, err
    back = tmp_path / "back.yaml"
    code, _, err = run_cli(capsys, "convert", str(xml), "-o", str(back))
    assert code == 0, err
    first = next(ln for ln in back.read_text().splitlines() if not ln.startswith("#"))
    assert first.startswith("main_tree:")   # after the file's comments, kept
    code, out, err = run_cli(capsys, "validate", str(back))
    assert code == 0, err
    code, _, err = run_cli(capsys, "convert", str(tmp_path / "missing.xml"))
    assert code == 1 and "missing.xml: no such tree file" in err


def test_nodes_listing_and_detail(capsys):
    code, out, _ = run_cli(capsys, "nodes")
    assert code == 0 and "RecoveryNode" in out
    code, out, _ = run_cli(capsys, "nodes", "RecoveryNode")
    assert code == 0 and "number_of_retries" in out
    code, _, err = run_cli(capsys, "nodes", "RecoveryNod")
    assert code == 1 and "did you mean 'RecoveryNode'" in err


# ------------------------------------------------------------------ end to end (simulator)
def test_demo_runs_and_writes_run_folder(tmp_path, capsys):
    out_dir = tmp_path / "demo"
    code, out, err = run_cli(capsys, "demo", "--out", str(out_dir))
    assert code == 0, err + out
    lines = out.strip().splitlines()
    assert lines[-1] == str(out_dir)
    assert lines[-2].startswith("succeeded in ") and "collisions: 0" in lines[-2]
    assert "\r" not in out  # the progress line stays quiet when stdout is not a terminal
    # (run.mcap needs the foxglove extra, which the test command installs)
    assert sorted(p.name for p in out_dir.iterdir()) == ["replay.html", "run.mcap", "run.png",
                                                          "summary.json", "ticks.jsonl",
                                                          "timing.jsonl", "tree.svg"]
    summary = json.loads((out_dir / "summary.json").read_text())
    assert summary["outcome"] == "succeeded" and summary["collisions"] == 0
    assert summary["recoveries"], "the demo is a stuck situation: some recovery must fire"
    code, out, _ = run_cli(capsys, "replay", str(out_dir), "--tick", "0")
    assert code == 0 and out.startswith("tick 0/")


def test_run_to_goals_and_errors(tmp_path, capsys):
    tree = os.path.join(ROOT, "trees", "smach_recovery.yaml")
    m = os.path.join(ROOT, "executive", "data", "maps", "two_rooms.yaml")
    rec = tmp_path / "run"
    code, out, err = run_cli(capsys, "run", tree, "--map", m, "--start", "5.5,2.5,0",
                             "--goal", "6.5,1.5,0", "--goal", "5.0,3.5,1.57",
                             "--record", str(rec), "--time-limit", "60")
    assert code == 0, err + out
    assert out.startswith("succeeded: 2/2 goals in ")
    assert (rec / "run.png").exists() and (rec / "summary.json").exists()
    code, _, err = run_cli(capsys, "run", tree, "--map", m, "--goal", "99,99,0")
    assert code == 1 and "--goal 99,99: outside the map" in err
    bad = tmp_path / "bad.yaml"
    bad.write_text("main_tree: T\ntrees:\n  T:\n    Sequence:\n      children:\n"
                   "        - Wiat: {}\n")
    code, _, err = run_cli(capsys, "run", str(bad), "--map", m, "--goal", "6,1,0")
    assert code == 1 and err.startswith("mission run: ") and "bad.yaml" in err
    assert "Wiat" in err and len(err.strip().splitlines()) == 1
    code, _, err = run_cli(capsys, "run", tree, "--map", m, "--goal", "6,1,0", "--hw")
    assert code == 1 and "robot: devices: give {base: URL, laser: URL}" in err


def test_scenario_run_table_and_json(tmp_path, capsys):
    s = tmp_path / "tiny.yaml"
    rows = ["#" * 30] + ["#" + "." * 28 + "#"] * 7 + ["#" + "." * 28 + "#"] * 7 + ["#" * 30]
    rows[8] = "#....S..................G....#"
    art = "".join(f"    {r}\n" for r in rows)
    s.write_text("description: a short straight drive\nmap:\n  resolution: 0.1\n  ascii: |\n"
                 + art + "time_limit: 30\n")
    code, out, err = run_cli(capsys, "scenario", "run", str(s), "--json")
    assert code == 0, err
    (r,) = json.loads(out)
    assert r["scenario"] == "tiny" and r["outcome"] == "succeeded" and r["passed"]
    bad_tree = tmp_path / "t.yaml"
    bad_tree.write_text("main_tree: T\ntrees: {}\n")
    code, _, err = run_cli(capsys, "scenario", "run", str(s), "--tree", str(bad_tree))
    assert code == 1 and err.startswith("mission scenario: ") and "t.yaml" in err


def test_progress_line_only_on_a_terminal():
    import io as _io

    from executive.progress import Progress, bar

    class Tty(_io.StringIO):
        def isatty(self):
            return True

    quiet, loud = _io.StringIO(), Tty()
    for stream in (quiet, loud):
        p = Progress(stream, every=1)
        p.update("t=1.0s")
        p.update("t=2.0s long")
        p.update("t=3s")
        p.done()
    assert quiet.getvalue() == ""
    assert loud.getvalue() == "\rt=1.0s\rt=2.0s long\rt=3s       \r           \r"
    assert bar(0.5, 10) == "[#####.....]" and bar(2.0, 4) == "[####]"
