# SPDX-License-Identifier: Apache-2.0
"""cmdRESET at the top level of brainstem_dio (PROTOCOL.md §3, cmdRESET; DESIGN.md
"cmdRESET"): back to the power-up state as `rst` would, the power-up message as its answer
and the next packet out, a packet already partly sent finished first, everything else not
yet sent dropped (finished timer results, RFLX values still waiting), running timers
stopped, and the bytes after the command served after the reset.
"""

from __future__ import annotations

import cocotb
import pytest

from bsd_model import (
    CMD_DEBUG,
    CMD_DIG_CFG,
    CMD_DIG_IO,
    CMD_PTIME_RD,
    CMD_RESET,
    DEVCODE_HOST,
    DEVCODE_RFLX,
    DIGCFG_TSTATE,
    RESYNC_ADDR,
    Model,
    Output,
    packet,
)
from bsd_tb import TBError, _hex
from top_builds import BUILDS
from top_helpers import A, P, check_result, configure, need, settle_pins, setup, start_timer
import runner


# The reset takes effect this many clocks after the command's last byte is taken
# (DESIGN.md "Latencies": execution 2 clocks, then the reset strobe's register).
RESET_CLOCKS = 3


def reset_cmd(tb, n: int = 1) -> bytes:
    """cmdRESET with N = n: the code and n - 1 random bytes, which it ignores."""
    return packet(A, CMD_RESET, *(tb.rng.randrange(256) for _ in range(n - 1)))


async def dirty(tb, m) -> None:
    """Move every free pin away from its power-up state: outputs driven high, inputs with
    the latch armed and timer bits set."""
    for i, pin in enumerate(P.free_pins):
        if i % 2 == 0:
            await configure(tb, m, pin, 0x00)
            await tb.command(m, packet(A, CMD_DIG_IO, pin, 1))
        else:
            await configure(tb, m, pin, 0x1F)
    tb.check_pins(m)


@cocotb.test(skip=not runner.on("gp1", "slow_fixed", "high_ids"))
async def test_reset_forms(dut) -> None:
    """Every N from 1 to 8: only the power-up message comes back (never cmdTooLong), and
    every pin's configuration, output latch and latch is back at power-up (fixed pins at
    their fixed configuration, a fixed ENA armed on the current level). cmdRESET to another
    address, and inside the resync probe's address, is ignored."""
    tb, m = await setup(dut, pins=None)
    for n in range(1, 9):
        await dirty(tb, m)
        cmd = reset_cmd(tb, n)
        exp = m.feed(cmd)
        # A fresh model's power-up message: m.reset() here would tell the coverage observer of a
        # reset the core never saw.
        assert exp.packets == Model(m.p).reset().packets, "the model's cmdRESET answer is the power-up message"
        await tb.source.send(cmd)
        await tb.expect(exp, what=f"cmdRESET with N = {n}")
        tb.check_pins(m)
        for pin in P.pins:
            await tb.command(m, packet(A, CMD_DIG_CFG, pin))
    await dirty(tb, m)
    for other in ((A + 2) % 256, RESYNC_ADDR):
        await tb.command(m, packet(other, CMD_RESET))
    tb.check_pins(m)
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1", "gp2", "slow_fixed"))
async def test_bytes_after_reset(dut) -> None:
    """Packets sent back to back behind a cmdRESET (no gap, in one burst) are served after
    the reset, in order: nothing is lost and the power-up message comes first. The first
    packet behind it is 1 to 4 bytes long, so its last byte is offered on each clock from
    the reset's execution to the reset itself. (slow_fixed, 20 pins: the DIG_CFG write and
    reads behind it meet the configuration memory's sweep after the reset, DESIGN.md
    decision 11.)"""
    tb, m = await setup(dut, pins=None)
    pin = P.free_pins[0]
    first = [packet(A, CMD_DEBUG), packet(A, 0x63), packet((A + 2) % 256, 1),
             packet(RESYNC_ADDR), packet(A, CMD_DIG_CFG, pin), packet(A, CMD_DEBUG, 7, 8)]
    for head in first:
        await dirty(tb, m)
        burst = (reset_cmd(tb, 1 + tb.rng.randrange(8)) + head
                 + packet(A, CMD_DIG_CFG, pin, 0x00) + packet(A, CMD_DIG_IO, pin, 1)
                 + packet(A, CMD_DIG_IO, DEVCODE_HOST | P.free_pins[-1]) + packet(A, CMD_DIG_CFG, pin))
        exp = m.feed(burst)
        await tb.source.send(burst)
        await tb.expect(exp, what=f"{_hex(head)} behind cmdRESET")
        tb.check_pins(m)
    tb.check_no_errors()


async def finished_result(tb, m, pin: int, flags: int) -> None:
    """Time `pin` (edge mode towards its TSTATE) with an edge 50 us after the start, and
    wait until the measurement has finished."""
    target = int(bool(m.cfg[pin] & DIGCFG_TSTATE))
    tb.set_pin(pin, 1 - target)
    await settle_pins(tb)
    m.set_pins(tb.pins)
    await start_timer(tb, m, pin, flags, [(50e-6, target)])
    await tb.wait_s(60e-6)


