# SPDX-License-Identifier: Apache-2.0
"""Many timers at once, at the top level of brainstem_dio, against the model (PROTOCOL.md
§4.2 and §5): 64 completions and a command reply on one clock; 64 timeouts at 2 MHz with
completions landing on the timeout clock; completions on 64 successive clocks (the event
queue's sizing); the output stalled for 200 ms with every timer's
result waiting (nothing lost, RFLX strobes not held back); ±1 tick on 64 timers at 2, 2.5,
12 and 48 MHz; a restart right after a delivery; a restart during the drain's run of 64
picks (its HOST and RFLX bits' write pending, the parser held).

The clock of a completion is set from the pads: a pad driven right after the edge E ends a
measurement on the clock E + 3 (two synchronizer flops, then the edge is seen), the clock a
command whose last byte is taken at E + 1 executes (its reply's event). Timeout clocks are
worked out from the core's tick count T (`u_timers.t_q`) and its tick strobe (`tick`):
at 2 MHz the tick pattern repeats every 16 clocks (5 ticks), so it is predicted from the
last 16 clocks.
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from bsd_model import (
    CMD_DIG_CFG,
    CMD_PTIME_RD,
    DEVCODE_HOST,
    DEVCODE_RFLX,
    DIGCFG_IODIR,
    DIGCFG_TMODE,
    DIGCFG_TSTATE,
    TICK_HZ,
    TIMER_MAX_TICKS,
    Output,
    packet,
)
from bsd_tb import TBError
from top_builds import BUILDS
from top_helpers import A, P, check_result, configure, finish_timers, need, set_pins_checked, setup, timer_value
import runner

ALL = (1 << P.num_pins) - 1
FLAGS = DEVCODE_HOST | DEVCODE_RFLX


async def edge_after(tb, item, n_taken: int) -> None:
    """Return right after the rising edge that took byte n_taken of a send_nowait item."""
    while len(item.times) < n_taken:
        await RisingEdge(tb.dut.clk)
        await ReadOnly()
    await FallingEdge(tb.dut.clk)


async def start_all(tb, m, cfg: int, flags: int = FLAGS) -> dict[int, float]:
    """Every pin an input with `cfg`, every timer started; returns each start's last-byte time."""
    for pin in range(P.num_pins):
        await configure(tb, m, pin, cfg)
    starts = {}
    for pin in range(P.num_pins):
        pkt = packet(A, CMD_PTIME_RD, flags | pin)
        exp = m.feed(pkt)
        starts[pin] = (await tb.source.send(pkt))[-1]
        await tb.expect(exp, settle_cycles=1)
    return starts


def all_results(tb, m, starts: dict[int, float], t_pad: float | dict[int, float],
                what: str = "") -> dict[int, int]:
    """Every timer's result (a packet or a strobe), each checked against its interval from
    its start to the pad edge at t_pad (one time for all pins, or each pin's)."""
    results = {}
    for pin in range(P.num_pins):
        got = timer_value(tb, m, pin)
        if got is None:
            raise TBError(f"{what}pin {pin}: no result")
        check_result(pin, got, (t_pad[pin] if isinstance(t_pad, dict) else t_pad) - starts[pin])
        results[pin] = got
    return results


