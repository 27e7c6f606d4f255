"""Unit tests of bsd_uart_rx and bsd_uart_tx (cocotb). tb/test_uart.py selects the tests of the
toplevel it built; the clock and baud come from $UART_CLK_HZ / $UART_BAUD.

The host side is cocotbext-uart (UartSource into bsd_uart_rx, UartSink on bsd_uart_tx's line); the
strict tb/uart_line.py LineMonitor checks what cocotbext-uart's receiver does not (stop bits,
frame timing), and malformed frames and glitches are driven by hand. Random data is seeded
from cocotb's seed (printed at the start of each test; COCOTB_RANDOM_SEED=<seed> replays it).
"""

from __future__ import annotations

import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, ReadOnly, RisingEdge, Timer
from cocotbext.uart import UartSink, UartSource

from uart_line import LineMonitor, bit_ps, drive_frame, drive_low, now_ps, quiet_uart_logs

CLK_HZ = int(os.environ.get("UART_CLK_HZ", "12000000"))
BAUD = int(os.environ.get("UART_BAUD", "115200"))
DIV = (CLK_HZ + BAUD // 2) // BAUD  # clocks per bit, as the RTL rounds it
PERIOD_PS = round(1e12 / CLK_HZ)
BIT_PS = DIV * PERIOD_PS  # the DUT's bit time
FRAME_PS = 10 * BIT_PS


def rng_for(dut) -> random.Random:
    seed = cocotb.RANDOM_SEED
    dut._log.info("CLK_HZ %d, BAUD %d (%d clocks per bit), seed %d", CLK_HZ, BAUD, DIV, seed)
    return random.Random(seed)


async def start_clock_and_reset(dut) -> None:
    cocotb.start_soon(Clock(dut.clk, PERIOD_PS, unit="ps", impl="gpi", period_high=PERIOD_PS // 2).start())
    dut.rst.value = 1
    await ClockCycles(dut.clk, 4)
    dut.rst.value = 0
    await RisingEdge(dut.clk)


# ====================================================================== bsd_uart_rx

class RxCollector:
    """Records bsd_uart_rx's valid_o strobes (time, byte) and frame_err_o strobes (time)."""

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


async def idle(frames: float = 1.0) -> None:
    await Timer(round(frames * FRAME_PS), unit="ps")


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


# ====================================================================== bsd_uart_tx

class TxDriver:
    """Offers bytes on bsd_uart_tx's s_axis (AXI-Stream rules) and records handshake times."""

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
