# SPDX-License-Identifier: Apache-2.0
"""cmdHB (PROTOCOL.md §3) at the top level of brainstem_dio: the core's UP/DOWN heartbeats
every HB_RATE x 25.6 ms and `link_up` with host answers in time, late, missing and wrong,
and with a stalled output (a heartbeat that falls due while the previous one is unsent is
skipped). Built with a slow clock and HB_RATE = 1 so a period is only 51 200 clocks; the
model gives every expected packet and link state. (Without heartbeats, link_up 0 is also
checked by test_commands' test_messages on every build.)
"""

from __future__ import annotations

import itertools

import cocotb
import pytest

from bsd_model import (
    CMD_DIG_CFG,
    CMD_HB,
    DEVCODE_HOST,
    DEVCODE_RFLX,
    DIGCFG_IODIR,
    DIGCFG_TSTATE,
    HB_ANSWER,
    TICK_S,
    Model,
    Output,
    packet,
    timer_interval,
)
from bsd_tb import TB, TBError
from top_builds import BUILDS
from top_helpers import P, check_result, need, start_timer, timer_value
import runner


class HeartbeatTB(TB):
    """TB with the heartbeat schedule: due times counted from the clock reset ended."""

    async def begin(self, model: Model) -> None:
        await self.start(model)
        self.k = 0  # heartbeats due so far

    def due_s(self, k: int) -> float:
        # The tick phase starts on the first clock out of reset.
        return self.t_reset + k * self.p.hb_period_s

    def check_link(self, model: Model, when: str) -> None:
        got = int(self.dut.link_up.value)
        if got != int(model.link_up):
            raise TBError(f"link_up = {got}, model {int(model.link_up)} {when}")

    async def next_due(self, model: Model, outcome: str = "sent") -> list[bytes]:
        """Run to just after the next due time and check link_up against the model there.
        outcome "sent": the heartbeat must leave on time; "queued": it falls due but the
        output is stalled; "skipped": the previous one is still unsent. Returns the
        model's heartbeat packets."""
        self.k += 1
        due = self.due_s(self.k)
        await self.until_s(due - 4 * TICK_S)
        self.check_link(model, f"just before heartbeat {self.k}")
        exp = model.heartbeat_skipped() if outcome == "skipped" else model.heartbeat_due()
        await self.until_s(due + 4 * TICK_S)
        self.check_link(model, f"just after heartbeat {self.k} fell due")
        if outcome == "sent":
            got = await self.expect(exp, what=f"heartbeat {self.k}")
            late = (got[0].t_first - due) / TICK_S
            if not -2 <= late <= 2:
                raise TBError(f"heartbeat {self.k} came {late:+.2f} ticks off its due time")
        return exp.packets

    async def answer(self, model: Model, kind: int) -> None:
        """The host answers (any type byte): silent, and link_up follows the model."""
        await self.command(model, packet(self.p.module_addr, CMD_HB, kind))
        self.check_link(model, f"after the answer {kind}")