@cocotb.test(skip=not runner.on("t64_2", "t64_48"))
async def test_64_completions_and_reply_one_clock(dut) -> None:
    """All 64 timers complete on the clock a DIG_CFG query executes: 64 results by ascending
    pin, then the query's reply; RFLX strobes by ascending ID on successive clocks."""
    need(P.timer_mask == ALL, "a timer on every pin")
    tb, m = await setup(dut, pins=0)
    starts = await start_all(tb, m, DIGCFG_IODIR | DIGCFG_TSTATE)      # edge mode, to 1
    query = packet(A, CMD_DIG_CFG, 5)
    sent = tb.source.send_nowait(query)
    await edge_after(tb, sent, len(query) - 1)
    tb.set_pins(ALL)                     # seen on the clock the query executes
    t_pad = tb.now_s()
    await tb.source.wait_sent(sent)
    await tb.cycles(400)
    exp = m.timers_complete(all_results(tb, m, starts, t_pad))
    exp.extend(m.feed(query))
    m.set_pins(ALL)
    got = await tb.expect(exp, what="64 results, then the reply")
    assert len(got) == 65
    strobes = tb.rflx[-64:]
    clocks = {round((b[0] - a[0]) * P.clk_hz) for a, b in zip(strobes, strobes[1:])}
    assert clocks == {1}, f"RFLX strobes {sorted(clocks)} clocks apart"
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("t64_2"))
async def test_completions_on_successive_clocks(dut) -> None:
    """Timer p completes one clock after timer p - 1: an event-queue entry on each of 64 clocks
    while the drain takes a one-result entry every 4 clocks (from 17 timers on it reads the
    entry from the queue's head, and finds no timer left a clock after the last), so many
    entries wait at once (the
    queue is sized by the timer count, 2 NT + 8: what this fills). Every result arrives, in
    event order, which is pin order here."""
    need(P.timer_mask == ALL, "a timer on every pin")
    tb, m = await setup(dut, pins=0)
    starts = await start_all(tb, m, DIGCFG_IODIR | DIGCFG_TSTATE)      # edge mode, to 1
    evq = dut.u_evq
    depth = 1 << len(evq.wr_q)
    peak = held = 0

    async def watch() -> None:
        # The entries held, counted from the queue's handshakes (its pointers are LFSR
        # states, not counts), its read register included.
        nonlocal peak, held
        while True:
            await RisingEdge(dut.clk)
            await ReadOnly()
            push = int(evq.s_axis_tvalid.value) and int(evq.s_axis_tready.value)
            pop = int(evq.m_axis_tvalid.value) and int(evq.m_axis_tready.value)
            held += push - pop
            peak = max(peak, held)

    watcher = cocotb.start_soon(watch())
    await tb.cycles(8)
    t_pad, level = {}, 0
    for pin in range(P.num_pins):
        await FallingEdge(dut.clk)
        level |= 1 << pin
        tb.set_pins(level)
        t_pad[pin] = tb.now_s()
    await tb.cycles(400)
    watcher.cancel()
    exp = m.timers_complete(all_results(tb, m, starts, t_pad))
    m.set_pins(ALL)
    got = await tb.expect(exp, what="64 results in pin order")
    assert len(got) == 64
    dut._log.info("event queue: at most %d of %d entries waiting", peak, depth)
    assert held == 0, f"{held} entries left in the event queue"
    assert peak >= 16, f"only {peak} entries ever waited: the test does not fill the queue"
    tb.check_no_errors()


class Ticks:
    """The core's tick count and strobe, and the 16-clock tick pattern of 2 MHz."""

    def __init__(self, tb) -> None:
        self.tb = tb
        self.pattern: list[int] = []

    async def learn(self) -> None:
        """Record 16 clocks' tick strobes (sampled before each edge)."""
        self.pattern = []
        for _ in range(16):
            await ReadOnly()
            self.pattern.append(int(self.tb.dut.tick.value))
            await RisingEdge(self.tb.dut.clk)
            await FallingEdge(self.tb.dut.clk)
        assert sum(self.pattern) == 5, self.pattern

    def t_now(self) -> int:
        return int(self.tb.dut.u_timers.t_q.value)

    def clocks_until(self, t_target: int) -> int:
        """Clocks from the current one (0) to the one whose tick makes T = t_target."""
        t, c = self.t_now(), 0
        while True:
            if self.pattern[c % 16]:
                t = (t + 1) & 0xFFFF
                if t == t_target:
                    return c
            c += 1


