"""Sweeps: the sweep file (points, errors with lines), the results store, executors that agree
bit for bit (process pool and Dask), resume after a kill, reports and the Optuna search."""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from PIL import Image

from executive.sweeps.apply import ApplyError, merged_params, tree_doc_with_ports
from executive.sweeps.report import point_stats, wilson, write_report
from executive.sweeps.spec import SweepError, load_sweep, parse_seeds
from executive.sweeps.store import ResultStore, records_equal
from executive.sweeps.sweep import run_sweep

REPO = Path(__file__).resolve().parent.parent

# Two small rooms: a straight run, and a run past a box the map does not know.
_ROOM = "\n".join(["#" * 34] + ["#" + "." * 32 + "#"] * 20 + ["#" * 34])
SCENARIO_A = {"name": "straight", "map": {"resolution": 0.1, "ascii": _ROOM},
              "start": [0.6, 0.6, 0.0], "goals": [[2.6, 0.6, 0.0]], "time_limit": 30}
SCENARIO_B = {"name": "past_box", "map": {"resolution": 0.1, "ascii": _ROOM},
              "start": [0.6, 0.7, 0.0], "goals": [[2.8, 0.7, 0.0]],
              "objects": [{"box": [1.5, 0.3, 1.7, 0.95]}], "time_limit": 30}


def _write(path: Path, doc: dict) -> Path:
    import yaml
    path.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return path


@pytest.fixture()
def catalogue(tmp_path: Path) -> Path:
    d = tmp_path / "scenarios"
    d.mkdir()
    _write(d / "straight.yaml", SCENARIO_A)
    _write(d / "past_box.yaml", SCENARIO_B)
    return d


def _spec(tmp_path: Path, body: str) -> Path:
    p = tmp_path / "sweep.yaml"
    p.write_text(textwrap.dedent(body), encoding="utf-8")
    return p


# --------------------------------------------------------------------------- the file
def test_grid_zip_and_points_expand_crossed_and_zipped(tmp_path, catalogue):
    spec = load_sweep(_spec(tmp_path, """\
        scenarios: scenarios/*.yaml
        seeds: 1..2
        grid:
          DWAPlannerROS.sim_time: [1.0, 2.0]
        zip:
          global_costmap.inflation_layer.inflation_radius: [0.5, 0.8]
          local_costmap.inflation_layer.inflation_radius: [0.4, 0.7]
        """))
    assert len(spec.points) == 4
    assert {p["DWAPlannerROS.sim_time"] for p in spec.points} == {1.0, 2.0}
    # zipped axes advance together: never 0.5 with 0.7
    pairs = {(p["global_costmap.inflation_layer.inflation_radius"],
              p["local_costmap.inflation_layer.inflation_radius"]) for p in spec.points}
    assert pairs == {(0.5, 0.4), (0.8, 0.7)}
    tasks = spec.tasks()
    assert len(tasks) == 2 * 2 * 4            # scenarios x seeds x points (one tree)
    assert len({t.run_id for t in tasks}) == len(tasks)
    assert [t.seed for t in tasks[:4]] == [1, 1, 1, 1]


def test_seeds_forms():
    assert parse_seeds("3..6") == [3, 4, 5, 6]
    assert parse_seeds([4, 9]) == [4, 9]
    assert parse_seeds(7) == [7]
    for bad in ("6..3", "a..b", [], True, 1.5):
        with pytest.raises(SweepError):
            parse_seeds(bad)