@cocotb.test(skip=not runner.on("heartbeat"))
async def test_heartbeats_and_link_up(dut) -> None:
    """First heartbeat one period after reset, UP/DOWN alternating, each on its due time;
    link_up checked just before and after every due time: answered in time, missing, late
    (answering the previous one), wrong; an answer with extra bytes counts; every other
    cmdHB shape is silent; a heartbeat due while the previous is unsent is skipped."""
    p = P
    tb = HeartbeatTB(dut, p)
    model = Model(p)
    await tb.begin(model)
    tb.check_link(model, "after reset")
    a = p.module_addr

    # No answers: UP, DOWN; link stays down.
    await tb.next_due(model)
    await tb.next_due(model)
    # Answered in time, twice: link up, and it stays up through the next due times.
    await tb.wait_s(1e-3)
    await tb.answer(model, 1 + HB_ANSWER)
    await tb.next_due(model)
    await tb.wait_s(5e-3)
    await tb.answer(model, 0 + HB_ANSWER)
    await tb.next_due(model)
    # Missing: the next due time takes the link down.
    await tb.next_due(model)
    # Late (answers the previous heartbeat) and wrong answers leave it down; the right one,
    # here with extra bytes after the type, brings it up.
    await tb.answer(model, 1 + HB_ANSWER)
    await tb.answer(model, 7)
    await tb.command(model, packet(a, CMD_HB, 0 + HB_ANSWER, 0, 0))
    tb.check_link(model, "after the right answer with extra bytes")
    # Host cmdHB packets of every other shape are consumed silently.
    for data in ([CMD_HB], [CMD_HB, 0 + HB_ANSWER, 0xFF], [CMD_HB, 0, 1, 2, 3, 4, 5, 6]):
        await tb.command(model, bytes([a, len(data), *data]))
    # Output stalled across two due times: the first heartbeat waits, the second is
    # skipped (no toggle of the type) and the link goes down.
    tb.sink.paused = True
    queued = await tb.next_due(model, "queued")
    await tb.next_due(model, "skipped")
    if tb.new_packets():
        raise TBError("a packet left while the output was stalled")
    tb.sink.paused = False
    # The queued heartbeat leaves now, with its own type; the next one has the other type.
    await tb.expect(Output(packets=queued), what="the stall")
    await tb.next_due(model)
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("heartbeat"))
async def test_stall_with_waiting_packets(dut) -> None:
    """The output stalled while any mix of a command reply, a timer result and a heartbeat
    falls due (all eight): nothing leaves during the stall, the RFLX strobe is not held
    back, and on the release every waiting packet leaves whole, in the order of its event
    (timer result, reply, heartbeat)."""
    p = P
    need(bool(p.hb_rate) and p.has_timer(1) and not p.is_fixed(1), "heartbeats and a timer on pin 1")
    tb = HeartbeatTB(dut, p)
    m = Model(p)
    await tb.begin(m)
    a, pin = p.module_addr, 1
    await tb.command(m, packet(a, CMD_DIG_CFG, pin, DIGCFG_IODIR | DIGCFG_TSTATE))  # edge to 1
    for want_r, want_t, want_h in itertools.product((0, 1), repeat=3):
        await tb.next_due(m)  # a fresh period: the stall below ends well before the next one
        tb.sink.paused = True
        exp = Output()
        if want_t:
            t0, wave = await start_timer(tb, m, pin, DEVCODE_HOST | DEVCODE_RFLX, [(100e-6, 1), (150e-6, 0)])
            await tb.until_s(t0 + 300e-6)
        if want_r:
            query = packet(a, CMD_DIG_CFG, pin)
            reply = m.feed(query)
            await tb.source.wait_sent(tb.source.send_nowait(query))
        await tb.wait_s(200e-6)
        hb: list[bytes] = []
        if want_h:
            hb = await tb.next_due(m, "queued")
        if tb.new_packets():
            raise TBError("a packet left while the output was stalled")
        tb.sink.paused = False
        n = want_t + want_r + len(hb)
        if not await tb.wait_new_packets(n, 2e-3):
            raise TBError(f"{n} packets expected after the release")
        if want_t:
            got = timer_value(tb, m, pin)
            if got is None:
                raise TBError("no timer result after the release")
            check_result(pin, got, timer_interval(t0, wave, False, 1))
            exp.extend(m.timer_complete(pin, got))
        if want_r:
            exp.extend(reply)
        exp.extend(Output(packets=hb))
        await tb.expect(exp, what=f"the release (reply {want_r}, timer {want_t}, heartbeat {want_h})")
        if want_t:
            m.set_pin(pin, 0)
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("clk2"))
async def test_no_heartbeat_when_off(dut) -> None:
    """HB_RATE = 0: no heartbeat ever, link_up stays 0 whatever the host sends."""
    p = P
    need(not p.hb_rate, "HB_RATE = 0")
    tb = TB(dut, p)
    model = Model(p)
    await tb.start(model)
    a = p.module_addr
    for kind in (HB_ANSWER, HB_ANSWER + 1):
        await tb.command(model, packet(a, CMD_HB, kind))
    await tb.wait_s(3 * 25.6e-3)
    if tb.new_packets():
        raise TBError("a packet without HB_RATE")
    if int(dut.link_up.value) != 0:
        raise TBError("link_up without HB_RATE")
    tb.check_no_errors()


@pytest.mark.parametrize("sim, build", runner.cases(["heartbeat", "clk2"], quick="verilator"))
def test_heartbeat_top(sim: str, build: str) -> None:
    runner.run(sim, "brainstem_dio", __file__, BUILDS[build], build)