@cocotb.test(skip=not runner.on("t64_2"))
async def test_64_timeouts_with_completions_on_the_timeout_clock(dut) -> None:
    """64 edge-mode timers time out at 2 MHz; every fourth one's pad reaches the target on
    the clock of its timeout (the completion wins: 65 535 ticks), every fourth one a clock
    after it (a timeout: 0); the rest time out. Results and their order against the model."""
    need(P.timer_mask == ALL and P.clk_hz == 2_000_000, "64 timers at 2 MHz")
    tb, m = await setup(dut, pins=0)
    ticks = Ticks(tb)
    for pin in range(P.num_pins):
        await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_TSTATE)      # edge mode, to 1
    t_start = {}
    for pin in range(P.num_pins):
        pkt = packet(A, CMD_PTIME_RD, FLAGS | pin)
        exp = m.feed(pkt)
        sent = tb.source.send_nowait(pkt)
        # T_start: T as the timer starts running (T after its start clock's tick).
        while not int(dut.u_timers.run_q.value) >> pin & 1:
            await RisingEdge(dut.clk)
            await ReadOnly()
        t_start[pin] = ticks.t_now()
        await tb.source.wait_sent(sent)
        await tb.expect(exp, settle_cycles=1)
    await tb.wait_s(TIMER_MAX_TICKS / TICK_HZ - 400e-6)
    await FallingEdge(dut.clk)
    await ticks.learn()
    # The clock (from now) of each timeout: the tick that makes T = T_start - 1.
    due = {pin: ticks.clocks_until((t_start[pin] - 1) & 0xFFFF) for pin in range(P.num_pins)}
    pads = {pin: due[pin] + (pin % 4) for pin in range(P.num_pins) if pin % 4 < 2}
    # A pad set during clock c is seen (completes) on clock c + 2.
    c = 0
    while any(at - 2 >= c for at in pads.values()):
        for pin, at in pads.items():
            if at - 2 == c:
                tb.set_pin(pin, 1)
        await RisingEdge(dut.clk)
        await FallingEdge(dut.clk)
        c += 1
    await tb.cycles(64 * 8 + 200)
    results = {}
    for pin in range(P.num_pins):
        got = timer_value(tb, m, pin)
        want = TIMER_MAX_TICKS if pin % 4 == 0 else 0
        assert got == want, (f"pin {pin}: result {got}, expected {want} "
                             f"(pad {['on', 'a clock after', 'never', 'never'][pin % 4]} at its timeout)")
        results[pin] = got
    exp = Output()
    for pin in sorted(range(P.num_pins), key=lambda p: (due[p], p)):   # by clock, then pin
        exp.extend(m.timer_complete(pin, results[pin]))
    m.set_pins(tb.pins)
    await tb.expect(exp, what="64 timeouts")
    assert len(set(due.values())) == P.num_pins, "timeouts expected on 64 distinct clocks"
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("t64_2"))
async def test_stall_200ms_every_result_waiting(dut) -> None:
    """m_axis stalled for 200 ms while all 64 timers complete (width mode, 30 us apart): each
    RFLX strobe comes within 100 clocks of its completion, the input keeps streaming commands
    without replies, and when the output resumes all 64 packets leave in completion order."""
    need(P.timer_mask == ALL, "a timer on every pin")
    tb, m = await setup(dut, pins=0)
    starts = await start_all(tb, m, DIGCFG_IODIR | DIGCFG_TMODE | DIGCFG_TSTATE)   # width, high pulse
    tb.sink.paused = True
    order = list(range(P.num_pins))
    tb.rng.shuffle(order)
    t_begin = tb.now_s() + 50e-6
    ends = {}
    for i, pin in enumerate(order):
        t_up, t_down = t_begin + i * 30e-6, t_begin + i * 30e-6 + 10e-6 + i * 1e-6
        tb.drive_waveform(pin, [(t_up, 1), (t_down, 0)])
        ends[pin] = (t_down, t_down - t_up)
    await tb.until_s(t_begin + 64 * 30e-6 + 200e-6)
    assert len(tb.rflx) - tb._n_rflx == 64, "RFLX strobes held back by the stall"
    for t, i, v in tb.rflx[tb._n_rflx:]:
        late = (t - ends[i][0]) * P.clk_hz
        assert late <= 100, f"timer {i}'s strobe {late:.0f} clocks after its completion"
    # Commands without replies still stream while the output is stalled.
    for pin in range(4):
        exp = m.feed(packet(A, CMD_DIG_CFG, pin, DIGCFG_IODIR))
        await tb.source.send(packet(A, CMD_DIG_CFG, pin, DIGCFG_IODIR), timeout_s=1e-3)
        assert not exp
    await tb.wait_s(200e-3)
    results = {}
    for _, i, v in tb.rflx[tb._n_rflx:]:
        check_result(i, v, ends[i][1])
        results[i] = v
    tb.sink.paused = False
    exp = Output()
    for pin in sorted(order, key=lambda p: ends[p][0]):
        exp.extend(m.timer_complete(pin, results[pin]))
    m.set_pins(0)
    got = await tb.expect(exp, timeout_s=5e-3, what="64 results after the stall")
    assert len(got) == 64
    tb.check_no_errors()


