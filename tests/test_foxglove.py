"""run.mcap read back with the mcap reader, and a live run watched over Foxglove's WebSocket
protocol on loopback."""

from __future__ import annotations

import json
import math
import struct
import threading
import time

import pytest

from executive.recorder import read_log, statuses_at

pytest.importorskip("foxglove", reason="foxglove-sdk not installed (pip install navbt[foxglove])")
mcap_reader = pytest.importorskip("mcap.reader", reason="mcap not installed (navbt[foxglove])")

SCHEMAS = {
    "/map": "foxglove.Grid", "/global_costmap": "foxglove.Grid",
    "/local_costmap": "foxglove.Grid", "/scan": "foxglove.LaserScan",
    "/pose": "foxglove.PoseInFrame", "/plan": "foxglove.PosesInFrame",
    "/tf": "foxglove.FrameTransforms", "/events": "foxglove.Log",
    "/behavior_tree": "navbt.BehaviorTreeStatus", "/cmd_vel": "navbt.Twist2D",
}


def test_run_mcap_channels_schemas_counts_and_stamps(demo_run):
    header, ticks, footer = read_log(str(demo_run / "ticks.jsonl"))
    with open(demo_run / "run.mcap", "rb") as f:
        reader = mcap_reader.make_reader(f)
        summary = reader.get_summary()
        by_topic = {c.topic: c for c in summary.channels.values()}
        # no AMCL in the demo: no particle cloud; every other channel is there
        assert set(by_topic) == set(SCHEMAS)
        for topic, name in SCHEMAS.items():
            c = by_topic[topic]
            assert summary.schemas[c.schema_id].name == name, topic
            assert c.message_encoding == ("json" if name.startswith("navbt.") else "protobuf")
        counts = {by_topic_id.topic: summary.statistics.channel_message_counts[cid]
                  for cid, by_topic_id in summary.channels.items()}
        n = len(ticks)
        assert counts["/pose"] == counts["/tf"] == counts["/cmd_vel"] == n
        assert counts["/map"] == 1
        events = [e for t in ticks for e in t.get("events", ())]
        assert counts["/events"] == len(events) + 1            # and the mission's end
        paths = sum(1 for t in ticks if isinstance(t.get("bb", {}).get("path"), dict))
        assert counts["/plan"] == paths
        changes = sum(1 for t in ticks[1:] if t.get("status"))
        assert counts["/behavior_tree"] == 1 + changes
        t_end = ticks[-1]["t"]
        assert int(t_end) <= counts["/local_costmap"] <= int(t_end) + 1          # 1 Hz
        assert summary.statistics.message_start_time == 0
        # the last message is the mission's end, stamped when the run stopped
        assert summary.statistics.message_end_time == round(footer["time_s"] * 1e9)
        # time stamps are sim time; JSON channels carry the tick log's values
        f.seek(0)
        reader = mcap_reader.make_reader(f)
        cmds, pose_times, tree = [], [], []
        for schema, channel, message in reader.iter_messages(topics=["/cmd_vel", "/pose",
                                                                     "/behavior_tree"]):
            if channel.topic == "/cmd_vel":
                cmds.append(json.loads(message.data))
            elif channel.topic == "/pose":
                pose_times.append(message.log_time)
            else:
                tree.append(json.loads(message.data))
        assert pose_times == [round(t["t"] * 1e9) for t in ticks]
        assert [[c["linear_x"], c["linear_y"], c["angular_z"]] for c in cmds] == \
            [t["cmd"] for t in ticks]
        assert [n["name"] for n in tree[0]["nodes"]] == [n[0] for n in header["nodes"]]
        last = tree[-1]
        changed = [t for t in ticks if t.get("status")][-1]
        assert last["tick"] == changed["tick"]
        # every tree message: each node's name, type, depth and its status after that tick
        for msg in tree:
            assert [[n["name"], n["type"], n["depth"]] for n in msg["nodes"]] == header["nodes"]
            assert [n["status"] for n in msg["nodes"]] == statuses_at(header, ticks, msg["tick"])


def test_map_to_odom_is_pose_after_inverse_odometry():
    import numpy as np

    from executive.foxglove_out import _map_odom
    from navcore.types import Pose2D
    rng = np.random.default_rng(3)
    for _ in range(200):
        est, odom = (Pose2D(*rng.uniform(-50, 50, 2), rng.uniform(-3.2, 3.2)) for _ in range(2))
        x, y, th = _map_odom(est, odom)
        want = est.compose(odom.inverse())
        assert abs(x - want.x) < 1e-9 and abs(y - want.y) < 1e-9
        assert abs(math.remainder(th - want.theta, 2 * math.pi)) < 1e-9
        back = Pose2D(x, y, th).compose(odom)   # map_odom * odom is the estimate
        assert abs(back.x - est.x) < 1e-9 and abs(back.y - est.y) < 1e-9


