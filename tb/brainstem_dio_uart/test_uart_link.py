# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of brainstem_dio_uart over its serial pins, with cocotbext-uart as the host,
and their pytest entry.

Builds (small FIFOs make overflow cheap to reach; the board keeps the default 512):
- b9600: 9600 baud from 2 MHz (208 clocks per bit; 2 MHz is the core's lowest clock) with
  the wrapper's default heartbeat (HB_RATE 10 = 256 ms) and an 8-byte FIFO;
- b115200: 115 200 baud from 2.304 MHz (20 clocks per bit) with a 25.6 ms heartbeat
  (HB_RATE 1) and a 16-byte FIFO;
- b9600-deep (make test-full): the b9600 build again, for the three tests (FIFO overflow, pins
  and strobes, every pin an output) whose logic b115200 runs in make test and that cost most
  at 208 clocks a bit.
Icarus is several times slower on the whole module, and a 9600-baud byte is 2083 clocks, so
on Icarus the 9600-baud build runs only the worked examples; the 115200-baud build runs
everything on both.

Every reply is checked against the reference model (tb/lib/bsd_model.py): the model is fed exactly the bytes the core received, so a test that
loses bytes on purpose (framing errors, FIFO overflow) still gets an exact expectation.

The host (`Host`) behaves as the original host library: it splits the byte stream into
packets by their length byte and echoes every heartbeat `A, 2, 0, t` with `A, 2, 0, t + 2`
(whole packets, between the test's own packets). Heartbeats are kept apart from the other
packets, which the tests compare with the model. Every byte the module sends is also read by
a strict receiver (uart_line.LineMonitor) that checks stop bits and frame timing.
Random data is seeded from cocotb's seed, printed at the start of each test.
"""

from __future__ import annotations

import random

import cocotb
import pytest
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, Event, First, ReadOnly, RisingEdge, Timer
from cocotbext.uart import UartSink, UartSource

from bsd_model import (
    CMD_DEBUG,
    CMD_DEV_VAL,
    CMD_DIG_CFG,
    CMD_DIG_IO,
    CMD_DIG_RST,
    CMD_HB,
    CMD_PTIME_RD,
    CMD_RESET,
    DEVCODE_HOST,
    DEVCODE_RFLX,
    DIGCFG_ENA,
    DIGCFG_IODIR,
    DIGCFG_TRG,
    DIGCFG_TSTATE,
    HB_ANSWER,
    HB_UNIT_S,
    RESYNC_ADDR,
    TICK_HZ,
    Model,
    Output,
    Params,
    message,
    packet,
    ticks_close,
)
from bsd_protocol import MAX_N as MAX_DATA
from bsd_protocol import MSG_CMD_Q_OVERFLOW
import runner
from runner import hdl_params
from uart_line import LineMonitor, drive_frame, drive_low, now_ps, quiet_uart_logs

BUILDS = {
    "b9600": {**Params(clk_hz=2_000_000, hb_rate=10).to_hdl(), "BAUD": 9600, "FIFO_DEPTH": 8},
    "b115200": {**Params(clk_hz=2_304_000, hb_rate=1).to_hdl(), "BAUD": 115_200, "FIFO_DEPTH": 16},
}
BUILDS["b9600-deep"] = BUILDS["b9600"]
SLOW = runner.on("b9600-deep")  # the tests b9600 ran already skip it


P = Params.from_env()
BAUD = int(hdl_params().get("BAUD", 9600))
DEPTH = int(hdl_params().get("FIFO_DEPTH", 8))
A = P.module_addr
DIV = (P.clk_hz + BAUD // 2) // BAUD  # clocks per bit, as the RTL rounds it
PERIOD_PS = round(1e12 / P.clk_hz)
BIT_PS = DIV * PERIOD_PS
FRAME_PS = 10 * BIT_PS
FIFO_LATENCY = 3  # clocks from bsd_uart_rx's valid_o to the core taking the byte (FIFO empty)


def hexs(data) -> str:
    return " ".join(f"{b:02X}" for b in data)


class Host:
    """The host end of the serial line (cocotbext-uart source and sink)."""

    def __init__(self, dut) -> None:
        self.dut = dut
        self.src = UartSource(dut.rx, baud=BAUD)
        self.sink = UartSink(dut.tx, baud=BAUD)
        self.mon = LineMonitor(dut.tx, BAUD)
        quiet_uart_logs(dut.rx, dut.tx)
        self.auto_answer = True
        self.received = bytearray()                   # every byte, in order
        self.packets: list[tuple[int, bytes]] = []    # (t_ps, packet), heartbeats excluded
        self.heartbeats: list[tuple[int, int]] = []   # (t_ps, type)
        self.answers = bytearray()                     # heartbeat answers sent, in order
        self.errors: list[str] = []
        self._n = 0
        self._got = Event()
        self._buf = bytearray()
        cocotb.start_soon(self._rx())

    async def _rx(self) -> None:
        while True:
            for byte in await self.sink.read():
                self.received.append(byte)
                if not self._buf:
                    self._t_first = now_ps()
                self._buf.append(byte)
                if len(self._buf) == 2 and byte > 8:
                    self.errors.append(f"packet with N = {byte}")
                if len(self._buf) >= 2 and len(self._buf) == self._buf[1] + 2:
                    self._packet(self._t_first, bytes(self._buf))
                    self._buf = bytearray()

    def _packet(self, t: int, pkt: bytes) -> None:
        if len(pkt) == 4 and pkt[0] == A and pkt[2] == CMD_HB and pkt[3] in (0, 1):
            self.heartbeats.append((t, pkt[3]))
            if self.auto_answer:
                answer = packet(A, CMD_HB, pkt[3] + HB_ANSWER)
                self.answers += answer
                self.src.write_nowait(answer)
        else:
            self.packets.append((t, pkt))
        self._got.set()

    async def send(self, data: bytes) -> None:
        """Queue bytes (whole packets: heartbeat answers go between them) and wait until the
        last one has left the host."""
        self.src.write_nowait(data)
        await self.src.wait()

    def new_packets(self) -> list[bytes]:
        got = [p for _, p in self.packets[self._n:]]
        self._n = len(self.packets)
        return got

    async def wait_packets(self, count: int, timeout_ps: int) -> None:
        deadline = now_ps() + timeout_ps
        while len(self.packets) - self._n < count and now_ps() < deadline:
            self._got.clear()
            await First(self._got.wait(), Timer(deadline - now_ps(), unit="ps"))

    async def quiet(self, frames: int = 3) -> None:
        """Wait until the module has sent nothing for `frames` byte times."""
        while True:
            n = len(self.received)
            await Timer(frames * FRAME_PS, unit="ps")
            if len(self.received) == n and not self._buf:
                return

    async def expect(self, exp: list[bytes], what: str = "", extra_frames: int = 12) -> None:
        """The model's packets, exactly (none missing, none extra), heartbeats aside."""
        n_bytes = sum(len(p) for p in exp)
        await self.wait_packets(len(exp), (n_bytes + 40) * FRAME_PS)
        await Timer(extra_frames * FRAME_PS, unit="ps")
        got = self.new_packets()
        assert got == exp, (f"after {what}: expected [{'; '.join(hexs(p) for p in exp)}] "
                            f"got [{'; '.join(hexs(p) for p in got)}]")
        self.check_line()

    async def command(self, model: Model, pkt: bytes) -> None:
        exp = model.feed(pkt)
        await self.send(pkt)
        await self.expect(exp.packets, hexs(pkt))

    def check_line(self) -> None:
        assert not self.errors, self.errors
        assert not self.mon.errors, self.mon.errors[:3]
        # The strict receiver and cocotbext-uart's agree on every byte so far (the sink
        # queues a byte half a bit before the monitor).
        mon = self.mon.data
        assert bytes(self.received[:len(mon)]) == mon and len(self.received) - len(mon) <= 1


class Strobes:
    """Times of one-clock strobes of the DUT: frame_err, rx_overflow, and bsd_uart_rx's valid_o
    with the byte and whether the FIFO dropped it. Also counts overflow bursts as the
    wrapper defines them: a dropped byte starts one unless no byte was dropped since the
    RX FIFO was last empty (the FIFO's empty_o)."""

    def __init__(self, dut) -> None:
        self.dut = dut
        self.frame_err: list[int] = []
        self.rx: list[tuple[int, int, bool]] = []  # (t_ps, byte, dropped)
        self.bursts = 0
        self._emptied = True
        self.overflow: list[int] = []
        cocotb.start_soon(self._count(dut.frame_err, self.frame_err))
        cocotb.start_soon(self._count(dut.rx_overflow, self.overflow))
        cocotb.start_soon(self._rx())
        cocotb.start_soon(self._empty())

    async def _empty(self) -> None:
        empty = self.dut.u_fifo.empty_o
        while True:
            await RisingEdge(empty)
            self._emptied = True

    async def _count(self, sig, out: list[int]) -> None:
        while True:
            await RisingEdge(sig)
            out.append(now_ps())

    async def _rx(self) -> None:
        valid = self.dut.u_rx.valid_o
        while True:
            await RisingEdge(valid)
            await ReadOnly()
            dropped = int(self.dut.u_fifo.s_axis_tready.value) == 0
            self.rx.append((now_ps(), int(self.dut.u_rx.data_o.value), dropped))
            if dropped and self._emptied:
                self.bursts += 1
                self._emptied = False

    def kept(self, since: int = 0) -> bytes:
        return bytes(b for _, b, dropped in self.rx[since:] if not dropped)

    def dropped(self, since: int = 0) -> int:
        return sum(1 for _, _, d in self.rx[since:] if d)


async def setup(dut, pins: int = 0) -> tuple[Host, Model, Strobes, random.Random]:
    seed = cocotb.RANDOM_SEED
    dut._log.info("params %s, baud %d (%d clocks per bit), FIFO %d, seed %d",
                  P.to_json(), BAUD, DIV, DEPTH, seed)
    rng = random.Random(seed)
    dut.rst.value = 1
    dut.pin_i.value = pins
    cocotb.start_soon(Clock(dut.clk, PERIOD_PS, unit="ps", impl="gpi",
                            period_high=PERIOD_PS // 2).start())
    host = Host(dut)
    strobes = Strobes(dut)
    model = Model(P, pins)
    await ClockCycles(dut.clk, 5)
    dut.rst.value = 0
    await RisingEdge(dut.clk)
    host.t_reset = now_ps()
    await host.expect(model.reset(pins).packets, "reset")
    return host, model, strobes, rng


def overflow_msg() -> bytes:
    return message(A, MSG_CMD_Q_OVERFLOW)


# ================================================================================ tests

@cocotb.test(skip=SLOW)
async def test_worked_examples(dut) -> None:
    """docs/PROTOCOL.md §7 over the serial line, in order, every reply from the model; the timer
    example measures 800 us from the core's acceptance of the PTIME_RD's last byte."""
    pins = 0b10001  # pin 0 reads 1; pin 4 high so its edge timer (target 0) waits for a fall
    host, m, strobes, rng = await setup(dut, pins)
    for pkt in (packet(A, CMD_DIG_CFG, 3), packet(A, CMD_DIG_CFG, 1, 0x00),
                packet(A, CMD_DIG_IO, 1, 1)):
        await host.command(m, pkt)
    await ReadOnly()
    assert (int(dut.pin_oe.value), int(dut.pin_o.value)) == (m.pin_oe(), m.pin_o()) == (0b10, 0b10)
    await RisingEdge(dut.clk)
    for pkt in (packet(A, CMD_DIG_IO, DEVCODE_HOST | 0), packet(A, CMD_DIG_IO, DEVCODE_HOST | 1),
                packet(A, CMD_DIG_CFG, 7, 0x01), packet(A, CMD_PTIME_RD, DEVCODE_HOST | 0)):
        await host.command(m, pkt)
    # Time pin 4: the pad falls 800 us after the last byte is accepted (asynchronously).
    pkt = packet(A, CMD_PTIME_RD, DEVCODE_HOST | 4)
    assert not m.feed(pkt)
    n_rx = len(strobes.rx)
    await host.send(pkt)
    # Its last byte's valid_o strobe (a heartbeat answer may have gone just before it).
    rx = strobes.rx[n_rx:]
    i = bytes(b for _, b, _ in rx).rfind(pkt)
    assert i >= 0 and not any(d for _, _, d in rx), "the PTIME_RD did not reach the core whole"
    t_accept = rx[i + len(pkt) - 1][0] + FIFO_LATENCY * PERIOD_PS
    off = rng.randrange(PERIOD_PS)
    await Timer(t_accept + 800_000_000 + off - now_ps(), unit="ps")
    dut.pin_i.value = pins & ~0b10000
    await Timer(100_000_000, unit="ps")
    dut.pin_i.value = pins
    await host.wait_packets(1, 20 * FRAME_PS)
    got = host.packets[host._n][1] if len(host.packets) > host._n else b""
    assert len(got) == 6 and got[2] == CMD_DEV_VAL and got[3] == P.timer_id(4), hexs(got)
    ticks = got[4] << 8 | got[5]
    interval = (800_000_000 + off) / 1e12
    assert abs(ticks - 500) <= 1 and ticks_close(ticks, interval, P.clk_hz), f"{ticks} ticks for 800 us"
    await host.expect(m.timer_complete(4, ticks).packets, "the timer result")
    for pkt in (packet(A, CMD_DIG_CFG), packet(A, CMD_DIG_CFG, 2, 0x01, 0xFF), packet(A, 0x63),
                packet(RESYNC_ADDR), packet(A, CMD_DEBUG, 1, 2)):
        await host.command(m, pkt)
    assert not strobes.frame_err and not strobes.dropped()


def random_command(rng: random.Random, reply: bool) -> bytes:
    """A command that does (reply=True) or does not produce a reply packet, pins static."""
    pins_plus = P.num_pins + 2
    if reply:
        kind = rng.randrange(7)
        if kind == 0:
            return packet(A, CMD_DIG_CFG, rng.randrange(pins_plus))           # query / index err
        if kind == 1:
            return packet(A, CMD_DIG_IO, DEVCODE_HOST | rng.randrange(pins_plus))  # read / err
        if kind == 2:
            return packet(A, rng.choice([1, 4, 0x63, 0x80]))                   # cmdInvalid
        if kind == 3:
            return packet(A, rng.choice([CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST]))  # too short
        if kind == 4:
            return packet(RESYNC_ADDR)
        if kind == 5:
            return packet(A, CMD_DEBUG, *rng.randbytes(rng.randrange(MAX_DATA)))  # echo, N 1..8
        return packet(A, CMD_DIG_RST, rng.randrange(P.num_pins), 0)            # too long
    kind = rng.randrange(4)
    pin = rng.randrange(P.num_pins)
    if kind == 0:
        return packet(A, CMD_DIG_CFG, pin, rng.choice([0x00, 0x01, 0x03, 0x05]))
    if kind == 1:
        return packet(A, CMD_DIG_IO, pin, rng.randrange(2))  # write (cmdIndexErr if input)
    if kind == 2:
        return packet(A + 2, CMD_DIG_CFG, pin)                # another module's packet
    return packet(A, CMD_DIG_RST, pin)


@cocotb.test(skip=runner.on("b9600", sims=["icarus"]) or SLOW)
async def test_back_to_back(dut) -> None:
    """Random commands sent back to back at the full line rate (no idle bit between frames):
    every reply as the model's, no byte lost, and each reply packet leaves at the full line
    rate too (its frames exactly 10 bit times apart)."""
    host, m, strobes, rng = await setup(dut, pins=0b10101 & ((1 << P.num_pins) - 1))
    count = 24 if BAUD < 100_000 else 80
    stream = b""
    for i in range(count):
        # A no-reply command after each reply keeps the backlog far below the FIFO depth.
        stream += random_command(rng, reply=(i % 2 == 0))
    exp = m.feed(stream)
    n_mon = len(host.mon.frames)
    await host.send(stream)
    await host.expect(exp.packets, "the back-to-back stream", extra_frames=20)
    # Heartbeat answers due during the stream were queued behind it.
    assert strobes.kept() == stream + bytes(host.answers), "the core did not get every byte"
    assert not strobes.frame_err and not strobes.dropped(), "a byte was lost"
    await ReadOnly()
    assert (int(dut.pin_oe.value), int(dut.pin_o.value)) == (m.pin_oe(), m.pin_o())
    # Frame timing of every reply packet, from the strict monitor.
    frames = host.mon.frames[n_mon:]
    i = 0
    while i < len(frames):
        n = frames[i + 1][1] + 2 if i + 1 < len(frames) else 1
        for k in range(i + 1, min(i + n, len(frames))):
            gap = frames[k][0] - frames[k - 1][0]
            assert gap == FRAME_PS, f"bytes of one packet {gap / PERIOD_PS} clocks apart"
        i += n


@cocotb.test(skip=runner.on("b9600", sims=["icarus"]) or SLOW)
async def test_framing_error(dut) -> None:
    """Malformed frames on the line (stop bit 0) are dropped and flagged: one between two
    packets changes nothing; one inside a packet leaves it incomplete, so the core drops it
    after RX_TIMEOUT_US and serves the next packet; a break gives one error and no byte."""
    host, m, strobes, rng = await setup(dut, pins=0b00001)
    host.auto_answer = False  # a heartbeat answer must not land in the broken packet
    q = packet(A, CMD_DIG_IO, DEVCODE_HOST | 0)
    await host.command(m, q)
    # A bad frame between packets.
    await drive_frame(dut.rx, rng.randrange(256), BIT_PS, stop=0, idle_after=2 * BIT_PS)
    assert len(strobes.frame_err) == 1
    await host.command(m, packet(A, CMD_DIG_CFG, 2))
    # A bad frame as the last byte of a packet: the rest waits for a byte that never comes.
    part = packet(A, CMD_DIG_CFG, 3)
    await host.send(part[:-1])
    await drive_frame(dut.rx, part[-1], BIT_PS, stop=0, idle_after=BIT_PS)
    assert len(strobes.frame_err) == 2
    assert not m.feed(part[:-1])
    await Timer(int((P.rx_timeout_us * 1e-6 + 0.002) * 1e12), unit="ps")
    m.idle(P.rx_timeout_us * 1e-6 + 0.002)
    await host.expect([], "a packet cut by a framing error")
    await host.command(m, packet(A, CMD_DIG_CFG, 3))
    # A break: the line low for 3 frame times; then good packets.
    await drive_low(dut.rx, 3 * FRAME_PS)
    await Timer(2 * BIT_PS, unit="ps")
    assert len(strobes.frame_err) == 3, strobes.frame_err
    host.auto_answer = True
    await host.command(m, q)
    await host.command(m, packet(RESYNC_ADDR))
    assert len(strobes.frame_err) == 3 and not strobes.dropped()
    # Only the good frames reached the core.
    assert strobes.kept() == (q + packet(A, CMD_DIG_CFG, 2) + part[:-1] + packet(A, CMD_DIG_CFG, 3)
                              + q + packet(RESYNC_ADDR)), hexs(strobes.kept())


async def flood(host: Host, m: Model, strobes: Strobes, commands: int) -> tuple[list[bytes], int, int]:
    """Send `commands` x `A, 1, 0x63` back to back (3 bytes in, a 4-byte cmdInvalid out: the
    input outruns the output) and wait until the module is quiet. Feeds the model exactly
    the bytes the FIFO kept; returns the core's expected packets, the bytes dropped and the
    overflow bursts. (A loss can turn the rest of the stream into packets the core consumes
    silently, e.g. `63 02 01 ..` to address 0x63; then the FIFO may run empty and a later
    loss is a new burst.)"""
    n_rx, n_bursts = len(strobes.rx), strobes.bursts
    await host.send(packet(A, 0x63) * commands)
    await host.quiet()
    exp = m.feed(strobes.kept(n_rx))
    return exp.packets, strobes.dropped(n_rx), strobes.bursts - n_bursts


@cocotb.test(skip=runner.on("b9600"))
async def test_fifo_overflow(dut) -> None:
    """The host outruns the module: bytes that find the RX FIFO full are dropped, the core
    gets exactly the kept bytes (its replies as the model's for them), and cmdQOverflow
    `A, 2, 0x80, 12` comes once per overflow burst, whole, between packets. After the
    partial packet left by the loss times out, the next good packet is served."""
    host, m, strobes, rng = await setup(dut)
    host.auto_answer = False
    commands = 3 * (DEPTH + 6)
    exp, dropped, bursts = await flood(host, m, strobes, commands)
    got = host.new_packets()
    dut._log.info("flood of %d commands: %d bytes dropped in %d bursts", commands, dropped, bursts)
    assert dropped > 0 and bursts >= 1, "the flood never overflowed the FIFO"
    assert len(strobes.overflow) == dropped, "rx_overflow pulses != bytes dropped"
    assert got.count(overflow_msg()) == bursts, [hexs(p) for p in got]
    t_msg = [t for t, p in host.packets if p == overflow_msg()][0]
    t_drop = min(t for t, _, d in strobes.rx if d)
    assert t_msg > t_drop
    assert [p for p in got if p != overflow_msg()] == exp, "core replies differ from the model"
    # No byte was dropped before the FIFO could be full: the input gains 1 byte per
    # command on the output, so the first loss comes after more than DEPTH commands.
    first_drop = [i for i, (_, _, d) in enumerate(strobes.rx) if d][0]
    assert first_drop >= 3 * DEPTH, f"first byte dropped at byte {first_drop}"
    # A second burst, after the FIFO emptied: a second message.
    # (DEPTH + 40 commands gain DEPTH + 40 bytes: more than the FIFO and the register
    # slices around the core hold.)
    exp, dropped, bursts = await flood(host, m, strobes, DEPTH + 40)
    got = host.new_packets()
    dut._log.info("second flood: %d bytes dropped in %d bursts", dropped, bursts)
    assert dropped > 0 and bursts >= 1 and got.count(overflow_msg()) == bursts, [hexs(p) for p in got]
    assert [p for p in got if p != overflow_msg()] == exp
    # Recovery: wait out RX_TIMEOUT_US (the loss may have left a partial packet), then serve.
    await Timer(int((P.rx_timeout_us * 1e-6 + 0.002) * 1e12), unit="ps")
    m.idle(P.rx_timeout_us * 1e-6 + 0.002)
    host.auto_answer = True
    await host.expect([], "the timeout after the floods")
    await host.command(m, packet(A, CMD_DIG_CFG, 3))
    await host.command(m, packet(A, CMD_DIG_IO, DEVCODE_HOST | 2))
    assert not strobes.frame_err


@cocotb.test(skip=not runner.on("b115200"))
async def test_heartbeat_host(dut) -> None:
    """The heartbeat answered by the host model as the original host library does: UP/DOWN
    heartbeats one period apart from reset, link_up rising on the answers and staying up
    while the host answers; falling at the first heartbeat due while the previous one is
    unanswered; back up on the next answer. Commands are served in between."""
    host, m, strobes, rng = await setup(dut)
    period_ps = round(P.hb_rate * HB_UNIT_S * 1e12)
    tol = 2 * FRAME_PS
    assert int(dut.link_up.value) == 0

    async def link_up_before(k: float) -> int:
        """link_up just before heartbeat k falls due."""
        await Timer(host.t_reset + round(k * period_ps) - 20 * PERIOD_PS - now_ps(), unit="ps")
        await ReadOnly()
        v = int(dut.link_up.value)
        await RisingEdge(dut.clk)
        return v

    assert await link_up_before(1) == 0
    assert await link_up_before(2) == 1  # heartbeat 1 answered
    host.auto_answer = False
    await host.command(m, packet(A, CMD_DIG_CFG, 1))
    assert await link_up_before(3) == 1  # heartbeat 2 unanswered: down when 3 falls due
    await Timer(40 * PERIOD_PS, unit="ps")
    assert int(dut.link_up.value) == 0
    while len(host.heartbeats) < 3:  # heartbeat 3 stays unanswered too
        await Timer(BIT_PS, unit="ps")
    host.auto_answer = True
    assert await link_up_before(4) == 0
    assert await link_up_before(5) == 1  # heartbeat 4 answered
    times = [t for t, _ in host.heartbeats][:4]
    types = [k for _, k in host.heartbeats][:4]
    assert types == [0, 1, 0, 1], types
    for k, t in enumerate(times, start=1):
        # The host sees a heartbeat when its first byte has arrived (9.5 bits after its start).
        late = t - host.t_reset - k * period_ps
        assert 0 <= late <= tol, f"heartbeat {k} {late / 1e6:.1f} us after its due time"
    host.check_line()


@cocotb.test(skip=not runner.on("b115200"))
async def test_reset_with_queue(dut) -> None:
    """cmdRESET over the serial line with commands queued behind it in the RX FIFO (one
    back-to-back burst): the power-up message first, then every queued command's reply as
    the model's, no byte dropped; link_up falls with the reset, and the heartbeat starts
    again from UP one period after it."""
    host, m, strobes, rng = await setup(dut, pins=0b10101 & ((1 << P.num_pins) - 1))
    period_ps = round(P.hb_rate * HB_UNIT_S * 1e12)
    await Timer(host.t_reset + round(1.5 * period_ps) - now_ps(), unit="ps")
    assert int(dut.link_up.value) == 1, "heartbeat 1 answered: the link is up"
    for pin in (1, 3):
        await host.command(m, packet(A, CMD_DIG_CFG, pin, 0x00))
    n_rx, n_hb = len(strobes.rx), len(host.heartbeats)
    burst = packet(A, CMD_RESET, *rng.randbytes(rng.randrange(MAX_DATA)))
    reset_len = len(burst)
    for i in range(12):
        burst += random_command(rng, reply=(i % 2 == 0))
    exp = m.feed(burst)
    await host.send(burst)
    await host.expect(exp.packets, "cmdRESET with commands queued behind it", extra_frames=20)
    assert strobes.kept(n_rx).startswith(burst) and not strobes.dropped(n_rx), "a byte was lost"
    assert (int(dut.pin_oe.value), int(dut.pin_o.value)) == (m.pin_oe(), m.pin_o())
    assert int(dut.link_up.value) == 0, "link_up after cmdRESET, before a heartbeat is answered"
    # The reset took effect a few clocks after its last byte left the UART receiver.
    t_rst = strobes.rx[n_rx + reset_len - 1][0]
    while len(host.heartbeats) < n_hb + 1:
        await Timer(BIT_PS, unit="ps")
    t_hb, kind = host.heartbeats[n_hb]
    assert kind == 0, "the first heartbeat after cmdRESET is UP"
    late = t_hb - t_rst - period_ps
    assert 0 <= late <= 2 * FRAME_PS + 20 * PERIOD_PS, f"first heartbeat {late / 1e6:.1f} us off"
    host.check_line()


@cocotb.test(skip=not runner.on("b9600", sims=["verilator"]))
async def test_heartbeat_default_rate(dut) -> None:
    """The wrapper's default HB_RATE (10 = 256 ms, the original module's): the first
    heartbeat (UP) comes 256 ms after reset; the host's answer raises link_up."""
    host, m, strobes, rng = await setup(dut)
    assert P.hb_rate == 10
    period_ps = round(10 * HB_UNIT_S * 1e12)
    await Timer(host.t_reset + period_ps - 2 * FRAME_PS - now_ps(), unit="ps")
    assert not host.heartbeats and int(dut.link_up.value) == 0
    await Timer(7 * FRAME_PS, unit="ps")  # its 4 bytes
    assert [k for _, k in host.heartbeats] == [0], host.heartbeats
    late = host.heartbeats[0][0] - host.t_reset - period_ps
    assert 0 <= late <= 2 * FRAME_PS, f"{late / 1e6:.1f} us late"
    await Timer(8 * FRAME_PS, unit="ps")  # the host's answer: 4 bytes
    assert int(dut.link_up.value) == 1
    await host.expect([], "the heartbeat")


class Pulses:
    """(id, data) of every rflx_valid strobe and the pin of every raw_trans pulse, in order,
    read in the clock each strobe is high (no per-clock loop while idle)."""

    def __init__(self, dut) -> None:
        self.dut = dut
        self.rflx: list[tuple[int, int]] = []
        self.trans: list[int] = []
        cocotb.start_soon(self._watch(dut.rflx_valid, self._rflx))
        cocotb.start_soon(self._watch(dut.raw_trans, self._trans))

    def _rflx(self, _v: int) -> None:
        self.rflx.append((int(self.dut.rflx_id.value), int(self.dut.rflx_data.value)))

    def _trans(self, v: int) -> None:
        self.trans += [p for p in range(P.num_pins) if v >> p & 1]

    async def _watch(self, sig, record) -> None:
        while True:
            await sig.value_change
            while True:
                await ReadOnly()
                v = sig.value
                if not v.is_resolvable or int(v) == 0:
                    break
                record(int(v))
                await RisingEdge(self.dut.clk)


@cocotb.test(skip=runner.on("b9600"))
async def test_pins_latch_rflx(dut) -> None:
    """The wrapper's pin ports and strobes against the model: pins 1..3 as outputs driven 1
    then 0 (pin_o, pin_oe), every pin's transition latch armed for rising edges firing once
    on raw_trans (and not on the fall), a DIG_IO read with RFLX on every pin (rflx_valid,
    rflx_id, rflx_data), and a timer result of 0xFF20-odd ticks (an edge 104.5 ms after the
    start) on RFLX: every bit of rflx_data set and cleared. About 260 k clocks; Icarus runs
    it only in make test-full."""
    host, m, strobes, rng = await setup(dut, 0)
    seen = Pulses(dut)

    async def pins_match(what: str) -> None:
        await ReadOnly()
        got = (int(dut.pin_oe.value), int(dut.pin_o.value))
        assert got == (m.pin_oe(), m.pin_o()), f"after {what}: pin_oe/pin_o {got}"
        await RisingEdge(dut.clk)

    out_pins = [p for p in (1, 2, 3) if not P.is_fixed(p)]
    for p in out_pins:
        await host.command(m, packet(A, CMD_DIG_CFG, p, 0x00))
        for v in (1, 0):
            await host.command(m, packet(A, CMD_DIG_IO, p, v))
            await pins_match(f"pin {p} <- {v}")
    # Every pin an input with its latch armed for rising edges.
    for p in P.pins:
        await host.command(m, packet(A, CMD_DIG_CFG, p, DIGCFG_IODIR | DIGCFG_ENA | DIGCFG_TRG))
    await pins_match("all inputs")
    hold_ps = int(3 * 1e12 / P.poll_hz) if P.poll_hz else 20 * PERIOD_PS
    exp = Output()
    for level in (1, 0):
        for p in P.pins:
            exp.extend(m.set_pin(p, level))
            dut.pin_i.value = m.levels
            await Timer(hold_ps, unit="ps")
    assert exp.trans == list(P.pins) and seen.trans == exp.trans, (
        f"raw_trans pulses {seen.trans}, model {exp.trans}")
    # DIG_IO read with RFLX: the level on the RFLX strobe (pin p high on odd pins).
    levels = sum(1 << p for p in P.pins if p % 2)
    m.set_pins(levels)
    dut.pin_i.value = levels
    await Timer(hold_ps, unit="ps")
    exp = Output()
    for p in P.pins:
        out = m.feed(packet(A, CMD_DIG_IO, DEVCODE_RFLX | p))
        await host.send(packet(A, CMD_DIG_IO, DEVCODE_RFLX | p))
        await host.expect(out.packets, f"RFLX read of pin {p}")
        exp.extend(out)
    assert exp.rflx and seen.rflx == exp.rflx, f"RFLX strobes {seen.rflx}, model {exp.rflx}"
    # A long timer result on RFLX (timer pin, edge mode towards 1, its pad low).
    pin = next(p for p in P.timer_pins if not P.is_fixed(p) and not levels >> p & 1)
    await host.command(m, packet(A, CMD_DIG_CFG, pin, DIGCFG_IODIR | DIGCFG_TSTATE))
    pkt = packet(A, CMD_PTIME_RD, DEVCODE_RFLX | pin)
    assert not m.feed(pkt)
    n_rflx = len(seen.rflx)
    await host.send(pkt)
    interval = 104.5e-3
    await Timer(round(interval * 1e12), unit="ps")  # from the last byte's stop bit: a bit over
    m.set_pin(pin, 1)
    dut.pin_i.value = m.levels
    await Timer(200_000_000, unit="ps")
    new = seen.rflx[n_rflx:]
    assert len(new) == 1 and new[0][0] == P.timer_id(pin), f"RFLX strobes {new}"
    ticks = new[0][1]
    assert 0xFE00 <= ticks < 0xFFFF and abs(ticks - interval * TICK_HZ) < 100, f"{ticks} ticks"
    done = m.timer_complete(pin, ticks)
    assert done.rflx == new and not done.packets, (done, new)
    await host.quiet()
    assert not host.new_packets() and not strobes.frame_err and not strobes.dropped()
    host.check_line()


@cocotb.test(skip=runner.on("b9600"))
async def test_every_pin_output(dut) -> None:
    """Every pin that is not fixed, in turn an output driven 1 then 0: pin_o and pin_oe
    against the model after each command (deterministic: each pin_o bit rises and falls in
    every run, whatever the seed)."""
    host, m, strobes, rng = await setup(dut, 0)
    free = [p for p in P.pins if not P.is_fixed(p)]
    assert free, "no pin to drive"
    for p in free:
        await host.command(m, packet(A, CMD_DIG_CFG, p, 0x00))
        for v in (1, 0):
            await host.command(m, packet(A, CMD_DIG_IO, p, v))
            await ReadOnly()
            got = (int(dut.pin_oe.value), int(dut.pin_o.value))
            assert got == (m.pin_oe(), m.pin_o()), f"pin {p} <- {v}: pin_oe/pin_o {got}"
            assert (m.pin_o() >> p & 1) == v, f"the model's pin {p} is not {v}"
            await RisingEdge(dut.clk)
    assert not strobes.frame_err and not strobes.dropped()
    host.check_line()


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="verilator", deep=["b9600-deep"],
                                                     only=lambda sim, build: (sim, build) != ("icarus", "b9600-deep")))
def test_brainstem_dio_uart(sim: str, build: str) -> None:
    runner.run(sim, "brainstem_dio_uart", __file__, BUILDS[build], build)