# make test runs the two ends (2 and 48 MHz); 2.5 and 12 MHz, two more 64-pin builds, are deep
# (make test-full), which keeps make test within its 5 minutes on a fresh clone.
@cocotb.test(skip=not runner.on("t64_2", "t64_2p5", "t64_12", "t64_48"))
async def test_accuracy_64_timers(dut) -> None:
    """64 timers at once (half edge, half width mode, random targets), intervals of 20 us to
    3 ms, completions at least 20 us apart: every result within one tick (plus the fixed
    latency) of the true interval, results and strobes in completion order."""
    need(P.timer_mask == ALL, "a timer on every pin")
    rng = None
    tb, m = await setup(dut, pins=0)
    rng = tb.rng
    tb.log.info("seed %d", tb.seed)
    for pin in range(P.num_pins):
        cfg = DIGCFG_IODIR | (DIGCFG_TMODE if pin % 2 else 0) | (DIGCFG_TSTATE if rng.random() < 0.5 else 0)
        await configure(tb, m, pin, cfg)
    runs = {}
    slots = rng.sample(range(5, 150), P.num_pins)
    for pin in range(P.num_pins):
        run_cfg = m.cfg[pin]
        target = int(bool(run_cfg & DIGCFG_TSTATE))
        level = tb.pins >> pin & 1
        pkt = packet(A, CMD_PTIME_RD, FLAGS | pin)
        exp = m.feed(pkt)
        t0 = (await tb.source.send(pkt))[-1]
        await tb.expect(exp, settle_cycles=1)
        runs[pin] = (t0, target, level)
    t_base = tb.now_s() + 20e-6
    wave_runs = {}
    for pin, (t0, target, level) in runs.items():
        t_end = t_base + slots[pin] * 20e-6
        dur = rng.uniform(5e-6, 15e-6)
        if pin % 2:   # width: a pulse at the target ending at t_end (leave it first if there)
            w = ([(t_end - 2 * dur, 1 - target)] if level == target else []) + \
                [(t_end - dur, target), (t_end, 1 - target)]
        else:         # edge: reach the target at t_end (leave it first if there)
            w = ([(t_end - dur, 1 - target)] if level == target else []) + [(t_end, target)]
        wave = [(0.0, level)] + w
        tb.drive_waveform(pin, w)
        wave_runs[pin] = (t0, wave)
    await finish_timers(tb, m, wave_runs)
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("t64_2", "gp1"))
async def test_restart_right_after_delivery(dut) -> None:
    """A PTIME_RD whose last byte comes the clock after the result's last byte has left
    starts again (no tmrConflict); one the clock before that gets tmrConflict. RFLX-only:
    a PTIME_RD right after the strobe starts again. Each restarted run measures correctly."""
    tb, m = await setup(dut, pins=0)
    pin = P.timer_pins[-1]
    await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_TSTATE)   # edge mode to 1
    for flags in (DEVCODE_HOST, DEVCODE_HOST | DEVCODE_RFLX, DEVCODE_RFLX):
        pkt = packet(A, CMD_PTIME_RD, flags | pin)
        exp = m.feed(pkt)
        t0 = (await tb.source.send(pkt))[-1]
        await tb.expect(exp, settle_cycles=1)
        tb.set_pin(pin, 1)
        t_pad = tb.now_s()
        # Wait for the delivery: the packet's last byte (HOST) or the strobe (RFLX only).
        n_pk, n_rf = len(tb.packets), len(tb.rflx)
        while (flags & DEVCODE_HOST and len(tb.packets) == n_pk) or \
                (not flags & DEVCODE_HOST and len(tb.rflx) == n_rf):
            await RisingEdge(dut.clk)
            await ReadOnly()
        await FallingEdge(dut.clk)
        got = timer_value(tb, m, pin)
        check_result(pin, got, t_pad - t0)
        exp = m.timer_complete(pin, got)
        await tb.expect(exp, what="the result")
        tb.set_pin(pin, 0)
        m.set_pin(pin, 0)
        # The PTIME_RD right away: its last byte is taken within a few clocks of the
        # delivery, and the timer is free.
        again = packet(A, CMD_PTIME_RD, flags | pin)
        exp = m.feed(again)
        assert not exp.packets, "the model sees the timer busy"
        t0 = (await tb.source.send(again))[-1]
        await tb.expect(exp, settle_cycles=4, what="the restart (no tmrConflict)")
        await tb.cycles(20)
        tb.set_pin(pin, 1)
        t_pad = tb.now_s()
        await tb.cycles(300)
        got = timer_value(tb, m, pin)
        check_result(pin, got, t_pad - t0)
        await tb.expect(m.timer_complete(pin, got), what="the restarted run's result")
        tb.set_pin(pin, 0)
        m.set_pin(pin, 0)
        await tb.cycles(10)
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1", "t64_2"))
async def test_latencies(dut) -> None:
    """DESIGN.md Latencies, with the output idle: a reply's first byte is offered on the 7th
    clock after the clock its command's last byte is taken (its handshake 7 clock edges
    later); a DIG_IO RFLX strobe is on rflx_* on that 7th clock too (it rises 6 edges later);
    a timer result's strobe and packet 7 clocks after its event clock (pad seen + 0)."""
    tb, m = await setup(dut, pins=0)
    pin = P.timer_pins[-1]
    query = packet(A, CMD_DIG_CFG, pin)
    exp = m.feed(query)
    t_last = (await tb.source.send(query))[-1]
    got = await tb.expect(exp, what="query")
    assert round((got[0].t_first - t_last) * P.clk_hz) == 7, (got[0].t_first - t_last) * P.clk_hz
    read = packet(A, 27, DEVCODE_RFLX | pin)
    exp = m.feed(read)
    t_last = (await tb.source.send(read))[-1]
    await tb.expect(exp, what="DIG_IO RFLX read")
    t_strobe = tb.rflx[-1][0]
    assert round((t_strobe - t_last) * P.clk_hz) == 6, (t_strobe - t_last) * P.clk_hz
    # A timer: a pad driven during clock c completes on clock c + 2 (the event clock).
    await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_TSTATE)
    pkt = packet(A, CMD_PTIME_RD, FLAGS | pin)
    exp = m.feed(pkt)
    t0 = (await tb.source.send(pkt))[-1]
    await tb.expect(exp, settle_cycles=1)
    await tb.cycles(30)
    await FallingEdge(dut.clk)
    tb.set_pin(pin, 1)
    t_pad = tb.now_s()            # during clock c; the event clock is c + 2
    await tb.cycles(100)
    got_v = timer_value(tb, m, pin)
    check_result(pin, got_v, t_pad - t0)
    exp = m.timer_complete(pin, got_v)
    m.set_pin(pin, 1)
    got = await tb.expect(exp, what="the result")
    # t_pad is half a clock into clock c: the event clock c + 2 starts 1.5 clocks later.
    strobe_after = (tb.rflx[-1][0] - t_pad) * P.clk_hz - 1.5
    first_after = (got[0].t_first - t_pad) * P.clk_hz - 1.5
    assert round(strobe_after) == 7 and round(first_after) == 8, (strobe_after, first_after)
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("t64_2"))
async def test_64_timeouts_then_restart(dut) -> None:
    """All 64 edge-mode timers time out (pads never reach the target): 64 results of 0 by
    ascending pin (each timeout's clock, ties by pin); then every timer starts again and is
    busy (a second start is tmrConflict, as the model says). Deterministic, unlike the
    timeouts of the random tests: every timer times out and restarts whatever the seed."""
    need(P.timer_mask == ALL, "a timer on every pin")
    tb, m = await setup(dut, pins=0)
    await start_all(tb, m, DIGCFG_IODIR | DIGCFG_TSTATE)        # edge mode, to 1; pads stay 0
    await tb.wait_s(TIMER_MAX_TICKS / TICK_HZ + 1e-3)
    exp = Output()
    for pin in range(P.num_pins):
        exp.extend(m.timer_complete(pin, 0))
    await tb.expect(exp, what="64 timeouts")
    for pin in range(P.num_pins):
        await tb.command(m, packet(A, CMD_PTIME_RD, FLAGS | pin))
    for pin in range(P.num_pins):
        assert pin in m.timers, f"the model has timer {pin} free after its restart"
        await tb.command(m, packet(A, CMD_PTIME_RD, FLAGS | pin))     # busy: tmrConflict
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("t64_2"))
async def test_every_pin_output_and_latch(dut) -> None:
    """Each of the 64 pins in turn: an output driven 1 then 0 (pin_o and pin_oe against the
    model after each command), then an input with its latch armed for rising edges, fired by
    its own pad (raw_trans against the model), then a plain input again; last, RFLX reads of
    pins whose IDs take every value of each 3-bit half (the drain ranks a DIG_IO value
    against the timer IDs by halves). Deterministic, so every pin's configuration bits,
    output latch and raw_trans, and the drain's ranking bits, toggle whatever the seed
    (the other tests here use the pins only as timer inputs)."""
    from bsd_model import CMD_DIG_IO, DIGCFG_ENA, DIGCFG_TRG
    tb, m = await setup(dut, pins=0)
    free = P.free_pins
    need(len(free) == 64, "64 configurable pins")
    for pin in free:
        await configure(tb, m, pin, 0)                     # an output
        for v in (1, 0):
            await tb.command(m, packet(A, CMD_DIG_IO, pin, v))
            tb.check_pins(m)
            assert (m.pin_o() >> pin & 1) == v, f"the model's pin {pin} is not {v}"
    for pin in free:
        await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_ENA | DIGCFG_TRG)
    for pin in free:
        await set_pins_checked(tb, m, tb.pins | 1 << pin)  # its latch fires
    await set_pins_checked(tb, m, 0)                       # a fall: nothing
    for pin in free:
        await configure(tb, m, pin, DIGCFG_IODIR)
    await set_pins_checked(tb, m, 1 << 63)
    n_rflx = len(tb.rflx)
    # IDs 0, 9, 18, .., 63 and back to 0: each value of the ID's bits 5:3 and 2:0 in turn
    # (the drain ranks a DIG_IO value against the timer IDs by those halves)
    ids = [9 * k for k in range(8)] + [0, 63, 0]
    for pin in ids:                                        # the strobes checked by tb.command
        await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_RFLX | pin))
    assert len(tb.rflx) == n_rflx + len(ids), tb.rflx[n_rflx:]
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("t64_2"))
async def test_restart_during_a_run_of_picks(dut) -> None:
    """From 17 timers a run's HOST and RFLX bits are a word in bsd_drain's one-port memory,
    read on every clock of a run of picks (while their items pass its stage A), so a start in
    such a run is written later, the
    parser held meanwhile (hold_o). All 64 RFLX-only timers complete on one clock (64 picks
    in a row); timer 0, freed by the run's first strobe, is restarted with HOST alone while
    the run goes on: the drain must show the write pending, the 64 strobes must come, and
    the restarted run's result must be a packet (no strobe), as the model says."""
    need(P.timer_mask == ALL, "a timer on every pin")
    tb, m = await setup(dut, pins=0)
    await set_pins_checked(tb, m, 0)
    starts = await start_all(tb, m, DIGCFG_IODIR | DIGCFG_TSTATE, DEVCODE_RFLX)  # edge mode, to 1
    n_rflx = len(tb.rflx)
    tb.set_pins(ALL)
    t_pad = tb.now_s()
    while len(tb.rflx) == n_rflx:
        await RisingEdge(dut.clk)
        await ReadOnly()
    await FallingEdge(dut.clk)
    again = packet(A, CMD_PTIME_RD, DEVCODE_HOST | 0)
    item = tb.source.send_nowait(again)
    held = 0
    for _ in range(40):  # (the packet's bytes and its 2 stages, well inside the 64 picks)
        await RisingEdge(dut.clk)
        await ReadOnly()
        held += int(dut.u_drain.hold_o.value)
    assert held > 0, "the restart's write was not pending: no start during the run of picks"
    t0 = (await tb.source.wait_sent(item))[-1]
    await tb.cycles(400)
    exp = m.timers_complete(all_results(tb, m, starts, t_pad))
    m.set_pins(ALL)
    await tb.expect(exp, what="64 strobes")
    exp = m.feed(again)
    assert not exp.packets, "the model sees timer 0 busy"
    await tb.expect(exp, what="the restart (no tmrConflict)")
    tb.set_pin(0, 0)
    m.set_pin(0, 0)
    await tb.cycles(20)
    tb.set_pin(0, 1)
    t_pad = tb.now_s()
    await tb.cycles(300)
    got = timer_value(tb, m, 0)
    if got is None:
        raise TBError("the restarted run (HOST alone): no packet")
    check_result(0, got, t_pad - t0)
    await tb.expect(m.timer_complete(0, got), what="the restarted run's packet, no strobe")
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("t64_2"))
async def test_every_timer_host_alone_then_rflx_alone(dut) -> None:
    """All 64 timers run with HOST alone, then RFLX alone, then both, each round completed
    together: every result goes where its start's DEVCODE sends it (packets, strobes, or
    both), checked against the model. The other tests start timers with both bits, so here
    each timer's HOST and RFLX bits are set and cleared whatever the seed."""
    need(P.timer_mask == ALL, "a timer on every pin")
    tb, m = await setup(dut, pins=0)
    for flags in (DEVCODE_HOST, DEVCODE_RFLX, FLAGS):
        await set_pins_checked(tb, m, 0)
        starts = await start_all(tb, m, DIGCFG_IODIR | DIGCFG_TSTATE, flags)  # edge mode, to 1
        n_rflx = len(tb.rflx)
        tb.set_pins(ALL)
        t_pad = tb.now_s()
        await tb.cycles(400)
        exp = m.timers_complete(all_results(tb, m, starts, t_pad, f"DEVCODE {flags:#x}, "))
        m.set_pins(ALL)
        got = await tb.expect(exp, what=f"DEVCODE {flags:#x}: 64 results")
        assert len(got) == (64 if flags & DEVCODE_HOST else 0), len(got)
        assert len(tb.rflx) - n_rflx == (64 if flags & DEVCODE_RFLX else 0), len(tb.rflx) - n_rflx
    tb.check_no_errors()


@pytest.mark.parametrize("sim, build", runner.cases(
    ["gp1", "t64_2", "t64_2p5", "t64_12", "t64_48"], quick="verilator", deep=["t64_2p5", "t64_12"]))
def test_scale_top(sim: str, build: str) -> None:
    runner.run(sim, "brainstem_dio", __file__, BUILDS[build], build)