def test_json_numbers_as_json_writes_them():
    from executive.foxglove_out import _num
    for v in (0.0, -0.0, 0.1234, -1.5, 1e-7, 1e22, 3, True, None, float("nan"), float("inf"),
              -float("inf")):
        assert _num(v) == json.dumps(v), v


def test_live_run_serves_every_channel_on_loopback():
    websocket = pytest.importorskip("websocket", reason="websocket-client not installed")
    from executive.foxglove_out import FoxgloveSink
    from executive.tree_loader import shipped_tree
    from executive.mission import World, build_mission, run_mission
    from executive.recorder import Recorder
    from executive.scenario import load_scenario, scenario_config
    import os
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    scenario = load_scenario(os.path.join(here, "executive", "data", "demo.yaml"))
    # paced at 4x real time: the 15 s demo lasts about 4 s, time enough to connect
    sink = FoxgloveSink(live=True, host="127.0.0.1", port=0, rate=4.0, grid=scenario.grid)
    port = sink.port
    assert port and port > 0
    mission = build_mission(shipped_tree("smach_recovery"), scenario_config(scenario),
                            scenario.grid, scenario.start,
                            world=World(scenario.objects, scenario.moving, scenario.phantoms,
                                        scenario.faults),
                            seed=scenario.seed, recorder=Recorder(None, sinks=[sink]))
    result: list = []
    runner = threading.Thread(target=lambda: result.append(
        run_mission(mission, scenario.goals, scenario.time_limit)), daemon=True)
    ws = websocket.create_connection(f"ws://127.0.0.1:{port}", timeout=5,
                                     subprotocols=["foxglove.sdk.v1"])
    try:
        info = json.loads(ws.recv())
        assert info["op"] == "serverInfo" and {"time", "parameters"} <= set(info["capabilities"])
        channels = {}
        while len(channels) < len(SCHEMAS):
            msg = json.loads(ws.recv())
            if msg["op"] == "advertise":
                channels.update({c["id"]: c for c in msg["channels"]})
        topics = {c["topic"]: c for c in channels.values()}
        assert {t: topics[t]["schemaName"] for t in SCHEMAS} == SCHEMAS
        subs = {i + 1: c["topic"] for i, c in enumerate(channels.values())}
        ws.send(json.dumps({"op": "subscribe", "subscriptions": [
            {"id": i, "channelId": topics[t]["id"]} for i, t in subs.items()]}))
        runner.start()
        seen: dict[str, int] = {}
        times: list[int] = []
        params = None
        deadline = time.monotonic() + 30.0
        while time.monotonic() < deadline and (
                set(seen) < set(SCHEMAS) or params is None or max(times, default=0) <= 0):
            try:
                msg = ws.recv()
            except websocket.WebSocketTimeoutException:
                break
            if isinstance(msg, str):
                obj = json.loads(msg)
                if obj.get("op") == "parameterValues":
                    params = {p["name"]: p.get("value") for p in obj["parameters"]}
                continue
            if msg[0] == 1:      # message data: subscription id, log time, payload
                sub, stamp = struct.unpack_from("<IQ", msg, 1)
                if not seen:     # the run has started: its parameters are known
                    ws.send(json.dumps({"op": "getParameters", "parameterNames": [],
                                        "id": "all"}))
                seen[subs[sub]] = seen.get(subs[sub], 0) + 1
            elif msg[0] == 2:    # server time (sim time)
                times.append(struct.unpack_from("<Q", msg, 1)[0])
        assert set(seen) == set(SCHEMAS), f"no messages on {set(SCHEMAS) - set(seen)}"
        assert times == sorted(times) and times[-1] > 0
        assert params and params["DWAPlannerROS.max_vel_x"] > 0
    finally:
        ws.close()
        runner.join(timeout=60)
        sink.close()
    assert result and result[0].outcome == "succeeded"


def test_live_port_in_use_is_a_clear_error(capsys):
    import os

    import foxglove

    from executive.cli import main
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    taken = foxglove.start_server(host="127.0.0.1", port=0)
    port = taken.port
    try:
        code = main(["run", os.path.join(root, "trees", "smach_recovery.yaml"), "--map",
                     os.path.join(root, "executive", "data", "maps", "two_rooms.yaml"),
                     "--goal", "6.5,1.5,0", "--live", "--port", str(port)])
    finally:
        taken.stop()
    err = capsys.readouterr().err
    assert code == 1 and f"--live: cannot serve on 127.0.0.1:{port}" in err
    assert len(err.strip().splitlines()) == 1
