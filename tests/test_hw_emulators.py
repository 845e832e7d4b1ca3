"""The emulator wire: fault injection, unplug, and the sim:// URL handler's pyserial semantics."""

from __future__ import annotations

import pytest
import serial

import hw.emulators as emu
from hw.emulators.link import Emulator, Faults, Link, Unplugged
from navcore.clock import SimClock


class Echo(Emulator):
    """Sends back what it receives; one byte 'T' per simulated second on its own."""

    device = "echo"

    def __init__(self, clock) -> None:
        super().__init__(clock)
        self.got = bytearray()
        self._t = clock.now()

    def receive(self, data: bytes) -> None:
        self.got += data
        self.emit(data)

    def advance(self, now: float) -> None:
        while now - self._t >= 1.0:
            self._t += 1.0
            self.emit(b"T")


def test_clean_link_passes_bytes_and_time() -> None:
    clock = SimClock()
    link = Link(Echo(clock))
    link.write(b"hello")
    assert link.read() == b"hello"
    clock.advance(2.5)
    assert link.read() == b"TT"


def test_faults_are_seeded_and_counted() -> None:
    def run(seed: int) -> bytes:
        clock = SimClock()
        link = Link(Echo(clock), Faults(corrupt=0.05, drop=0.05, garbage=0.5), seed=seed)
        out = b""
        for _ in range(20):
            link.write(bytes(range(50)))
            out += link.read()
        assert link.bytes_corrupted > 0 and link.bytes_dropped > 0
        return out
    assert run(1) == run(1) != run(2)


def test_delay_holds_bytes_for_clock_seconds() -> None:
    clock = SimClock()
    link = Link(Echo(clock), Faults(delay=0.5))
    link.write(b"x")
    assert link.read() == b""
    clock.advance(0.49)
    assert link.read() == b""
    clock.advance(0.02)
    assert link.read() == b"x"


def test_host_side_faults_reach_the_device() -> None:
    clock = SimClock()
    e = Echo(clock)
    link = Link(e, Faults(host_drop=1.0))
    link.write(b"abc")
    assert bytes(e.got) == b""


def test_unplug_power_cycles_and_refuses_io() -> None:
    clock = SimClock()
    e = Echo(clock)
    link = Link(e)
    link.write(b"pending")
    link.unplug()
    with pytest.raises(Unplugged):
        link.read()
    with pytest.raises(Unplugged):
        link.write(b"x")
    link.replug()
    assert link.read() == b""               # what was in flight died with the power


def test_sim_url_port_semantics() -> None:
    clock = SimClock()
    from hw.emulators.urg04lx import Urg04lxEmulator
    link = emu.plug("u-sem", Urg04lxEmulator(clock))
    try:
        port = serial.serial_for_url("sim://urg04lx?id=u-sem", baudrate=115200, timeout=0.05)
        assert link.emulator.baudrate == 115200            # baud changes reach the device
        port.baudrate = 19200
        assert link.emulator.baudrate == 19200
        port.write(b"VV\n")
        reply = port.read(1000)                           # returns after the timeout
        assert reply.startswith(b"VV\n00P\n") and reply.endswith(b"\n\n")
        assert port.read(10) == b""
        link.unplug()
        with pytest.raises(serial.SerialException, match="disconnected"):
            port.read(1)
        link.replug()
        with pytest.raises(serial.SerialException, match="disconnected"):
            port.write(b"VV\n")                           # the old handle is stale for good
        port.close()
        port = serial.serial_for_url("sim://urg04lx?id=u-sem", timeout=0.05)
        port.write(b"VV\n")
        assert port.read(1000).startswith(b"VV\n00P\n")
        port.close()
    finally:
        emu.unplug_all()


@pytest.mark.parametrize("url,message", [("sim://toaster", "unknown emulated device"),
                                         ("sim://urg04lx?corupt=0.1", "unknown option"),
                                         ("sim://urg04lx?corrupt=lots", "bad option value")])
def test_bad_sim_urls_are_explained(url: str, message: str) -> None:
    with pytest.raises(serial.SerialException, match=message):
        serial.serial_for_url(url)
    emu.unplug_all()


def test_unplugged_device_cannot_be_opened() -> None:
    from hw.emulators.kobuki import KobukiEmulator
    link = emu.plug("k-off", KobukiEmulator(SimClock()))
    link.unplug()
    with pytest.raises(serial.SerialException, match="not present"):
        serial.serial_for_url("sim://kobuki?id=k-off")
    with pytest.raises(serial.SerialException, match="is a kobuki, not a urg04lx"):
        link.replug()
        serial.serial_for_url("sim://urg04lx?id=k-off")
    emu.unplug_all()
