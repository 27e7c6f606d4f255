# SPDX-License-Identifier: Apache-2.0
"""cocotb testbench for brainstem_dio: clock, reset, AXI-Stream source/sink, pin drivers and
monitors, and helpers that check the core against the reference model (bsd_model.py).

Times: the TB measures simulation time in ps and converts it to "core seconds" = clock
cycles / CLK_HZ, because the simulated clock period is rounded to whole ps (48 MHz runs at
20.833 ns) while the core counts time in cycles of its nominal CLK_HZ. Every time this module
hands out (`now_s`, acceptance times, packet times) is in core seconds.

Sampling discipline: everything is driven right after a rising edge and sampled in
ReadOnly() of the same time step, i.e. the values the *next* rising edge will see. That
avoids the race of reading outputs right after the edge, which each simulator resolves
differently.
"""

from __future__ import annotations

import os
import random
from collections import deque
from dataclasses import dataclass, field
from typing import Iterable, Sequence

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, Event, First, ReadOnly, RisingEdge, Timer
from cocotb.utils import get_sim_time

import fcov
from bsd_model import MAX_DATA, Model, Output, Params


class TBError(AssertionError):
    """A protocol-rule or model mismatch seen by the testbench."""


def _hex(data: Iterable[int]) -> str:
    return " ".join(f"{b:02X}" for b in data)


@dataclass
class RxPacket:
    data: bytes
    t_first: float  # core seconds of the first and last byte's transfer
    t_last: float


@dataclass
class _Send:
    data: bytes
    gap_cycles: int
    times: list[float] = field(default_factory=list)
    done: Event = field(default_factory=Event)


class AxisSource:
    """Host -> core byte stream driver. Holds tvalid/tdata until the byte is taken; may
    insert seeded random idle gaps between bytes. Records each byte's transfer time."""

    def __init__(self, tb: TB) -> None:
        self.tb = tb
        dut = tb.dut
        self.tdata = dut.s_axis_tdata
        self.tvalid = dut.s_axis_tvalid
        self.tready = dut.s_axis_tready
        self.gap_prob = 0.0
        self.max_gap = 3
        self.accepted: list[tuple[float, int]] = []
        self._queue: deque[_Send] = deque()
        self._wake = Event()
        self._idle = Event()
        self._idle.set()
        self._gen = 0
        self.tvalid.value = 0
        self.tdata.value = 0
        self._task = cocotb.start_soon(self._run())

    def send_nowait(self, data: Sequence[int], gap_cycles: int = 0) -> _Send:
        """Queue bytes; `gap_cycles` idle clocks precede the first one."""
        item = _Send(bytes(data), gap_cycles)
        if not item.data:
            item.done.set()
            return item
        self._queue.append(item)
        self._idle.clear()
        self._wake.set()
        return item

    async def send(self, data: Sequence[int], gap_cycles: int = 0, timeout_s: float = 20e-3) -> list[float]:
        """Send bytes and return once the last is taken: each byte's transfer time. A core
        that stops taking bytes fails the test instead of hanging it."""
        item = self.send_nowait(data, gap_cycles)
        await self._wait(item.done, timeout_s, f"the core took {{n}} of {len(item.data)} bytes of {_hex(item.data)}", item)
        return item.times

    async def wait_sent(self, item: _Send, timeout_s: float = 20e-3) -> list[float]:
        """Wait for a `send_nowait` to finish (with a timeout, like `send`)."""
        await self._wait(item.done, timeout_s, f"the core took {{n}} of {len(item.data)} bytes of {_hex(item.data)}", item)
        return item.times

    async def wait_idle(self, timeout_s: float = 100e-3) -> None:
        await self._wait(self._idle, timeout_s, "the core stopped taking bytes", None)

    async def _wait(self, event: Event, timeout_s: float, msg: str, item: _Send | None) -> None:
        if event.is_set():
            return
        await First(event.wait(), Timer(self.tb.to_ps(timeout_s), unit="ps"))
        if not event.is_set():
            raise TBError(f"{msg.format(n=len(item.times) if item else 0)} within {timeout_s * 1e3:g} ms")

    def flush(self) -> None:
        """Forget queued bytes, including one being offered (a reset abandons the host's
        transfer as well)."""
        self._gen += 1
        for item in self._queue:
            item.done.set()
        self._queue.clear()

    async def _run(self) -> None:
        clk = self.tb.clk
        rng = self.tb.rng
        while True:
            if not self._queue:
                self.tvalid.value = 0
                self._idle.set()
                self._wake.clear()
                await self._wake.wait()
                await RisingEdge(clk)  # start on a clock edge, whoever woke us
                continue
            gen = self._gen
            item = self._queue[0]
            for i, byte in enumerate(item.data):
                gap = item.gap_cycles if i == 0 else 0
                if self.gap_prob and rng.random() < self.gap_prob:
                    gap += rng.randint(1, self.max_gap)
                if gap:
                    self.tvalid.value = 0
                    await self.tb.cycles(gap)
                self.tdata.value = byte
                self.tvalid.value = 1
                while gen == self._gen:
                    await ReadOnly()
                    if self.tready.value != 1:
                        # The core holds the byte back: sleep until it may take it.
                        await self.tready.value_change
                        continue
                    await RisingEdge(clk)
                    break
                if gen != self._gen:
                    break
                t = self.tb.now_s()
                item.times.append(t)
                self.accepted.append((t, byte))
            if gen != self._gen:
                self.tvalid.value = 0
            else:
                self._queue.popleft()
                item.done.set()


