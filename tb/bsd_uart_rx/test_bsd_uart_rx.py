# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_uart_rx (8N1 receiver), and their pytest entry: bytes from cocotbext-uart,
baud mismatch, glitches, framing errors (tb/lib/uart_unit.py has the shared set-up).
"""

from __future__ import annotations

import random

import cocotb
import pytest
from cocotb.triggers import ReadOnly, RisingEdge, Timer
from cocotbext.uart import UartSource

from uart_line import LineMonitor, drive_frame, drive_low, now_ps, quiet_uart_logs
from uart_unit import BAUD, BIT_PS, BUILDS, DIV, FRAME_PS, PERIOD_PS, idle, rng_for, start_clock_and_reset
import runner


class RxCollector:
    """Records uart_rx's valid_o strobes (time, byte) and frame_err_o strobes (time)."""

    def __init__(self, dut) -> None:
        self.dut = dut
        self.bytes: list[tuple[int, int]] = []
        self.errors: list[int] = []
        cocotb.start_soon(self._valid())
        cocotb.start_soon(self._err())

    async def _valid(self) -> None:
        while True:
            await RisingEdge(self.dut.valid_o)
            await ReadOnly()
            self.bytes.append((now_ps(), int(self.dut.data_o.value)))

    async def _err(self) -> None:
        while True:
            await RisingEdge(self.dut.frame_err_o)
            self.errors.append(now_ps())

    @property
    def data(self) -> bytes:
        return bytes(b for _, b in self.bytes)


async def rx_setup(dut) -> tuple[RxCollector, random.Random]:
    rng = rng_for(dut)
    dut.rx_i.value = 1
    await start_clock_and_reset(dut)
    return RxCollector(dut), rng


@cocotb.test()
async def test_rx_bytes(dut) -> None:
    """Back-to-back bytes at the nominal rate: all received, none flagged, and each valid_o
    strobe comes at the middle of the stop bit (+ the 2-flop synchronizer's latency)."""
    col, rng = await rx_setup(dut)
    src = UartSource(dut.rx_i, baud=BAUD)
    starts = LineMonitor(dut.rx_i, BAUD)  # the host's own frames, for their start times
    quiet_uart_logs(dut.rx_i)
    data = bytes([0x00, 0xFF, 0x55, 0xAA, 0x01, 0x80]) + bytes(rng.randrange(256) for _ in range(58))
    await idle(0.3)  # asynchronous to the clock
    await Timer(rng.randrange(PERIOD_PS), unit="ps")
    await src.write(data)
    await src.wait()
    await idle(1)
    assert col.data == data, f"received {col.data.hex()} sent {data.hex()}"
    assert not col.errors, f"framing errors at {col.errors}"
    assert starts.data == data and not starts.errors
    # Sampling point, in the receiver's own time base: the start edge reaches the FSM 2..3
    # clocks later (synchronizer), the stop bit's middle is DIV/2 + 9 * DIV clocks after that,
    # and valid_o is set on that very edge.
    for (t_start, _), (t_valid, _) in zip(starts.frames, col.bytes):
        clocks = (t_valid - t_start) / PERIOD_PS - (DIV // 2 + 9 * DIV)
        assert 2 < clocks <= 3.001, (
            f"valid_o {clocks:.2f} clocks after the stop bit's middle (expected 2..3)")


@cocotb.test()
async def test_rx_baud_mismatch(dut) -> None:
    """A host 2 % (and 3 %) slower or faster than the receiver, bytes back to back: every
    byte received, no framing error."""
    col, rng = await rx_setup(dut)
    quiet_uart_logs(dut.rx_i)
    expected = b""
    for factor in (0.98, 1.02, 0.97, 1.03):
        src = UartSource(dut.rx_i, baud=BAUD * factor)
        data = bytes([0x00, 0xFF, 0x7F, 0xFE]) + bytes(rng.randrange(256) for _ in range(28))
        await Timer(rng.randrange(PERIOD_PS), unit="ps")
        await src.write(data)
        await src.wait()
        await idle(1)
        src._run_cr.cancel()  # the next rate gets its own source on the same line
        expected += data
        assert col.data == expected, f"host at {factor:.2f} x BAUD: received {col.data.hex()}"
        assert not col.errors, f"host at {factor:.2f} x BAUD: framing errors"


@cocotb.test()
async def test_rx_glitch(dut) -> None:
    """Low pulses shorter than half a bit (1 clock .. 0.45 bit) are not start bits: no byte,
    no error, and a real frame right after is received. A 0.7-bit pulse is a start bit
    (the line then reads 1s: byte 0xFF), so the threshold really lies at half a bit."""
    col, rng = await rx_setup(dut)
    for clocks in (1, 2, 5, DIV // 4, round(0.45 * DIV)):
        await Timer(rng.randrange(PERIOD_PS), unit="ps")
        await drive_low(dut.rx_i, clocks * PERIOD_PS)
        await idle(1.5)
        assert not col.bytes and not col.errors, f"a {clocks}-clock glitch was taken as a frame"
    # A glitch, one bit of idle, then a real frame.
    for byte in (0x3C, 0x00):
        await drive_low(dut.rx_i, round(0.4 * BIT_PS))
        await Timer(BIT_PS, unit="ps")
        await drive_frame(dut.rx_i, byte, BIT_PS)
        await idle(0.5)
    assert col.data == bytes([0x3C, 0x00]) and not col.errors, col.data.hex()
    await drive_low(dut.rx_i, round(0.7 * BIT_PS))
    await idle(1.5)
    assert col.data == bytes([0x3C, 0x00, 0xFF]) and not col.errors, col.data.hex()


@cocotb.test()
async def test_rx_framing(dut) -> None:
    """A frame whose stop bit is 0 is dropped with one frame_err_o strobe; a break (line low
    for 3 frames) gives exactly one error and no bytes; the receiver resynchronizes on the
    next start bit after the line returns high."""
    col, rng = await rx_setup(dut)
    await drive_frame(dut.rx_i, 0xA5, BIT_PS, stop=0, idle_after=BIT_PS)
    await idle(0.5)
    assert not col.bytes and len(col.errors) == 1, (col.bytes, col.errors)
    await drive_frame(dut.rx_i, 0x5A, BIT_PS)
    await idle(0.5)
    assert col.data == bytes([0x5A]) and len(col.errors) == 1
    # Break, then a good frame 2 bits after the line returns high.
    await drive_low(dut.rx_i, 3 * FRAME_PS)
    await Timer(2 * BIT_PS, unit="ps")
    await drive_frame(dut.rx_i, 0xC3, BIT_PS)
    await idle(0.5)
    assert col.data == bytes([0x5A, 0xC3]) and len(col.errors) == 2, (col.data.hex(), col.errors)
    # A bad stop bit that stays low for half a bit more, then a good frame right away.
    byte = rng.randrange(256)
    await drive_frame(dut.rx_i, 0x00, BIT_PS, stop=0)
    dut.rx_i.value = 0
    await Timer(BIT_PS // 2, unit="ps")
    dut.rx_i.value = 1
    await Timer(BIT_PS, unit="ps")
    await drive_frame(dut.rx_i, byte, BIT_PS)
    await idle(0.5)
    assert col.data == bytes([0x5A, 0xC3, byte]) and len(col.errors) == 3, (col.data.hex(), col.errors)


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_uart_rx(sim: str, build: str) -> None:
    runner.run(sim, "bsd_uart_rx", __file__, BUILDS[build], build)
