# SPDX-License-Identifier: Apache-2.0
"""Flow control, ordering and reset at the top level of brainstem_dio (PROTOCOL.md §5, §6):
full-rate input, replies holding the input, event order with a stalled output, long
stalls, and a reset in the middle of traffic.
"""

from __future__ import annotations

import cocotb
import pytest

from bsd_model import (
    CMD_DIG_CFG,
    CMD_DIG_IO,
    CMD_DIG_RST,
    CMD_PTIME_RD,
    DEVCODE_HOST,
    DEVCODE_RFLX,
    DIGCFG_IODIR,
    DIGCFG_TSTATE,
    RESYNC_ADDR,
    TICK_S,
    Output,
    packet,
    timer_interval,
)
from bsd_tb import TBError, _hex
from top_builds import BUILDS
from top_helpers import (
    A,
    P,
    check_result,
    configure,
    measure,
    need,
    set_pins_checked,
    settle_pins,
    setup,
    start_timer,
    timer_value,
)
import runner


@cocotb.test(skip=not runner.on("gp1"))
async def test_throughput(dut) -> None:
    """With m_axis_tready high, commands without replies stream at one byte per clock,
    DIG_IO reads with only the RFLX bit (a strobe, no packet) included."""
    tb, m = await setup(dut, pins=None)
    pin = P.free_pins[0]
    await configure(tb, m, pin, 0x00)
    rpin = next((p for p in P.pins if p != pin and m.is_input(p)), None)
    stream = b""
    for i in range(20):
        stream += packet(A, CMD_DIG_IO, pin, i & 1)
        stream += packet(A, CMD_DIG_RST, (pin + 1) % P.num_pins)
        stream += packet(A, CMD_DIG_CFG, pin, 0x00)
        if rpin is not None:  # back to back: the slot frees in time for the next one
            stream += packet(A, CMD_DIG_IO, DEVCODE_RFLX | rpin) * 2
        stream += packet(A ^ 0x10, CMD_DIG_CFG, 0) + packet(A) + packet(0x11, 3, 4, 5, 6, 7, 8, 9, 10)
    exp = m.feed(stream)
    times = await tb.source.send(stream)
    await tb.expect(exp, what="no-reply stream")
    steps = {round((b - a) * P.clk_hz) for a, b in zip(times, times[1:])}
    assert steps == {1}, f"input gaps of {sorted(steps)} clocks in a no-reply stream"
    tb.check_pins(m)
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1", "gp2"))
async def test_order_stalled(dut) -> None:
    """DESIGN.md 1: with m_axis stalled, packets leave oldest first (a timer result that
    completed before a command's reply goes first, and after it goes after); results of one
    clock by ascending pin; RFLX strobes are not held back by the stall."""
    tpins = [p for p in P.timer_pins if not P.is_fixed(p)]
    need(len(tpins) >= 2, "two configurable timer pins")
    tb, m = await setup(dut, pins=0)
    p1, p2 = tpins[:2]
    for p in (p1, p2):
        await configure(tb, m, p, DIGCFG_IODIR | DIGCFG_TSTATE)  # edge to 1
    await set_pins_checked(tb, m, tb.pins & ~(1 << p1 | 1 << p2))
    query = packet(A, CMD_DIG_CFG, 0)

    async def stalled_case(timer_first: bool) -> None:
        target = int(bool(m.cfg[p1] & DIGCFG_TSTATE))
        t0, wave = await start_timer(tb, m, p1, DEVCODE_HOST | DEVCODE_RFLX, [(200e-6, target), (300e-6, 1 - target)])
        tb.sink.paused = True
        if timer_first:
            await tb.until_s(t0 + 250e-6)
            assert [i for _, i, _ in tb.rflx[tb._n_rflx:]] == [P.timer_id(p1)], "RFLX held back by the stall"
            sent = tb.source.send_nowait(query)
            await tb.wait_s(20e-6)
        else:
            sent = tb.source.send_nowait(query)
            await tb.until_s(t0 + 250e-6)
        got = timer_value(tb, m, p1)
        assert got is not None
        check_result(p1, got, timer_interval(t0, wave, False, target))
        if timer_first:
            exp = m.timer_complete(p1, got).extend(m.feed(query))
        else:
            exp = m.feed(query).extend(m.timer_complete(p1, got))
        await tb.cycles(100)
        tb.sink.paused = False
        await tb.source.wait_sent(sent)
        await tb.expect(exp, what="stalled output")
        await tb.until_s(wave[-1][0] + 5e-6)
        m.set_pin(p1, wave[-1][1])

    await stalled_case(timer_first=True)
    await stalled_case(timer_first=False)
    # Two results of one clock: ascending pin, whatever order the timers started in.
    tb.sink.paused = True
    t_a = (await tb.source.send(packet(A, CMD_PTIME_RD, DEVCODE_HOST | DEVCODE_RFLX | p2)))[-1]
    m.feed(packet(A, CMD_PTIME_RD, DEVCODE_HOST | DEVCODE_RFLX | p2))
    t_b = (await tb.source.send(packet(A, CMD_PTIME_RD, DEVCODE_HOST | DEVCODE_RFLX | p1)))[-1]
    m.feed(packet(A, CMD_PTIME_RD, DEVCODE_HOST | DEVCODE_RFLX | p1))
    await tb.wait_s(100e-6)
    targets = {p: int(bool(m.cfg[p] & DIGCFG_TSTATE)) for p in (p1, p2)}
    tb.set_pins(tb.pins & ~(1 << p1 | 1 << p2) | targets[p1] << p1 | targets[p2] << p2)  # same instant
    t_edge = tb.now_s()
    await tb.wait_s(20e-6)
    tb.sink.paused = False
    got = {p: timer_value(tb, m, p) for p in (p1, p2)}
    for p, t0 in ((p2, t_a), (p1, t_b)):
        assert got[p] is not None
        check_result(p, got[p], t_edge - t0)
    exp = m.timers_complete(got)
    strobes = [t for t, i, _ in tb.rflx[tb._n_rflx:]]
    assert len(strobes) == 2 and round((strobes[1] - strobes[0]) * P.clk_hz) == 1, \
        f"two RFLX results of one clock must strobe on successive clocks: {strobes}"
    await tb.expect(exp, what="same-clock results")
    m.set_pins(tb.pins)
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1"))
async def test_reply_hold(dut) -> None:
    """DESIGN.md 2: while a reply waits, the core holds back a packet that could produce
    another reply: the *last* byte of an own packet with 1 <= N <= 8; a packet ended by its
    length byte with a reply (the 0xAD probe, own N > 8) is taken whole and then waits, with
    the byte after it. Every other byte streams: the address and length of an own packet,
    whole packets to other addresses and 0xAD packets with N > 0."""
    tb, m = await setup(dut, pins=None)
    query = packet(A, CMD_DIG_CFG, 0)
    other = A ^ 0x40
    cases = [
        # (bytes offered while a reply waits, fewest and most the core may take meanwhile)
        (packet(A, CMD_DIG_CFG, 0), 3, 3),
        (packet(A, CMD_DIG_CFG, 1, 0x01), 4, 4),  # a set: no reply of its own, but may error
        (packet(A, CMD_DIG_IO, 0x80, 1, 2, 3, 4, 5, 6), 9, 9),
        (packet(RESYNC_ADDR) + query, 2, 2),  # the probe is taken, the next byte waits
        (bytes([A, 9]) + query, 2, 2),  # N > 8 to us: likewise
        (packet(other, 1, 2, 3) + query, 5 + 3, 5 + 3),  # foreign packets stream whole
        (packet(RESYNC_ADDR, A, 2), 4, 4),  # 0xAD with N > 0 never replies: streams whole
    ]
    problems = []
    for data, least, most in cases:
        tb.sink.paused = True
        exp = m.feed(query)
        await tb.source.send(query)
        sent = tb.source.send_nowait(data)
        await tb.cycles(60)
        taken = len(sent.times)
        if not least <= taken <= most:
            problems.append(f"{_hex(data)}: the core took {taken} bytes while a reply waited, "
                            f"DESIGN.md 2 says {least if least == most else f'{least}..{most}'}")
        tb.sink.paused = False
        await tb.source.wait_sent(sent)
        exp.extend(m.feed(data))
        await tb.expect(exp, what=_hex(data))
    if problems:
        raise TBError("; ".join(problems))
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("slow_fixed"))
async def test_long_stall(dut) -> None:
    """The core's own stall (m_axis_tready low for several RX timeouts while a reply waits
    and the host offers the next packet) never drops that packet."""
    need(P.rx_timeout_us > 0, "an RX timeout")
    tb, m = await setup(dut, pins=None)
    limit = P.rx_timeout_s
    q1 = packet(A, CMD_DIG_CFG, 0)
    q2 = packet(A, CMD_DIG_IO, DEVCODE_HOST | DEVCODE_RFLX | (P.num_pins - 1))
    for hold_s in (3 * limit, limit + 5 * TICK_S):
        tb.sink.paused = True
        exp = m.feed(q1)
        await tb.source.send(q1)
        send2 = tb.source.send_nowait(q2)
        await tb.wait_s(hold_s)
        assert len(send2.times) < len(q2), "the core took a packet that may reply while a reply waits"
        tb.sink.paused = False
        await tb.source.wait_sent(send2)
        exp.extend(m.feed(q2))
        await tb.expect(exp, what=f"a {hold_s * 1e6:.0f} us stall (RX timeout {limit * 1e6:.0f} us)")
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1", "slow_fixed"))
async def test_reset_mid(dut) -> None:
    """rst in the middle of a host packet, of an outgoing packet, and of a running timer:
    back to the power-up state, parser waiting for an address, no stale result."""
    tb, m = await setup(dut, pins=0)
    query = packet(A, CMD_DIG_CFG, P.num_pins - 1)
    for cut in (1, 2, 3):
        partial = packet(A, CMD_DIG_CFG, 0, 0x00)[:cut]
        m.feed(partial)
        await tb.source.send(partial)
        await tb.reset()
        await tb.expect(m.reset(tb.pins), what=f"reset after {cut} bytes")
        await tb.command(m, query)
    # Configuration, latches and outputs go back to power-up.
    for pin in P.free_pins:
        await configure(tb, m, pin, 0x00)
        await tb.command(m, packet(A, CMD_DIG_IO, pin, 1))
    tb.check_pins(m)
    await tb.reset()
    await tb.expect(m.reset(tb.pins), what="reset")
    tb.check_pins(m)
    for pin in P.pins:
        await tb.command(m, packet(A, CMD_DIG_CFG, pin))
    # An outgoing packet cut by rst is abandoned; the next packet out is the power-up one.
    tb.sink.budget = 2
    m.feed(query)
    await tb.source.send(query)
    await tb.cycles(20)
    await tb.reset()
    tb.sink.budget = None
    await tb.expect(m.reset(tb.pins), what="reset during a reply")
    # A running timer is forgotten: no result, and the pin can be timed again at once.
    tp = [p for p in P.timer_pins if m.is_input(p)]
    if tp:
        pin = tp[0]
        target = int(bool(m.cfg[pin] & DIGCFG_TSTATE))
        await set_pins_checked(tb, m, tb.pins & ~(1 << pin) | (1 - target) << pin)
        await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | DEVCODE_RFLX | pin))
        await tb.reset()
        await tb.expect(m.reset(tb.pins), what="reset during a measurement")
        tb.set_pin(pin, target)
        await settle_pins(tb)
        m.set_pins(tb.pins)
        await tb.expect(Output(), settle_cycles=200, what="edge after reset")
        await measure(tb, m, pin, DEVCODE_HOST | DEVCODE_RFLX, [(20e-6, 1 - target), (100e-6, target)])
    tb.check_no_errors()


@pytest.mark.parametrize("sim, build", runner.cases(["gp1", "slow_fixed", "gp2"], quick="verilator"))
def test_ordering_top(sim: str, build: str) -> None:
    runner.run(sim, "brainstem_dio", __file__, BUILDS[build], build)