class AxisSink:
    """Core -> host byte stream monitor. Assembles packets on tlast, checks tlast against the
    length byte, and checks the AXI-Stream rules every cycle while tvalid is high: tvalid
    held until taken, tdata/tlast stable while stalled. Drives tready: always 1, paused (0),
    or random with probability `ready_prob`."""

    def __init__(self, tb: TB) -> None:
        self.tb = tb
        dut = tb.dut
        self.tdata = dut.m_axis_tdata
        self.tvalid = dut.m_axis_tvalid
        self.tready = dut.m_axis_tready
        self.tlast = dut.m_axis_tlast
        self.ready_prob = 1.0
        self._paused = False
        self._resume = Event()
        self._resume.set()
        self.budget: int | None = None  # bytes it may still take before pausing
        self.packets: list[RxPacket] = []
        self._partial = bytearray()
        self._t_first = 0.0
        self._got = Event()
        self.tready.value = 1
        self._task = cocotb.start_soon(self._run())

    def _ready(self) -> int:
        if self.paused or self.budget == 0:
            return 0
        if self.ready_prob >= 1.0:
            return 1
        return int(self.tb.rng.random() < self.ready_prob)

    def abandon(self) -> None:
        self._partial = bytearray()

    @property
    def paused(self) -> bool:
        return self._paused

    @paused.setter
    def paused(self, value: bool) -> None:
        self._paused = value
        if self.tb.fcov is not None:
            self.tb.fcov.on_pause(value)
        if value:
            self._resume.clear()
        else:
            self._resume.set()

    async def _run(self) -> None:
        clk = self.tb.clk
        rst = self.tb.dut.rst
        prev: tuple[int, int, int] | None = None  # (tdata, tlast, tready) of a valid beat
        while True:
            ready = self._ready()
            self.tready.value = ready
            await ReadOnly()
            if rst.value != 0:
                self.abandon()
                prev = None
                await RisingEdge(clk)
                continue
            valid_v = self.tvalid.value
            if not valid_v.is_resolvable:
                self.tb.fail(f"m_axis_tvalid is {valid_v} after reset")
            valid = int(valid_v) if valid_v.is_resolvable else 0
            if prev is not None and not prev[2]:
                self._check_held(valid, prev)
            if not valid:
                prev = None
                await RisingEdge(self.tvalid)
                continue
            data, last = int(self.tdata.value), int(self.tlast.value)
            prev = (data, last, ready)
            if self._paused:
                # A long stall costs no per-cycle work: any change of the offered beat
                # before the resume is a violation (unless rst abandons it).
                await First(self.tvalid.value_change, self.tdata.value_change,
                            self.tlast.value_change, self._resume.wait())
                await ReadOnly()
                if rst.value == 0 and self._paused:
                    self._check_held(int(self.tvalid.value), prev)
                await RisingEdge(clk)
                continue
            await RisingEdge(clk)
            if ready:
                self._take(data, last)

    def _check_held(self, valid: int, prev: tuple[int, int, int]) -> None:
        """The last beat was not taken: it must still be offered, unchanged."""
        if not valid:
            self.tb.fail("m_axis_tvalid fell before its byte was taken")
        elif (int(self.tdata.value), int(self.tlast.value)) != prev[:2]:
            self.tb.fail(
                f"m_axis tdata/tlast changed while stalled: {prev[:2]} -> "
                f"{(int(self.tdata.value), int(self.tlast.value))}"
            )

    def _take(self, byte: int, last: int) -> None:
        now = self.tb.now_s()
        if self.budget:
            self.budget -= 1
        if not self._partial:
            self._t_first = now
        self._partial.append(byte)
        i = len(self._partial) - 1
        if i == 1 and byte > MAX_DATA:
            self.tb.fail(f"core sent a packet with N = {byte}: {_hex(self._partial)}")
        want_last = i >= 1 and i == self._partial[1] + 1
        if bool(last) != want_last:
            self.tb.fail(
                f"m_axis_tlast = {last} on byte {i} of {_hex(self._partial)} "
                "(must be 1 exactly on byte N+1)"
            )
        if last or want_last:
            self.packets.append(RxPacket(bytes(self._partial), self._t_first, now))
            self._partial = bytearray()
            self._got.set()

    async def wait_count(self, count: int, timeout_s: float) -> bool:
        """Wait until `count` packets have arrived in total; False on timeout."""
        deadline = self.tb.now_s() + timeout_s
        while len(self.packets) < count:
            left = deadline - self.tb.now_s()
            if left <= 0:
                return False
            self._got.clear()
            await First(self._got.wait(), Timer(self.tb.to_ps(left), unit="ps"))
        return True


