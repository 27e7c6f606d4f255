# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_uart_tx (8N1 transmitter), and their pytest entry: back-to-back bytes,
gaps, baud mismatch at the receiver, reset mid-frame, every frame checked by a strict line
monitor (tb/lib/uart_unit.py has the shared set-up).
"""

from __future__ import annotations

import random

import cocotb
import pytest
from cocotb.triggers import ClockCycles, ReadOnly, RisingEdge, Timer
from cocotbext.uart import UartSink

from uart_line import LineMonitor, now_ps, quiet_uart_logs
from uart_unit import BAUD, BIT_PS, BUILDS, DIV, FRAME_PS, PERIOD_PS, rng_for, start_clock_and_reset
import runner


class TxDriver:
    """Offers bytes on uart_tx's s_axis (AXI-Stream rules) and records handshake times."""

    def __init__(self, dut) -> None:
        self.dut = dut
        self.handshakes: list[int] = []
        dut.s_axis_tvalid.value = 0
        dut.s_axis_tdata.value = 0

    async def send(self, data: bytes, gaps: list[int] | None = None) -> None:
        dut = self.dut
        for i, byte in enumerate(data):
            if gaps and gaps[i]:
                dut.s_axis_tvalid.value = 0
                await ClockCycles(dut.clk, gaps[i])
            dut.s_axis_tdata.value = byte
            dut.s_axis_tvalid.value = 1
            while True:
                await ReadOnly()
                if dut.s_axis_tready.value == 1:
                    await RisingEdge(dut.clk)
                    break
                await RisingEdge(dut.s_axis_tready)
            self.handshakes.append(now_ps())
        dut.s_axis_tvalid.value = 0


async def tx_setup(dut, monitor_bauds=(BAUD,)) -> tuple[TxDriver, list[LineMonitor], random.Random]:
    rng = rng_for(dut)
    drv = TxDriver(dut)
    await start_clock_and_reset(dut)
    mons = [LineMonitor(dut.tx_o, b) for b in monitor_bauds]
    return drv, mons, rng


def check_monitor(mon: LineMonitor, data: bytes, what: str) -> None:
    assert not mon.errors, f"{what}: {mon.errors[:3]}"
    assert mon.data == data, f"{what}: line carried {mon.data.hex()} sent {data.hex()}"


@cocotb.test()
async def test_tx_back_to_back(dut) -> None:
    """Bytes offered back to back leave at the full line rate: frames exactly 10 bit times
    apart, the first one a clock after its handshake; good start and stop bits; the line
    idles high before and after. cocotbext-uart's UartSink receives the same bytes."""
    drv, (mon,), rng = await tx_setup(dut)
    sink = UartSink(dut.tx_o, baud=BAUD)
    quiet_uart_logs(dut.tx_o)
    await ReadOnly()
    assert dut.tx_o.value == 1 and dut.s_axis_tready.value == 1, "not idle after reset"
    await RisingEdge(dut.clk)
    data = bytes([0x00, 0xFF, 0x55]) + bytes(rng.randrange(256) for _ in range(45))
    await drv.send(data)
    await Timer(2 * FRAME_PS, unit="ps")
    check_monitor(mon, data, "nominal rate")
    assert bytes(sink.read_nowait()) == data
    starts = [t for t, _ in mon.frames]
    for k in range(1, len(starts)):
        assert starts[k] - starts[k - 1] == FRAME_PS, (
            f"frames {k - 1} and {k} {(starts[k] - starts[k - 1]) / PERIOD_PS} clocks apart, "
            f"expected {10 * DIV}")
    # The first byte's start bit begins at the clock edge of its handshake.
    assert starts[0] == drv.handshakes[0], (starts[0], drv.handshakes[0])
    await ReadOnly()
    assert dut.tx_o.value == 1 and dut.s_axis_tready.value == 1


@cocotb.test()
async def test_tx_gaps(dut) -> None:
    """Bytes with random idle gaps: each frame starts on its handshake's clock edge, the line
    is high between frames, and s_axis_tready is 0 exactly while a frame is on the line
    (except on the stop bit's last clock)."""
    drv, (mon,), rng = await tx_setup(dut)
    data = bytes(rng.randrange(256) for _ in range(24))
    gaps = [rng.choice([0, 0, 1, 7, DIV, 3 * DIV, 12 * DIV]) for _ in data]
    await drv.send(data, gaps)
    await Timer(2 * FRAME_PS, unit="ps")
    check_monitor(mon, data, "with gaps")
    for k, ((t, _), hs) in enumerate(zip(mon.frames, drv.handshakes)):
        assert t == hs, f"frame {k} starts {(t - hs) / PERIOD_PS} clocks after its handshake"
    for k in range(1, len(drv.handshakes)):
        assert drv.handshakes[k] - drv.handshakes[k - 1] >= FRAME_PS, "a byte taken mid-frame"


@cocotb.test()
async def test_tx_baud_mismatch(dut) -> None:
    """Receivers 2 % (and 3 %) slower or faster than the transmitter read every byte of a
    back-to-back stream, stop bits included (strict monitors and cocotbext-uart sinks)."""
    factors = (0.98, 1.02, 0.97, 1.03)
    drv, mons, rng = await tx_setup(dut, tuple(BAUD * f for f in factors))
    sinks = [UartSink(dut.tx_o, baud=BAUD * f) for f in factors]
    quiet_uart_logs(dut.tx_o)
    data = bytes([0x00, 0xFF, 0x0F, 0xF0]) + bytes(rng.randrange(256) for _ in range(36))
    await drv.send(data)
    await Timer(2 * FRAME_PS, unit="ps")
    for f, mon, sink in zip(factors, mons, sinks):
        check_monitor(mon, data, f"receiver at {f:.2f} x BAUD")
        assert bytes(sink.read_nowait()) == data, f"UartSink at {f:.2f} x BAUD"


@cocotb.test()
async def test_tx_reset_mid_frame(dut) -> None:
    """rst in the middle of a frame: the line goes high (idle) at once and the next byte is
    sent whole."""
    drv, (mon,), rng = await tx_setup(dut)
    await drv.send(bytes([0x00]))
    await Timer(3 * BIT_PS, unit="ps")
    await RisingEdge(dut.clk)
    dut.rst.value = 1
    await RisingEdge(dut.clk)
    dut.rst.value = 0
    await ReadOnly()
    assert dut.tx_o.value == 1 and dut.s_axis_tready.value == 1
    await RisingEdge(dut.clk)
    await Timer(FRAME_PS, unit="ps")
    await RisingEdge(dut.clk)
    # The cut frame's data bits read as the idle 1s: whatever the monitor made of it, start
    # afresh from here.
    mon.errors.clear()
    n_before = len(mon.frames)
    byte = rng.randrange(256)
    await drv.send(bytes([byte]))
    await Timer(2 * FRAME_PS, unit="ps")
    assert not mon.errors, mon.errors
    assert mon.data[n_before:] == bytes([byte]), mon.data.hex()


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_uart_tx(sim: str, build: str) -> None:
    runner.run(sim, "bsd_uart_tx", __file__, BUILDS[build], build)