@pytest.mark.parametrize("body, line, words", [
    ("scenarios: scenarios/*.yaml\ngrdi:\n  DWAPlannerROS.sim_time: [1.0]\n", 2, "did you mean 'grid'"),
    ("scenarios: scenarios/*.yaml\ngrid:\n  DWAPlannerROS.sim_tiem: [1.0, 2.0]\n", 3, "sim_tiem"),
    ("scenarios: scenarios/*.yaml\ngrid:\n  DWAPlannerROS.sim_time: [1.0, -4.0]\n", 3, "sim_time"),
    ("scenarios: scenarios/*.yaml\nzip:\n  a.b: [1, 2]\n  c.d: [1]\n", 2, "same length"),
    ("scenarios: scenarios/nothing*.yaml\n", 1, "matches no file"),
    ("scenarios: scenarios/*.yaml\nseeds: 9..2\n", 2, "A <= B"),
    ("scenarios: scenarios/*.yaml\ngrid:\n  Escalation/NoSuchNode.search_radius: [1.0]\n", 3,
     "no node of type or name 'NoSuchNode'"),
    ("scenarios: scenarios/*.yaml\ngrid:\n  Escalation/TemporaryGoal.search_radius: [x]\n", 3,
     "search_radius"),
    ("scenarios: scenarios/*.yaml\nsearch:\n  DWAPlannerROS.sim_time: {low: 3, high: 1}\n", 3,
     "high"),
    # an integer parameter searched over a float range: Optuna would propose 1.5
    ("scenarios: scenarios/*.yaml\nsearch:\n  DWAPlannerROS.vx_samples: {low: 1, high: 20, "
     "step: 0.5}\n", 3, "must be an integer"),
    ("scenarios: [scenarios/*.yaml\n", 2, "not valid YAML"),
    ("- scenarios/*.yaml\n", 1, "must be a mapping"),
    ("grid:\n  DWAPlannerROS.sim_time: [1.0]\n", 1, "scenarios: missing"),
    # YAML would keep the second axis and drop the first one's values silently
    ("scenarios: scenarios/*.yaml\ngrid:\n  DWAPlannerROS.sim_time: [1.0]\n"
     "  DWAPlannerROS.sim_time: [2.0]\n", 4, "appears twice"),
    # a bad value is named at its own line, wherever the point takes it from
    ("scenarios: scenarios/*.yaml\npoints:\n  - {DWAPlannerROS.sim_time: 1.0}\n"
     "  - {DWAPlannerROS.sim_tiem: 2.0}\n", 4, "sim_tiem"),
    ("scenarios: scenarios/*.yaml\ngrid:\n  DWAPlannerROS.sim_time: [1.0, 2.0]\nzip:\n"
     "  DWAPlannerROS.vx_samples:\n    - 3\n    - -4\n", 7, "vx_samples"),
])
def test_bad_sweep_files_name_file_and_line(tmp_path, catalogue, body, line, words):
    p = _spec(tmp_path, body)
    with pytest.raises(SweepError) as e:
        load_sweep(p)
    msg = str(e.value)
    assert msg.startswith(f"{p}:{line}: "), msg
    assert words in msg, msg


def test_points_merge_deeply_and_ports_land_on_named_nodes():
    base = {"global_costmap": {"inflation_layer": {"inflation_radius": 1.0,
                                                   "cost_scaling_factor": 3.0}}}
    out = merged_params(base, {"global_costmap.inflation_layer.inflation_radius": 0.4})
    assert out["global_costmap"]["inflation_layer"] == {"inflation_radius": 0.4,
                                                        "cost_scaling_factor": 3.0}
    assert base["global_costmap"]["inflation_layer"]["inflation_radius"] == 1.0
    doc = {"main_tree": "T", "trees": {"T": {"Sequence": {"children": [
        {"Wait": {"wait_duration": 1.0}},
        {"Wait": {"name": "Long", "wait_duration": 5.0}}]}}}}
    changed = tree_doc_with_ports(doc, {"T/Long.wait_duration": 9.0}, "t.yaml")
    kids = changed["trees"]["T"]["Sequence"]["children"]
    assert [k["Wait"]["wait_duration"] for k in kids] == [1.0, 9.0]
    changed = tree_doc_with_ports(doc, {"T/Wait.wait_duration": 2.0}, "t.yaml")
    assert [k["Wait"]["wait_duration"] for k in changed["trees"]["T"]["Sequence"]["children"]] \
        == [2.0, 2.0]
    with pytest.raises(ApplyError, match="no subtree 'U'"):
        tree_doc_with_ports(doc, {"U/Wait.wait_duration": 2.0}, "t.yaml")


# --------------------------------------------------------------------------- running
SMALL = """\
    name: small
    scenarios: scenarios/*.yaml
    seeds: [3, 4]
    grid:
      DWAPlannerROS.max_vel_x: [0.3, 0.45, 0.55]
    """