class PulseMonitor:
    """Records (time, value) of a one-clock strobe output without a per-cycle loop while idle."""

    def __init__(self, tb: TB, strobe, values) -> None:
        self.tb = tb
        self.strobe = strobe
        self.values = values
        self.events: list[tuple[float, tuple[int, ...]]] = []
        self._task = cocotb.start_soon(self._run())

    async def _run(self) -> None:
        clk = self.tb.clk
        while True:
            await self.strobe.value_change
            while True:
                await ReadOnly()
                v = self.strobe.value
                if not v.is_resolvable or int(v) == 0:
                    break
                self.events.append((self.tb.now_s(), (int(v),) + tuple(int(s.value) for s in self.values)))
                await RisingEdge(clk)


class TB:
    """brainstem_dio testbench: owns the clock, reset, the streams, pins and monitors."""

    def __init__(self, dut, params: Params, seed: int | None = None) -> None:
        self.dut = dut
        self.p = params
        if seed is None:
            # cocotb's per-test seed (derived from COCOTB_RANDOM_SEED and the test name), or
            # BSD_SEED to replay one test's stimulus exactly.
            env = os.environ.get("BSD_SEED")
            seed = int(env) if env else cocotb.RANDOM_SEED
        self.seed = seed
        self.rng = random.Random(self.seed)
        self.log = dut._log
        self.clk = dut.clk
        self.period_ps = round(1e12 / params.clk_hz)
        self.errors: list[str] = []
        self._pins = 0
        self.t_reset = 0.0
        self.fcov: fcov.Sampler | None = None
        dut.rst.value = 1
        dut.pin_i.value = 0
        cocotb.start_soon(Clock(dut.clk, self.period_ps, unit="ps", impl="gpi",
                                period_high=self.period_ps // 2).start())
        self.source = AxisSource(self)
        self.sink = AxisSink(self)
        self._rflx = PulseMonitor(self, dut.rflx_valid, [dut.rflx_id, dut.rflx_data])
        self._trans = PulseMonitor(self, dut.raw_trans, [])
        # Cursors: what has already been checked against the model.
        self._n_pkt = 0
        self._n_rflx = 0
        self._n_trans = 0
        if fcov.enabled():  # functional coverage ($BSD_FCOV_DIR): samples what expect checks
            self.fcov = fcov.Sampler(self)

    # ---------------------------------------------------------------- time
    def now_s(self) -> float:
        return get_sim_time("ps") / self.period_ps / self.p.clk_hz

    def to_ps(self, seconds: float) -> int:
        return max(1, round(seconds * self.p.clk_hz * self.period_ps))

    def cycles_of(self, seconds: float) -> int:
        return round(seconds * self.p.clk_hz)

    async def wait_s(self, seconds: float) -> None:
        if seconds > 0:
            await Timer(self.to_ps(seconds), unit="ps")

    async def until_s(self, t: float) -> None:
        await self.wait_s(t - self.now_s())

    async def cycles(self, n: int) -> None:
        """Wait n rising edges from a rising edge; long waits cost one trigger, not n."""
        if n <= 8:
            await ClockCycles(self.clk, n)
        else:
            await Timer((n - 1) * self.period_ps + self.period_ps // 2, unit="ps")
            await RisingEdge(self.clk)

    # ---------------------------------------------------------------- errors
    def fail(self, msg: str) -> None:
        self.errors.append(msg)
        self.log.error(msg)

    def check_no_errors(self) -> None:
        if self.errors:
            raise TBError("; ".join(self.errors[:5]))

    # ---------------------------------------------------------------- reset / pins
    async def reset(self, cycles: int = 4, pins: int | None = None) -> None:
        """Synchronous reset; a partly sent packet in either direction is abandoned. New pad
        levels, if given, are applied while rst is high (so nothing running before the reset
        sees them) and held long enough for the synchronizer before rst falls."""
        await RisingEdge(self.clk)
        self.dut.rst.value = 1
        self.source.flush()
        self.sink.abandon()
        await RisingEdge(self.clk)
        if pins is not None:
            self.set_pins(pins)
        await ClockCycles(self.clk, cycles)
        self.dut.rst.value = 0
        await RisingEdge(self.clk)
        self.t_reset = self.now_s()  # first edge that samples rst = 0
        if self.fcov is not None:
            self.fcov.on_reset()

    def set_pins(self, levels: int) -> None:
        self._pins = levels & ((1 << self.p.num_pins) - 1)
        self.dut.pin_i.value = self._pins

    def set_pin(self, pin: int, level: int) -> None:
        mask = 1 << pin
        self.set_pins(self._pins & ~mask | (mask if level else 0))

    @property
    def pins(self) -> int:
        return self._pins

    def drive_waveform(self, pin: int, waveform: Sequence[tuple[float, int]]):
        """Drive pin levels at absolute core times [(t, level)...] in the background
        (asynchronously to the clock). Entries in the past are applied at once."""

        async def run() -> None:
            for t, level in waveform:
                await self.until_s(t)
                self.set_pin(pin, level)

        return cocotb.start_soon(run())

    # ---------------------------------------------------------------- monitors
    @property
    def packets(self) -> list[RxPacket]:
        return self.sink.packets

    @property
    def rflx(self) -> list[tuple[float, int, int]]:
        return [(t, v[1], v[2]) for t, v in self._rflx.events]

    @property
    def trans(self) -> list[tuple[float, int]]:
        """(time, pin) of every raw_trans pulse; several pins on one clock: ascending."""
        out = []
        for t, (bits,) in self._trans.events:
            out += [(t, p) for p in range(self.p.num_pins) if bits >> p & 1]
        return out

    async def wait_new_packets(self, n: int, timeout_s: float) -> bool:
        """Wait until `n` packets have arrived that new_packets() has not returned yet."""
        return await self.sink.wait_count(self._n_pkt + n, timeout_s)

    def new_packets(self) -> list[RxPacket]:
        pk = self.packets[self._n_pkt:]
        self._n_pkt = len(self.packets)
        return pk

    def new_rflx(self) -> list[tuple[float, int, int]]:
        r = self.rflx[self._n_rflx:]
        self._n_rflx += len(r)
        return r

    def new_trans(self) -> list[tuple[float, int]]:
        t = self.trans[self._n_trans:]
        self._n_trans += len(t)
        return t

    def sync_cursors(self) -> None:
        """Forget everything seen so far (e.g. after a reset the test does not check)."""
        self._n_pkt = len(self.packets)
        self._n_rflx = len(self.rflx)
        self._n_trans = len(self.trans)

    # ---------------------------------------------------------------- model checks
    async def expect(self, exp: Output, timeout_s: float | None = None, settle_cycles: int = 40,
                     what: str = "") -> list[RxPacket]:
        """Wait for the model's packets, then `settle_cycles` more for anything extra, and
        compare packets, RFLX strobes and raw_trans pulses with the model, byte for byte."""
        t_begin = self.now_s() if self.fcov is not None else 0.0
        if timeout_s is None:
            timeout_s = 2e-3 + 200 * len(exp.packets) / self.p.clk_hz
        want = self._n_pkt + len(exp.packets)
        await self.sink.wait_count(want, timeout_s)
        await self.cycles(settle_cycles)
        self.check_no_errors()
        got = self.new_packets()
        got_b = [p.data for p in got]
        ctx = f" after {what}" if what else ""
        if got_b != exp.packets:
            raise TBError(
                f"packets{ctx}: expected [{'; '.join(_hex(p) for p in exp.packets)}] "
                f"got [{'; '.join(_hex(p) for p in got_b)}]"
            )
        rflx_t = self.new_rflx()
        rflx = [(i, d) for _, i, d in rflx_t]
        if rflx != exp.rflx:
            raise TBError(f"RFLX strobes{ctx}: expected {exp.rflx} got {rflx}")
        trans = [p for _, p in self.new_trans()]
        if trans != exp.trans:
            raise TBError(f"raw_trans pulses{ctx}: expected {exp.trans} got {trans}")
        self.check_no_errors()
        if self.fcov is not None:
            self.fcov.on_expect(exp, got, rflx_t, t_begin)
        return got

    async def command(self, model: Model, data: Sequence[int], **kw) -> list[RxPacket]:
        """Send one host packet (or any bytes) and check what comes back against the model."""
        if self.fcov is not None:
            self.fcov.attach(model)
        exp = model.feed(data)
        await self.source.send(data)
        return await self.expect(exp, what=_hex(data), **kw)

    async def transact(self, data: Sequence[int], n_replies: int, timeout_s: float = 2e-3,
                       settle_cycles: int = 40) -> list[RxPacket]:
        """Send bytes and wait for `n_replies` packets (exactly: extra ones fail)."""
        await self.source.send(data)
        if not await self.sink.wait_count(self._n_pkt + n_replies, timeout_s):
            raise TBError(f"timeout waiting for {n_replies} replies to {_hex(data)}")
        await self.cycles(settle_cycles)
        got = self.new_packets()
        if len(got) != n_replies:
            raise TBError(f"{len(got)} replies to {_hex(data)}, expected {n_replies}")
        return got

    def check_pins(self, model: Model) -> None:
        oe, o = int(self.dut.pin_oe.value), int(self.dut.pin_o.value)
        if (oe, o) != (model.pin_oe(), model.pin_o()):
            raise TBError(
                f"pin_oe/pin_o = {oe:0{self.p.num_pins}b}/{o:0{self.p.num_pins}b}, model "
                f"{model.pin_oe():0{self.p.num_pins}b}/{model.pin_o():0{self.p.num_pins}b}"
            )

    async def start(self, model: Model | None = None, pins: int = 0) -> Output:
        """Reset with pads `pins`, and check the power-up message (against `model` if given)."""
        await self.reset(pins=pins)
        if model is not None and self.fcov is not None:
            self.fcov.attach(model)
        exp = model.reset(pins) if model is not None else Output()
        if model is not None:
            await self.expect(exp, what="reset")
            self.check_pins(model)
        return exp