@cocotb.test(skip=not runner.on("gp1", "gp2"))
async def test_reset_drops_what_waits(dut) -> None:
    """Output stalled: a finished timer result whose first byte is offered but not taken,
    and a measurement still running. cmdRESET: the result is dropped (the offered byte
    becomes the power-up message's, AXI-Stream holds), the running timer stops (no result,
    and PTIME_RD starts it again at once)."""
    tb, m = await setup(dut, pins=(1 << P.num_pins) - 1)
    done_pin, run_pin = P.timer_pins[-1], P.timer_pins[0]
    need(done_pin != run_pin, "two timer pins")
    tb.sink.paused = True
    await finished_result(tb, m, done_pin, DEVCODE_HOST)
    await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | DEVCODE_RFLX | run_pin))
    if int(dut.m_axis_tvalid.value) != 1:
        raise TBError("the finished result is not offered on m_axis")
    cmd = reset_cmd(tb)
    exp = m.feed(cmd)                    # the model forgets both measurements
    await tb.source.send(cmd)
    await tb.cycles(20)
    tb.sink.paused = False
    await tb.expect(exp, what="cmdRESET with a result waiting and a timer running")
    # The stopped timer gives nothing when its pad moves, and is free at once.
    m.set_pins(tb.pins)
    tb.set_pin(run_pin, 1 - (tb.pins >> run_pin & 1))
    await settle_pins(tb)
    await tb.expect(m.set_pins(tb.pins), settle_cycles=400, what="an edge on the stopped timer's pin")
    await finished_result(tb, m, run_pin, DEVCODE_HOST)
    got = tb.packets[tb._n_pkt:]
    if len(got) != 1:
        raise TBError(f"expected one timer result after the reset, got {[_hex(p.data) for p in got]}")
    value = got[0].data[4] << 8 | got[0].data[5]
    check_result(run_pin, value, 50e-6)
    await tb.expect(m.timer_complete(run_pin, value), what="timing again after cmdRESET")
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1", "high_ids"))
async def test_reset_finishes_partial_packet(dut) -> None:
    """A timer result with 1 to 5 of its 6 bytes taken when cmdRESET executes is finished,
    whole, then the power-up message follows; with none taken it is replaced."""
    tb, m = await setup(dut, pins=(1 << P.num_pins) - 1)
    pin = P.timer_pins[-1]
    for taken in range(6):
        tb.sink.budget = taken
        await finished_result(tb, m, pin, DEVCODE_HOST)
        cmd = reset_cmd(tb)
        await tb.source.send(cmd)
        await tb.cycles(20)
        tb.sink.budget = None
        tb.sink.paused = False
        if not await tb.wait_new_packets(1 + (taken > 0), 2e-3):
            raise TBError(f"{taken} bytes taken: packets missing after cmdRESET")
        exp = Output()
        if taken:
            d = tb.packets[tb._n_pkt].data
            value = d[4] << 8 | d[5]
            check_result(pin, value, 50e-6)
            exp.extend(m.timer_complete(pin, value))
        exp.extend(m.feed(cmd))
        await tb.expect(exp, what=f"cmdRESET with {taken} bytes of a result taken")
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1"))
async def test_reset_against_rflx_burst(dut) -> None:
    """Every timer pin finishes on one clock with RFLX only (their strobes leave on
    successive clocks, lowest ID first) while cmdRESET lands well before, during or after
    that burst: the strobes seen are the expected ones in order, cut where the reset drops
    those still waiting, never repeated; no packet but the power-up message. The sweep
    must see all three outcomes (none, some, all)."""
    tb, m = await setup(dut, pins=(1 << P.num_pins) - 1)
    pins = [p for p in P.timer_pins if m.is_input(p)]
    need(len(pins) >= 3, "three timer pins")
    want = [P.timer_id(p) for p in pins]
    high = tb.pins
    low = high & ~sum(1 << p for p in pins)
    outcomes = set()
    for lead in range(-10, 14):
        for pin in pins:
            await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_RFLX | pin))
        # lead > 0: the reset's bytes go first and the pads fall `lead` clocks after they
        # start; lead <= 0: the pads fall first.
        cmd = reset_cmd(tb)
        if lead <= 0:
            tb.set_pins(low)
            await tb.cycles(-lead + 1)
            await tb.source.send(cmd)
        else:
            send = tb.source.send_nowait(cmd)
            await tb.cycles(lead)
            tb.set_pins(low)
            await tb.source.wait_sent(send)
        await tb.cycles(40)
        got = [(i, v) for _, i, v in tb.new_rflx()]
        ids = [i for i, _ in got]
        if ids != want[:len(ids)] or any(v == 0 for _, v in got):
            raise TBError(f"lead {lead}: RFLX strobes {got}, expected a prefix of ids {want}")
        outcomes.add("none" if not ids else "all" if len(ids) == len(want) else "some")
        m.set_pins(low)
        await tb.expect(Output(packets=m.feed(cmd).packets), what=f"cmdRESET, lead {lead}")
        tb.set_pins(high)
        await settle_pins(tb)
        m.set_pins(high)
    if outcomes != {"none", "some", "all"}:
        raise TBError(f"the sweep saw only {sorted(outcomes)}: it missed the reset's window")
    tb.check_no_errors()


@pytest.mark.parametrize("sim, build", runner.cases(["gp1", "slow_fixed", "gp2", "high_ids"], quick="verilator"))
def test_soft_reset_top(sim: str, build: str) -> None:
    runner.run(sim, "brainstem_dio", __file__, BUILDS[build], build)