def test_pool_and_dask_give_identical_records(tmp_path, catalogue, monkeypatch):
    """2 scenarios x 2 seeds x 3 points on a process pool and on a Dask LocalCluster (with 4
    runs in each Dask task: the runs of a task come back together and are written one by one)."""
    pytest.importorskip("dask.distributed")
    from executive.sweeps import runner
    monkeypatch.setattr(runner, "TASKS_PER_WORKER", 1)
    assert runner.chunk_size(12, 2) == 4
    spec = load_sweep(_spec(tmp_path, SMALL))
    out = io.StringIO()
    a = run_sweep(spec, str(tmp_path / "pool"), jobs=2, out=out)
    b = run_sweep(spec, str(tmp_path / "dask"), jobs=2, dask="local", out=out)
    assert (a.planned, a.ran, a.errors) == (12, 12, 0)
    assert (b.planned, b.ran, b.errors) == (12, 12, 0)
    ra = ResultStore.open_existing(str(tmp_path / "pool")).records()
    rb = ResultStore.open_existing(str(tmp_path / "dask")).records()
    assert len(ra) == 12 and records_equal(ra, rb)
    assert all(r["outcome"] != "error" and r["contacts"] == 0 for r in ra)
    assert all(r["outcome"] == "succeeded" for r in ra if r["scenario"] == "straight.yaml")
    # speed matters: the slowest point takes longer than the fastest on the straight run
    t = {r["point"]["DWAPlannerROS.max_vel_x"]: r["sim_time_s"] for r in ra
         if r["scenario"] == "straight.yaml" and r["seed"] == 3}
    assert t[0.3] > t[0.55]
    assert all(r["path_length_m"] > 1.6 for r in ra if r["solved"])  # 2 m less the goal tolerance
    assert all(0.25 < r["min_clearance_m"] < 1.0 for r in ra)      # never touched, never far
    assert all(r["turning_rad_per_m"] >= 0 for r in ra)
    # running the same sweep again finds everything finished
    again = run_sweep(spec, str(tmp_path / "pool"), jobs=2, out=out)
    assert (again.skipped, again.ran) == (12, 0)


