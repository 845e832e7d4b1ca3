"""replay.html: its data agrees with the tick log, and in a real headless browser the scrubber
shows each tick's number, node statuses and robot pose as ticks.jsonl records them."""

from __future__ import annotations

import io
import shutil

import numpy as np
import pytest
from PIL import Image

from executive.recorder import read_log, statuses_at
from executive.replay_html import path_points, read_page_data


def test_page_data_matches_tick_log_and_is_offline(demo_run):
    header, ticks, footer = read_log(str(demo_run / "ticks.jsonl"))
    text = (demo_run / "replay.html").read_text()
    assert "http://" not in text and "https://" not in text and "src=\"" not in text
    data = read_page_data(str(demo_run / "replay.html"))
    assert data["ticks"] == [t["tick"] for t in ticks]
    assert data["pose"] == [t.get("pose") for t in ticks]
    assert [n[:3] for n in data["nodes"]] == header["nodes"]
    kinds = dict(zip((n[1] for n in data["nodes"]), (n[3] for n in data["nodes"])))
    assert kinds["RecoveryNode"] == "control" and kinds["IsGoalNearby"] == "condition"
    assert kinds["RateController"] == "decorator" and kinds["FollowPath"] == "action"
    # sampled layers: scans (5 Hz), local costmaps (1 Hz), a global costmap, the map
    t_end = ticks[-1]["t"]
    assert len(data["scans"]) >= int(t_end / 0.2) - 1
    assert len(data["local_costmaps"]) >= int(t_end)
    assert data["global_costmaps"] and data["map"]["png"].startswith("data:image/png;base64,")
    assert data["footer"]["outcome"] == "succeeded"
    # each replan's path, encoded small: its points within half a centimetre of the log's
    logged = [(i, t["bb"]["path"]["path"]) for i, t in enumerate(ticks)
              if isinstance(t.get("bb", {}).get("path"), dict) and t["bb"]["path"]["path"]]
    shown = [(i, path_points(code)) for i, code in data["paths"] if code]
    assert len(logged) >= 3 and [i for i, _ in shown] == [i for i, _ in logged]
    for (_, got), (_, want) in zip(shown, logged):
        assert np.abs(np.asarray(got) - np.asarray(want)).max() <= 0.005 + 1e-9


def _driver():
    chromium = shutil.which("chromium") or shutil.which("chromium-browser") \
        or shutil.which("google-chrome")
    driver_exe = shutil.which("chromedriver")
    if chromium is None or driver_exe is None:
        pytest.skip("no headless browser: install Debian's chromium and chromium-driver "
                    "(.ci/run does: apt-get install -y chromium chromium-driver)")
    webdriver = pytest.importorskip("selenium.webdriver",
                                    reason="selenium not installed (pip install navbt[replay])")
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--window-size=1400,900"):
        options.add_argument(arg)
    return webdriver.Chrome(service=Service(executable_path=driver_exe), options=options)


def test_replay_page_in_headless_chromium(demo_run):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    header, ticks, _ = read_log(str(demo_run / "ticks.jsonl"))
    driver = _driver()
    try:
        driver.get((demo_run / "replay.html").as_uri())
        scrubber = driver.find_element(By.ID, "scrubber")
        assert int(scrubber.get_attribute("max")) == len(ticks) - 1

        def check(i: int) -> None:
            line = ticks[i]
            assert driver.find_element(By.ID, "tick").text == str(line["tick"])
            shown = [driver.find_element(By.ID, f"node-{n}").get_attribute("data-status")
                     for n in range(len(header["nodes"]))]
            assert shown == statuses_at(header, ticks, line["tick"])
            pose = driver.find_element(By.ID, "pose").text
            assert pose == ", ".join(f"{v:.2f}" for v in line["pose"])

        check(0)
        for i in (len(ticks) // 3, 2 * len(ticks) // 3, len(ticks) - 1):
            driver.execute_script("const s = document.getElementById('scrubber');"
                                  "s.value = arguments[0];"
                                  "s.dispatchEvent(new Event('input'));", i)
            check(i)
        # the keyboard moves the scrubber too
        i = len(ticks) // 2
        driver.execute_script("const s = document.getElementById('scrubber');"
                              "s.value = arguments[0]; s.dispatchEvent(new Event('input'));", i)
        scrubber.send_keys(Keys.ARROW_RIGHT)
        check(i + 1)
        assert any(s != "INVALID" for s in statuses_at(header, ticks, ticks[i + 1]["tick"]))
        # the map view is drawn: many colours, mostly not white
        png = driver.find_element(By.ID, "view").screenshot_as_png
        px = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).reshape(-1, 3)
        assert len(np.unique(px, axis=0)) > 20
        assert np.mean(np.any(px < 240, axis=1)) > 0.2
        # the page decodes the encoded paths to the points the log holds
        page_path = driver.execute_script("return paths.filter(p => p[1].length).pop()[1];")
        want = [t["bb"]["path"]["path"] for t in ticks
                if isinstance(t.get("bb", {}).get("path"), dict) and t["bb"]["path"]["path"]][-1]
        assert np.abs(np.asarray(page_path) - np.asarray(want)).max() <= 0.005 + 1e-9
        errors = [e for e in driver.get_log("browser") if e.get("level") == "SEVERE"]
        assert not errors, errors
    finally:
        driver.quit()


def test_replay_cli_writes_page_for_old_folder_and_draws_a_frame(demo_run, tmp_path, capsys):
    from executive.cli import main
    old = tmp_path / "old"
    old.mkdir()
    shutil.copy(demo_run / "ticks.jsonl", old / "ticks.jsonl")   # a folder from before pages
    assert main(["replay", str(old), "--tick", "5", "-f", "png"]) == 1
    assert "--html" in capsys.readouterr().err
    assert main(["replay", str(old), "--html"]) == 0
    assert capsys.readouterr().out.strip() == str(old / "replay.html")
    data = read_page_data(str(old / "replay.html"))
    _, ticks, _ = read_log(str(old / "ticks.jsonl"))
    assert data["pose"] == [t.get("pose") for t in ticks] and "scans" not in data
    assert main(["replay", str(demo_run), "--tick", "40", "-f", "png", "-o",
                 str(tmp_path / "f.png")]) == 0
    img = np.asarray(Image.open(tmp_path / "f.png").convert("RGB"))
    assert img.shape == (600, 1060, 3)
    # the robot's footprint (blue), the laser (red) and a RUNNING node (orange) are drawn
    colours = {tuple(c) for c in img.reshape(-1, 3)}
    assert {(0, 90, 200), (230, 0, 90), (242, 142, 0)} <= colours
