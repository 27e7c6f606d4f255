# SPDX-License-Identifier: Apache-2.0
"""The one-shot transition latch at the top level of brainstem_dio (PROTOCOL.md §4.1,
docs/DESIGN.md decision 5): directed fire/spent/re-arm sequences on every configurable pin;
seeded random pad changes, DIG_RST and DIG_CFG sets checked against the model; the POLL_HZ
sampling grid; and the clock on which a re-arm meets a matching edge.
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import ReadOnly, RisingEdge, Timer

from bsd_model import (
    CMD_DIG_CFG,
    CMD_DIG_RST,
    DIGCFG_ENA,
    DIGCFG_IODIR,
    DIGCFG_TRG,
    Model,
    Output,
    Params,
    packet,
)
from bsd_tb import TB, TBError
from top_builds import BUILDS
from top_helpers import OUT_OF_RANGE, A, P, configure, need, set_pins_checked, setup
import runner


# A command's state change lands this many clocks after its last byte's handshake
# (docs/DESIGN.md, "Latencies").
EXEC_CLOCKS = 2


def hold_s(p: Params) -> float:
    """How long a pad level is held so that at least one poll sees it."""
    return 2.5 / p.poll_hz if p.poll_hz else 20 / p.clk_hz


@cocotb.test(skip=not runner.on("clk8", "clk8_poll0"))
async def test_random_sequence(dut) -> None:
    """Random pad levels, DIG_RST and DIG_CFG sets (ENA, TRG, IODIR) on every free pin."""
    p = P
    tb = TB(dut, p)
    model = Model(p)
    await tb.start(model)
    a = p.module_addr
    tb.log.info("seed %d", tb.seed)
    pins = p.free_pins
    for step in range(300):
        pin = tb.rng.choice(pins)
        r = tb.rng.random()
        if r < 0.2:
            cfg = tb.rng.choice([DIGCFG_IODIR | DIGCFG_ENA, DIGCFG_IODIR | DIGCFG_ENA | DIGCFG_TRG,
                                 DIGCFG_IODIR, DIGCFG_ENA | DIGCFG_TRG])
            await tb.command(model, packet(a, CMD_DIG_CFG, pin, cfg), settle_cycles=4)
        elif r < 0.35:
            await tb.command(model, packet(a, CMD_DIG_RST, pin), settle_cycles=4)
        else:
            level = 1 - model.level(pin)
            tb.set_pin(pin, level)
            exp = model.set_pin(pin, level)
            await tb.wait_s(hold_s(p))
            await tb.expect(exp, settle_cycles=4, what=f"step {step}: pin {pin} -> {level}")
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("clk8"))
async def test_polling_grid(dut) -> None:
    """POLL_HZ > 0: the latch fires on a poll, so a glitch between two polls is never seen
    and every raw_trans pulse lands on the poll grid that starts at reset."""
    p = P
    tb = TB(dut, p)
    model = Model(p)
    await tb.start(model)
    t_reset = tb.t_reset  # the poll phase starts on the first clock out of reset
    a, pin, period = p.module_addr, 0, 1 / p.poll_hz
    await tb.command(model, packet(a, CMD_DIG_CFG, pin, DIGCFG_IODIR | DIGCFG_ENA | DIGCFG_TRG))
    for k in range(3, 9):
        # A glitch well inside the k-th poll interval: unseen.
        await tb.until_s(t_reset + (k + 0.3) * period)
        tb.set_pin(pin, 1)
        await tb.until_s(t_reset + (k + 0.6) * period)
        tb.set_pin(pin, 0)
    await tb.until_s(t_reset + 9.5 * period)
    fired = tb.new_trans()
    if fired:
        raise TBError(f"a {0.3 * period * 1e6:.0f} us glitch between polls fired the latch "
                      f"at {[(t - t_reset) / period for t, _ in fired]} poll periods after reset")
    # A real edge fires on the next poll.
    tb.set_pin(pin, 1)
    model.set_pin(pin, 1)
    await tb.wait_s(2 * period)
    fired = tb.new_trans()
    if [q for _, q in fired] != [pin]:
        raise TBError(f"raw_trans {fired}, expected pin {pin} once")
    # Poll k strobes at the clock k * CLK_HZ / POLL_HZ after reset (± 1), then the
    # synchronized level is compared, and raw_trans is registered. Counted in whole clocks.
    clocks = round((fired[0][0] - t_reset) * p.clk_hz)
    per_poll = p.clk_hz / p.poll_hz
    off_clocks = clocks - round(clocks / per_poll) * per_poll
    if not 0 <= off_clocks <= 4:
        raise TBError(f"raw_trans {off_clocks:.2f} clocks off the poll grid")
    tb.log.info("raw_trans %.2f clocks after a poll", off_clocks)


@cocotb.test(skip=not runner.on("clk8_poll0"))
async def test_rearm_meets_edge(dut) -> None:
    """POLL_HZ = 0: re-arm a live latch (DIG_CFG set) while its pad moves in the TRG
    direction (TRG rising, then falling), at every clock offset around the command. The re-arm takes effect EXEC_CLOCKS after the last byte's
    handshake and sees the pad 2 clocks late: an edge whose synchronized level arrives
    before the arm clock fires (then the arm re-baselines); one that arrives on the arm
    clock is absorbed (decision 5: re-arm wins); a later one fires after the arm."""
    p = P
    tb = TB(dut, p)
    await tb.start()
    a, pin = p.module_addr, p.free_pins[0]
    half = tb.period_ps // 2
    for trg in (1, 0):  # rising edges, then the same with falling ones
        cfg = packet(a, CMD_DIG_CFG, pin, DIGCFG_IODIR | DIGCFG_ENA | (DIGCFG_TRG if trg else 0))
        fires = {}
        for d in range(-6, 5):
            tb.set_pin(pin, 1 - trg)
            await tb.source.send(cfg)          # arm with the pad away from the TRG level
            await tb.cycles(10)
            tb.new_trans()
            # Drive the same command by hand so the handshake clock is known: byte i is
            # taken at edge i; the pad moves a quarter clock after edge len-1+d.
            last = len(cfg) - 1
            move = cocotb.start_soon(_rise_after_edges(tb, pin, last + d, half // 2, trg))
            for b in cfg:
                dut.s_axis_tdata.value = b
                dut.s_axis_tvalid.value = 1
                await ReadOnly()
                if int(dut.s_axis_tready.value) != 1:
                    raise TBError("the core stalled a command with no reply waiting")
                await RisingEdge(tb.clk)
            dut.s_axis_tvalid.value = 0
            await move
            await tb.cycles(12)
            fires[d] = len(tb.new_trans())
        tb.log.info("TRG %d: fires by pad-edge offset: %s", trg, fires)
        # A pad edge a quarter clock after edge E0 + d reaches the latch's input at edge
        # E0 + d + 2 and is compared at E0 + d + 3. Compared before the arm clock: fires
        # once (and is re-baselined); on it (d = EXEC_CLOCKS - 3): absorbed; after: fires.
        absorbed = EXEC_CLOCKS - 3
        want = {d: 0 if d == absorbed else 1 for d in fires}
        if fires != want:
            raise TBError(f"TRG {trg}: fires by offset {fires}, expected {want}")
        if tb.fcov is not None:
            tb.fcov.latch_race(trg)


async def _rise_after_edges(tb: TB, pin: int, edges: int, extra_ps: int, level: int = 1) -> None:
    if edges < 0:
        # Negative offsets: the pad moves before the first byte is even offered.
        tb.set_pin(pin, level)
        await Timer(1, unit="ps")
        return
    for _ in range(edges + 1):
        await RisingEdge(tb.clk)
    await Timer(extra_ps, unit="ps")
    tb.set_pin(pin, level)


@cocotb.test(skip=not runner.on("gp1", "slow_fixed", "gp2"))
async def test_dig_rst_latch(dut) -> None:
    """ENA/TRG one-shot on raw_trans: fires once per arm in the TRG direction, a present
    level never fires, DIG_RST and DIG_CFG set re-arm, ENA = 0 and outputs never fire,
    DIG_RST on an output or disabled pin is silent, several pins on one sample: ascending."""
    tb, m = await setup(dut, pins=0)
    free = [p for p in P.free_pins]
    need(bool(free), "a configurable pin")
    for pin in free:
        lv = lambda level: tb.pins & ~(1 << pin) | (level << pin)  # noqa: E731
        await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_ENA | DIGCFG_TRG)  # rising
        await set_pins_checked(tb, m, lv(1))  # fires
        await set_pins_checked(tb, m, lv(0))
        await set_pins_checked(tb, m, lv(1))  # one-shot: nothing
        await tb.command(m, packet(A, CMD_DIG_RST, pin))  # re-armed at level 1
        await set_pins_checked(tb, m, lv(0))  # falling: not the TRG direction
        await set_pins_checked(tb, m, lv(1))  # fires
        await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_ENA)  # falling, re-armed at 1
        await set_pins_checked(tb, m, lv(0))  # fires
        await set_pins_checked(tb, m, lv(1))
        await tb.command(m, packet(A, CMD_DIG_RST, pin, 0))  # re-arm + cmdTooLong
        await set_pins_checked(tb, m, lv(0))  # fires
        await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_TRG)  # ENA = 0
        await set_pins_checked(tb, m, lv(1))
        await tb.command(m, packet(A, CMD_DIG_RST, pin))  # silent, inert
        await set_pins_checked(tb, m, lv(0))
        await configure(tb, m, pin, DIGCFG_ENA | DIGCFG_TRG)  # output with ENA
        await tb.command(m, packet(A, CMD_DIG_RST, pin))  # silent
        await set_pins_checked(tb, m, lv(1))
        await set_pins_checked(tb, m, lv(0))
        await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_ENA | DIGCFG_TRG)
        # A level already present never fires by itself.
        await set_pins_checked(tb, m, lv(0))
        await tb.cycles(200)
        await tb.expect(Output(), what="idle armed pin")
    for pin in OUT_OF_RANGE:
        await tb.command(m, packet(A, CMD_DIG_RST, pin))
    await tb.command(m, packet(A, CMD_DIG_RST))
    # Every free pin armed for rising edges, all rise on one sample: ascending pin order.
    for pin in free:
        await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_ENA | DIGCFG_TRG)
    await set_pins_checked(tb, m, tb.pins | sum(1 << p for p in free))
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("high_ids"))
async def test_every_pin_latch(dut) -> None:
    """The widest build (8 pins): every pin's latch armed for rising edges fires once when
    its pad rises (one pin at a time, then all together after a DIG_RST of each), never on
    the fall; raw_trans compared with the model after every pad change."""
    tb, m = await setup(dut, pins=0)
    free = [p for p in P.free_pins]
    need(len(free) == P.num_pins, "every pin configurable")
    for pin in free:
        await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_ENA | DIGCFG_TRG)
    for pin in free:
        await set_pins_checked(tb, m, tb.pins | 1 << pin)  # fires
    await set_pins_checked(tb, m, 0)  # falling: nothing
    for pin in free:
        await tb.command(m, packet(A, CMD_DIG_RST, pin))
    await set_pins_checked(tb, m, sum(1 << p for p in free))  # all at once, ascending
    tb.check_no_errors()


@pytest.mark.parametrize("sim, build", runner.cases(
    ["gp1", "slow_fixed", "gp2", "high_ids", "clk8", "clk8_poll0"], quick="verilator"))
def test_latch_top(sim: str, build: str) -> None:
    runner.run(sim, "brainstem_dio", __file__, BUILDS[build], build)