def test_dask_tasks_hold_a_few_runs_and_keep_every_worker_busy():
    from executive.sweeps.runner import MAX_RUNS_PER_TASK, TASKS_PER_WORKER, chunk_size
    assert chunk_size(12, 2) == 1                    # a small sweep: one run a task
    assert chunk_size(24, 2) == 3                    # still TASKS_PER_WORKER tasks a worker
    assert chunk_size(10_000, 2) == MAX_RUNS_PER_TASK
    assert chunk_size(5, 0) == 1
    for n, w in [(24, 2), (100, 3), (1000, 8)]:
        assert -(-n // chunk_size(n, w)) >= TASKS_PER_WORKER * w


def _is_warm() -> bool:
    from executive.sweeps import runner
    return runner.warmed


def test_dask_workers_that_join_later_are_warmed_too(tmp_path, catalogue):
    """On a cluster given by its address, the warm-up is a worker plugin: a worker that joins
    after the first run (a cluster scaled up, a restarted worker) warms as well; closing the
    executor takes the plugin off the cluster again."""
    pytest.importorskip("dask.distributed")
    from dask.distributed import LocalCluster

    from executive.sweeps.runner import Executor
    task = load_sweep(_spec(tmp_path, SMALL.replace("[3, 4]", "[3]"))).tasks()[0]
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster:
        got: list[dict] = []
        with Executor(1, cluster.scheduler_address) as ex:
            ex.run([task], lambda t, r, timing: got.append(r))
            assert got[0]["outcome"] == "succeeded"
            client = ex._client
            assert list(client.run(_is_warm).values()) == [True]
            cluster.scale(2)
            client.wait_for_workers(2, timeout=120)
            deadline = time.monotonic() + 120   # the new worker's setup runs in the background
            while not all(client.run(_is_warm).values()) and time.monotonic() < deadline:
                time.sleep(0.2)
            assert list(client.run(_is_warm).values()) == [True, True]
            assert "navbt-warm-kernels" in cluster.scheduler.worker_plugins
        assert "navbt-warm-kernels" not in cluster.scheduler.worker_plugins


def test_a_run_that_raises_is_an_error_record_and_the_sweep_goes_on(tmp_path, catalogue):
    broken = dict(SCENARIO_A, name="broken", params={"DWAPlannerROS": {"sim_time": 1.0}})
    _write(catalogue / "zz_broken.yaml", broken)
    spec = load_sweep(_spec(tmp_path, SMALL.replace("[3, 4]", "[3]")))
    # break the file after the check: the run itself must report it, not kill the sweep
    (catalogue / "zz_broken.yaml").write_text("map: {ascii: '#'}\n", encoding="utf-8")
    summary = run_sweep(spec, str(tmp_path / "out"), jobs=1, out=io.StringIO())
    records = ResultStore.open_existing(str(tmp_path / "out")).records()
    assert summary.ran == 9 and summary.errors == 3
    bad = [r for r in records if r["scenario"] == "zz_broken.yaml"]
    assert len(bad) == 3 and all(r["outcome"] == "error" and "ScenarioError" in r["error"]
                                 for r in bad)
    assert sum(r["outcome"] in ("succeeded", "timeout") for r in records) == 6


def _children(pid: int) -> list[int]:
    try:
        out = subprocess.run(["ps", "-o", "pid=,args=", "--ppid", str(pid)],
                             capture_output=True, text=True, timeout=10).stdout
    except (OSError, subprocess.TimeoutExpired):
        return []
    return [int(line.split()[0]) for line in out.splitlines()
            if "resource_tracker" not in line and line.strip()]


def test_killed_sweep_resumes_only_the_missing_points(tmp_path, catalogue):
    """Kill a worker, then the parent, mid-sweep; the next invocation runs only what is missing."""
    body = SMALL.replace("[3, 4]", "1..6")      # 2 x 6 x 3 = 36 runs
    spec_path = _spec(tmp_path, body)
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "executive.cli", "sweep", str(spec_path), "--out", str(out),
           "--jobs", "2"]
    proc = subprocess.Popen(cmd, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    db = out / "results.sqlite"
    killed_child = False
    deadline = time.monotonic() + 240
    try:
        while time.monotonic() < deadline:
            n = ResultStore(str(out)).count() if db.exists() else 0
            if n >= 4 and not killed_child:
                kids = _children(proc.pid)
                if kids:
                    os.kill(kids[0], signal.SIGKILL)
                    killed_child = True
            if killed_child and n >= 8:
                break
            if proc.poll() is not None:
                break
            time.sleep(0.05)
        assert proc.poll() is None, "the sweep finished before it could be killed"
        proc.send_signal(signal.SIGKILL)
    finally:
        proc.wait(timeout=30)
    assert killed_child
    first = ResultStore(str(out))
    n1 = first.count()
    done_before = first.finished_ids()
    first.close()
    assert 8 <= n1 < 36
    res = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stdout + res.stderr
    assert f"{n1} already finished, {36 - n1} to run" in res.stdout
    store = ResultStore(str(out))
    records = store.records(with_timing=True)
    assert len(records) == 36 and len({r["run_id"] for r in records}) == 36
    assert {r["run_id"] for r in records if r["session"] == 1} == done_before
    assert store.count(session=2) == 36 - n1
    assert not any(r["outcome"] == "error" for r in records)


# --------------------------------------------------------------------------- reports
def test_wilson_interval_matches_the_formula():
    lo, hi = wilson(9, 10)
    assert lo == pytest.approx(0.5958, abs=1e-4) and hi == pytest.approx(0.9821, abs=1e-4)
    assert wilson(0, 5)[0] == 0.0 and wilson(0, 5)[1] == pytest.approx(0.4345, abs=1e-4)
    assert wilson(5, 5)[1] == 1.0
    assert wilson(0, 0) == (0.0, 1.0)


def _records(points: list[dict], solved: list[list[int]]) -> list[dict]:
    out = []
    for i, (p, ss) in enumerate(zip(points, solved)):
        for j, s in enumerate(ss):
            out.append({"run_id": f"{i}-{j}", "scenario": "s.yaml", "seed": j, "tree": "t",
                        "point": p, "outcome": "succeeded" if s else "failed", "reason": None,
                        "passed": s, "solved": s, "sim_time_s": 10.0 + i, "recoveries": [],
                        "n_recoveries": 0, "contacts": 0, "path_length_m": 3.0,
                        "goals_reached": s, "goals_total": 1, "error": None,
                        "navbt_version": "x"})
    return out


def test_report_table_heat_map_and_curves(tmp_path):
    pts = [{"a.x": x, "a.y": y} for x in (1.0, 2.0) for y in (0.1, 0.2, 0.3)]
    solved = [[1, 1, 1, 1], [1, 1, 0, 0], [0, 0, 0, 0], [1, 0, 1, 0], [1, 1, 1, 0], [1, 1, 1, 1]]
    records = _records(pts, solved)
    stats = point_stats(records)
    assert [s.solved for s in stats] == [4, 2, 0, 2, 3, 4]
    out = io.StringIO()
    written = write_report(records, str(tmp_path), out, name="t")
    table = out.getvalue()
    assert "100%" in table and "[51, 100]" in table and "0%" in table
    heat = [p for p in written["pictures"] if os.path.basename(p).startswith("heat_")]
    assert len(heat) == 1
    img = Image.open(heat[0]).convert("RGB")
    # the cell of 100 % is green, the cell of 0 % is red
    px = img.load()
    w, h = img.size
    gw, gh = (w - 140) / 2, (h - 140) / 3
    green = px[int(70 + 0.2 * gw), int(h - 70 - 0.2 * gh)]          # x=1.0, y=0.1: 4/4
    red = px[int(70 + 0.2 * gw), int(h - 70 - 2.2 * gh)]            # x=1.0, y=0.3: 0/4
    assert green[1] > 150 and green[0] < 100
    assert red[0] > 150 and red[1] < 100
    curves = [p for p in written["pictures"] if os.path.basename(p).startswith("curve_")]
    assert len(curves) == 2 and all(Image.open(p).getbbox() for p in curves)
    rep = json.loads((tmp_path / "report.json").read_text())
    assert rep["points"][0]["ci95"] == [pytest.approx(0.5101, abs=1e-3), 1.0]


def test_tune_finds_the_faster_speed_and_writes_an_overlay(tmp_path, catalogue):
    pytest.importorskip("optuna")
    from executive.sweeps.tune import tune
    spec = load_sweep(_spec(tmp_path, """\
        name: speed
        scenarios: scenarios/straight.yaml
        seeds: [1]
        search:
          DWAPlannerROS.max_vel_x: {choices: [0.2, 0.5]}
        trials: 4
        sampler_seed: 3
        """))
    out = io.StringIO()
    res = tune(spec, str(tmp_path / "tune"), jobs=1, out=out)
    # both solve it; the tie-break on time prefers the faster robot
    assert res["best"] == {"DWAPlannerROS.max_vel_x": 0.5}
    import yaml
    overlay = yaml.safe_load((tmp_path / "tune" / "best_config.yaml").read_text())
    assert overlay == {"DWAPlannerROS": {"max_vel_x": 0.5}}
    # the store holds each distinct run once, however many trials asked for it
    store = ResultStore(str(tmp_path / "tune"))
    assert store.count() == len({json.dumps(r["point"]) for r in store.records()}) <= 2


def test_a_point_changes_one_value_of_a_layer_and_keeps_the_rest(catalogue):
    from executive.scenario import load_scenario, scenario_config
    from executive.sweeps.apply import apply_point
    sc = load_scenario(catalogue / "straight.yaml")
    s = apply_point(sc, {"global_costmap.inflation_layer.inflation_radius": 0.35}, None)
    layer = scenario_config(s).ns("global_costmap")["inflation_layer"]
    assert layer == {"inflation_radius": 0.35, "cost_scaling_factor": 10.0}   # robot.yaml's
    assert scenario_config(s).ns("local_costmap")["inflation_layer"]["inflation_radius"] == 0.55


def test_sweep_over_ros_parameter_files(tmp_path, catalogue):
    """``params:`` loads rosparam files as ``--params`` does; the point goes on top."""
    (tmp_path / "dwa.yaml").write_text("DWAPlannerROS:\n  max_vel_x: 0.25\n  sim_time: 1.2\n",
                                       encoding="utf-8")
    spec = load_sweep(_spec(tmp_path, """\
        scenarios: scenarios/straight.yaml
        params: [dwa.yaml]
        grid:
          DWAPlannerROS.sim_time: [1.5, 2.5]
        """))
    from executive.config import ConfigSources
    from executive.scenario import load_scenario, scenario_config
    from executive.sweeps.apply import apply_point
    assert isinstance(spec.config, ConfigSources)
    t = spec.tasks()[1]
    s = apply_point(load_scenario(t.scenario), dict(t.point), t.config)
    dwa = scenario_config(s, t.config).ns("DWAPlannerROS")
    assert (dwa["max_vel_x"], dwa["sim_time"]) == (0.25, 2.5)
    # the base config is part of a run's identity
    other = load_sweep(_spec(tmp_path, "scenarios: scenarios/straight.yaml\n"
                                       "grid:\n  DWAPlannerROS.sim_time: [1.5, 2.5]\n"))
    assert {x.run_id for x in spec.tasks()}.isdisjoint({x.run_id for x in other.tasks()})


def test_clearance_and_turning_of_known_paths():
    import math

    import numpy as np

    from executive.scenario import Shape
    from executive.sweeps.metrics import min_clearance, turning_per_metre
    from navcore.maps import OccupancyGrid
    grid = OccupancyGrid(np.zeros((40, 60), np.int16), 0.1)     # 6 m x 4 m, empty
    grid.data[:, 59] = 100                                       # a wall at x = 5.9..6.0
    box = Shape("box", (2.0, 1.0, 2.4, 1.4))
    line = [(0.55 + 0.01 * i, 2.05, 0.0) for i in range(100)]    # y = 2.05, x 0.55 .. 1.54
    # nearest obstacle: the box corner (2.05, 1.35) cell centre from (1.54, 2.05)
    assert min_clearance(line, grid, [box]) == pytest.approx(math.hypot(2.05 - 1.55, 2.05 - 1.35),
                                                             abs=0.011)
    assert min_clearance(line, grid) == pytest.approx(5.95 - 1.55, abs=0.011)   # the wall
    assert turning_per_metre(line) == 0.0
    r = 1.5
    arc = [(r * math.cos(a), r * math.sin(a), a + math.pi / 2)
           for a in np.linspace(0, math.pi / 2, 200)]
    assert turning_per_metre(arc) == pytest.approx(1 / r, rel=1e-3)
    assert turning_per_metre([(0, 0, 0), (0, 0, 1)]) is None    # turned on the spot only


@pytest.mark.parametrize("path", sorted((REPO / "examples" / "sweeps").glob("*.yaml")),
                         ids=lambda p: p.name)
def test_example_sweep_files_check(path):
    spec = load_sweep(path)
    assert spec.tasks() and (spec.points or spec.search)


def test_only_a_warning_about_the_points_own_key_refuses_it(tmp_path, catalogue):
    """The base config's warning about vtheta_samples (a misspelling of vth_samples) says
    nothing about a point that sets vth_samples; a point setting vtheta_samples is refused."""
    from executive.scenario import load_scenario
    from executive.sweeps.apply import apply_point
    base = tmp_path / "robot.yaml"
    base.write_text("DWAPlannerROS: {vtheta_samples: 20}\n", encoding="utf-8")
    sc = load_scenario(catalogue / "straight.yaml")
    s = apply_point(sc, {"DWAPlannerROS.vth_samples": 12}, str(base))
    assert s.params["DWAPlannerROS"]["vth_samples"] == 12
    with pytest.raises(ApplyError, match="'DWAPlannerROS.vtheta_samples': .*misspelling"):
        apply_point(sc, {"DWAPlannerROS.vtheta_samples": 12}, str(base))
