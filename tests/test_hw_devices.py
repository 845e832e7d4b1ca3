"""open_devices: a robot's devices from config URLs, and clear errors for a wrong config."""

from __future__ import annotations

import threading

import pytest

import hw.emulators as emu
from hw.devices import DeviceConfigError, close_devices, open_devices, parse_device_url
from hw.emulators.harness import wait_until
from hw.interfaces import Base, ImuSensor, Laser
from navcore.clock import WallClock
from navcore.params import ParameterError
from navcore.types import Pose2D, Twist


@pytest.fixture
def clean_registry():
    yield
    emu.unplug_all()
    assert [t.name for t in threading.enumerate() if t.name.endswith("-reader")] == []


def test_url_forms() -> None:
    assert parse_device_url("base", "kobuki:///dev/ttyUSB0") == ("kobuki", "/dev/ttyUSB0")
    assert parse_device_url("laser", "urg04lx://sim") == ("urg04lx", "sim://urg04lx")
    assert parse_device_url("laser", "lms291://sim?corrupt=0.01&id=rear") == \
        ("lms291", "sim://lms291?corrupt=0.01&id=rear")
    assert parse_device_url("imu", "vectornav://socket://10.0.0.5:7000") == \
        ("vectornav", "socket://10.0.0.5:7000")


@pytest.mark.parametrize("devices,message", [
    ({"arm": "kobuki://sim"}, "unknown role 'arm'"),
    ({"laser": "kobuki://sim"}, "'kobuki' is not a laser device"),
    ({"base": "/dev/ttyUSB0"}, "is not '<device>://<port>'"),
    ({"laser": {"url": "urg04lx://sim", "mount": [0.1, 0.0]}}, "devices.laser.mount"),
    ({"laser": {"url": "urg04lx://sim", "frame": "x"}}, "unknown key"),
    ({"base": {"url": "kobuki://sim", "params": {"cmd_vel_timout": 1.0}}}, "cmd_vel_timeout"),
])
def test_config_errors_name_the_entry(devices, message: str) -> None:
    with pytest.raises(DeviceConfigError, match=message):
        open_devices(devices, WallClock())
    assert [t.name for t in threading.enumerate() if t.name.endswith("-reader")] == []


def test_a_whole_robot_on_emulators(clean_registry) -> None:
    clock = WallClock()
    devs = open_devices({"base": "kobuki://sim?id=robot-base",
                         "laser": {"url": "urg04lx://sim?id=robot-laser",
                                   "mount": [0.2, 0.0, 0.0], "params": {"cluster": 2}},
                         "imu": "razor://sim?id=robot-imu"}, clock)
    try:
        assert isinstance(devs["base"], Base) and isinstance(devs["laser"], Laser)
        assert isinstance(devs["imu"], ImuSensor)
        assert devs["laser"].mount == Pose2D(0.2, 0.0, 0.0)
        assert wait_until(lambda: all(d.connected for d in devs.values()), 8.0), \
            {k: d.last_error for k, d in devs.items()}
        assert wait_until(lambda: devs["laser"].scan() is not None and devs["imu"].imu()
                          is not None and devs["base"].odometry() is not None, 5.0), \
            {k: d.last_error for k, d in devs.items()}
        assert len(devs["laser"].scan().ranges) == 341
        devs["base"].send(Twist(0.1, 0.0, 0.0))
        base_emu = emu.lookup("robot-base").emulator
        assert wait_until(lambda: base_emu.speed == 100, 2.0)
    finally:
        close_devices(devs)
    assert base_emu.speed == 0


def test_parameter_error_type_is_kept_in_the_chain() -> None:
    with pytest.raises(DeviceConfigError) as info:
        open_devices({"laser": {"url": "urg04lx://sim", "params": {"skip": 12}}}, WallClock())
    assert "above its maximum" in str(info.value)
    assert issubclass(ParameterError, ValueError)


def test_devices_over_tcp(clean_registry) -> None:
    from hw.emulators.kobuki import KobukiEmulator
    from hw.emulators.tcp_port import TcpDevice
    clock = WallClock()
    e = KobukiEmulator(clock)
    link = emu.Link(e)
    with TcpDevice(link) as srv:
        devs = open_devices({"base": f"kobuki://{srv.url}"}, clock)
        try:
            base = devs["base"]
            assert base.wait_connected(3.0), base.last_error
            base.send(Twist(0.2, 0.0, 0.0))
            assert wait_until(lambda: e.speed == 200, 2.0)
            link.unplug()
            assert wait_until(lambda: not base.connected, 2.0)
            link.replug()
            assert wait_until(lambda: base.connects == 2, 3.0), base.last_error
        finally:
            close_devices(devs)
    assert [t.name for t in threading.enumerate() if t.name == "tcp-device"] == []
