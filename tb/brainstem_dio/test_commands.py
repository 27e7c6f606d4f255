# SPDX-License-Identifier: Apache-2.0
"""Commands, messages and framing at the top level of brainstem_dio (PROTOCOL.md §2, §3, §7):
every reply checked against the model (tb/lib/bsd_model.py).
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import ReadOnly, RisingEdge

from bsd_model import (
    CMD_DEBUG,
    CMD_DIG_CFG,
    CMD_DIG_IO,
    CMD_DIG_RST,
    CMD_HB,
    CMD_PTIME_RD,
    DEVCODE_HOST,
    DEVCODE_RFLX,
    DIGCFG_ENA,
    DIGCFG_IODIR,
    DIGCFG_TRG,
    DIGCFG_TSTATE,
    MAX_DATA,
    RESYNC_ADDR,
    TICK_S,
    packet,
)
from bsd_tb import _hex
from top_builds import BUILDS
from top_helpers import (
    FLAGS,
    OUT_OF_RANGE,
    A,
    P,
    configure,
    finish_timers,
    input_pins,
    measure,
    need,
    set_pins_checked,
    setup,
    start_timer,
)
import runner


@cocotb.test(skip=not runner.on("gp1", "gp2"))
async def test_worked_examples(dut) -> None:
    """PROTOCOL.md §7, in order, every reply from the model."""
    need(P.num_pins >= 5 and P.has_timer(4) and not P.has_timer(0) and not P.fixed_mask, "§7's pins")
    pins = 0b00001 | 0b10000  # pin 0 reads 1; pin 4 high so its edge timer waits for a fall
    tb, m = await setup(dut, pins)
    await tb.command(m, packet(A, CMD_DIG_CFG, 3))
    await tb.command(m, packet(A, CMD_DIG_CFG, 1, 0x00))
    tb.check_pins(m)
    await tb.command(m, packet(A, CMD_DIG_IO, 1, 1))
    tb.check_pins(m)
    await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_HOST | 0))
    await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_HOST | 1))
    await tb.command(m, packet(A, CMD_DIG_CFG, 7, 0x01))
    await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | 0))
    off = tb.rng.random() / P.clk_hz  # asynchronous to the clock
    got = await measure(tb, m, 4, DEVCODE_HOST, [(800e-6 + off, 0), (900e-6, 1)])
    assert got is not None and abs(got - 500) <= 1, got
    await tb.command(m, packet(A, CMD_DIG_CFG))
    await tb.command(m, packet(A, CMD_DIG_CFG, 2, 0x01, 0xFF))
    await tb.command(m, packet(A, 0x63))
    await tb.command(m, packet(RESYNC_ADDR))
    await tb.command(m, packet(A, CMD_DEBUG, 1, 2))
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1", "slow_fixed", "gp2"))
async def test_dig_cfg(dut) -> None:
    """Query and set on every pin and out of range, all DIGCFG bit patterns, bits 7:5
    ignored, pin_oe following IODIR, cmdTooLong after a set, FIXED pins per the model."""
    tb, m = await setup(dut, pins=None)
    for pin in list(P.pins) + OUT_OF_RANGE:
        await tb.command(m, packet(A, CMD_DIG_CFG, pin))
    values = [0x00, 0x01, 0x1F, 0xE0, 0xFF, 0xE1, 0x10, 0x08, 0x04, 0x02] + [tb.rng.randrange(256) for _ in range(6)]
    for value in values:
        for pin in P.pins:
            await tb.command(m, packet(A, CMD_DIG_CFG, pin, value))
            tb.check_pins(m)
        for pin in P.pins:
            await tb.command(m, packet(A, CMD_DIG_CFG, pin))
    for pin in OUT_OF_RANGE:
        await tb.command(m, packet(A, CMD_DIG_CFG, pin, 0x00))
    for n_extra in range(1, MAX_DATA - 2):
        pin = tb.rng.randrange(P.num_pins)
        await tb.command(m, packet(A, CMD_DIG_CFG, pin, tb.rng.randrange(256), *range(n_extra)))
        await tb.command(m, packet(A, CMD_DIG_CFG, pin))
        tb.check_pins(m)
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1", "slow_fixed", "gp2", "high_ids"))
async def test_dig_io(dut) -> None:
    """DIG_IO read with HOST/RFLX/both/neither, write values, pin_o/pin_oe, index errors,
    an input's pin_o showing its latch, RFLX strobes not held back by a stalled output."""
    tb, m = await setup(dut, pins=None)
    for _ in range(3):
        await set_pins_checked(tb, m, tb.rng.getrandbits(P.num_pins))
        for pin in P.pins:
            for flags in FLAGS:
                await tb.command(m, packet(A, CMD_DIG_IO, flags | pin))
    for pin in OUT_OF_RANGE:
        await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_HOST | (pin & 0x3F)))
        await tb.command(m, packet(A, CMD_DIG_IO, pin, 1))
    # Outputs: writes of several values, reads and writes of the wrong direction.
    outs = [p for p in P.free_pins if p % 2 == 1] or P.free_pins[:1]
    for pin in outs:
        await configure(tb, m, pin, 0x00)
    tb.check_pins(m)
    for value in (1, 0, 2, 0x80, 0xFF, 0):
        for pin in P.pins:
            await tb.command(m, packet(A, CMD_DIG_IO, pin, value))
            tb.check_pins(m)
    for pin in P.pins:
        await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_HOST | DEVCODE_RFLX | pin))
    # An input shows its output latch on pin_o.
    for pin in outs:
        await tb.command(m, packet(A, CMD_DIG_IO, pin, 1))
        await configure(tb, m, pin, 0x01)
        tb.check_pins(m)
    for n_extra in range(1, MAX_DATA - 2):
        await configure(tb, m, outs[0], 0x00)
        await tb.command(m, packet(A, CMD_DIG_IO, outs[0], n_extra & 1, *([7] * n_extra)))
        tb.check_pins(m)
    # RFLX is never held back by the host link.
    tb.sink.paused = True
    ins = input_pins(m)
    for pin in ins:
        await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_RFLX | pin), settle_cycles=8)
    # Strobes on consecutive commands streamed back to back.
    burst = b"".join(packet(A, CMD_DIG_IO, DEVCODE_RFLX | p) for p in ins)
    await tb.command(m, burst)
    tb.sink.paused = False
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1", "slow_fixed", "gp2"))
async def test_messages(dut) -> None:
    """Every message of §2 and its precedence: cmdInvalid (any N, codes 4 and 0x80 too)
    before cmdTooShort before the command's own error; cmdTooLong only after success;
    cmdHB from the host always silent; link_up 0 without heartbeats."""
    tb, m = await setup(dut, pins=None)
    rng = tb.rng
    invalid = [4, 0x80, 1, 25, 30, 0x63, 0xFF] + rng.sample(range(31, 256), 6)
    for code in invalid:
        for n in (1, 2, 3, MAX_DATA):
            await tb.command(m, packet(A, code, *[rng.choice([0, 1, A, 26]) for _ in range(n - 1)]))
    for n in range(4, MAX_DATA):  # every other N, once
        await tb.command(m, packet(A, rng.choice(invalid), *[rng.choice([0, 1, A, 26]) for _ in range(n - 1)]))
    for cmd in (CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST, CMD_PTIME_RD):
        await tb.command(m, packet(A, cmd))
    # cmdIndexErr, each reason, with and without extra bytes (no cmdTooLong after an error).
    # (an output with a timer where one exists, so that a pin without one stays an input:
    # GP 1.0's only such pin is pin 0)
    outs = ([p for p in P.free_pins if P.has_timer(p)] or P.free_pins)[:1]
    for pin in outs:
        await configure(tb, m, pin, 0x00)
    ins = input_pins(m)
    no_timer = [p for p in P.pins if not P.has_timer(p)]
    assert not no_timer or any(m.is_input(p) for p in no_timer), "no input pin without a timer to time"
    for extra in ((), (0,), (1, 2, 3, 4)):
        for pin in OUT_OF_RANGE:
            await tb.command(m, packet(A, CMD_DIG_CFG, pin, *extra[:1]))
            await tb.command(m, packet(A, CMD_DIG_CFG, pin, 0x01, *extra))
            await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_HOST | DEVCODE_RFLX | (pin & 0x3F)))
            await tb.command(m, packet(A, CMD_DIG_IO, pin, 1, *extra))
            await tb.command(m, packet(A, CMD_DIG_RST, pin, *extra))
            await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | (pin & 0x3F), *extra))
        for pin in outs:  # reading or timing an output
            await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_HOST | pin))
            await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | pin, *extra))
        for pin in ins[:2]:  # writing an input
            await tb.command(m, packet(A, CMD_DIG_IO, pin, 1, *extra))
        for pin in no_timer:
            if m.is_input(pin):
                await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | pin, *extra))
    tb.check_pins(m)
    # tmrConflict: a running timer (static pad: it will not finish during this test).
    tpins = [p for p in P.timer_pins if m.is_input(p)]
    if tpins:
        t = tpins[0]
        await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | t))
        for flags in FLAGS:
            await tb.command(m, packet(A, CMD_PTIME_RD, flags | t))
            await tb.command(m, packet(A, CMD_PTIME_RD, flags | t, 9, 9))
        # cmdTooLong after a PTIME_RD that starts its timer
        if len(tpins) > 1:
            await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | tpins[1], 0))
            await tb.command(m, packet(A, CMD_PTIME_RD, tpins[1]))
    # cmdTooLong after each command that succeeded, every N up to 8.
    pin_in = ins[0]
    for n in range(4, MAX_DATA + 1):
        extra = tuple(rng.randrange(256) for _ in range(n - 3))
        await tb.command(m, packet(A, CMD_DIG_CFG, pin_in, 0x01, *extra))
        if outs:
            await tb.command(m, packet(A, CMD_DIG_IO, outs[0], n & 1, *extra))
            tb.check_pins(m)
        await tb.command(m, packet(A, CMD_DIG_RST, pin_in, *extra, 0))
    # cmdDEBUG: echoed whole for every N from 1 (just the code) to 8, never cmdTooShort/TooLong;
    # echoes back to back, and an echo held behind a stalled output.
    for n in range(1, MAX_DATA + 1):
        await tb.command(m, packet(A, CMD_DEBUG, *[rng.randrange(256) for _ in range(n - 1)]))
    await tb.command(m, b"".join(packet(A, CMD_DEBUG, *range(n, 2 * n - 1)) for n in range(MAX_DATA, 0, -1)))
    held = packet(A, CMD_DEBUG, 0xFF, 0, 0x80, 1, 2, 3, 0xAD) + packet(A, CMD_DIG_CFG, pin_in) + packet(A, CMD_DEBUG, *range(7))
    exp = m.feed(held)
    tb.sink.paused = True
    tb.source.send_nowait(held)
    await tb.cycles(400)
    tb.sink.paused = False
    await tb.expect(exp, what=_hex(held))
    # cmdHB from the host: silent for any N, any type.
    for data in ([CMD_HB], [CMD_HB, 2], [CMD_HB, 3], [CMD_HB, 0], [CMD_HB, 2, 1, 2, 3, 4, 5, 6]):
        await tb.command(m, packet(A, *data))
    for n in range(3, MAX_DATA):
        await tb.command(m, packet(A, CMD_HB, *range(2, n + 1)))
    await ReadOnly()
    assert int(dut.link_up.value) == 0, "link_up must be 0 while HB_RATE = 0"
    await RisingEdge(dut.clk)
    # serialError: N > 8 to our address.
    for n in (9, 10, 0x80, 0xFF):
        await tb.command(m, bytes([A, n]))
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1", "slow_fixed", "gp2"))
async def test_framing(dut) -> None:
    """Resync probe; 0xAD with N > 0 and other addresses consumed whole, even when their
    data looks like our packets; N = 0 to us; N > 8 to us and to others: the next byte is a
    new address."""
    tb, m = await setup(dut, pins=None)
    rng = tb.rng
    query = packet(A, CMD_DIG_CFG, 0)
    await tb.command(m, packet(RESYNC_ADDR))
    for n in range(1, MAX_DATA + 1):
        await tb.command(m, bytes([RESYNC_ADDR, n]) + (query + packet(RESYNC_ADDR) + query)[:n])
        await tb.command(m, query)
    others = [0, 1, 3, (A + 1) & 0xFF, A - 1, (A + 2) & 0xFF, 0xAC, 0xAE, 0xFF] + [rng.randrange(256) for _ in range(5)]
    others = [o for o in others if o not in (A, RESYNC_ADDR)]
    for addr in others:
        n = rng.randint(0, MAX_DATA)
        data = (query + bytes([A, 0]) + packet(RESYNC_ADDR) + query)[:n]
        await tb.command(m, bytes([addr, n]) + data)
        await tb.command(m, query)
    # N = 0 to us: nothing, and the next byte is an address.
    await tb.command(m, packet(A))
    await tb.command(m, packet(A) + query)
    # N > 8: address and length dropped, the next byte is a new address.
    for addr in (A, others[0], RESYNC_ADDR):
        for n in (9, 0xAD, A if A > 8 else 0x20, 0xFF):
            await tb.command(m, bytes([addr, n]) + query)
            await tb.command(m, bytes([addr, n, RESYNC_ADDR, 0]))
    # Everything back to back in one stream.
    stream = b"".join([bytes([A, 9]), query, bytes([0x55, 2, A, 2]), packet(RESYNC_ADDR),
                       packet(A), bytes([RESYNC_ADDR, 1, A]), query])
    await tb.command(m, stream)
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("slow_fixed"))
async def test_rx_timeout(dut) -> None:
    """A partial packet is dropped after RX_TIMEOUT_US of input idle time, not before: gaps
    just above and just below it, cut after the address, the length and a data byte."""
    need(P.rx_timeout_us > 0, "an RX timeout")
    tb, m = await setup(dut, pins=None)
    limit = P.rx_timeout_s
    # DESIGN.md 10: dropped between RX_TIMEOUT_US and RX_TIMEOUT_US + 1 tick of idle time;
    # Two clocks of slack: the tick phase and the idle count's first and last clock.
    slack = 2 / P.clk_hz
    gaps = [(limit + TICK_S + slack, True), (limit - slack, False), (limit + 50e-6, True),
            (limit / 2, False), (3 * limit, True), (limit - 20e-6, False)]
    full = packet(A, CMD_DIG_CFG, P.num_pins - 1)
    for cut in (1, 2, 3):
        for gap_s, above in gaps:
            first, rest = full[:cut], full[cut:]
            # Dropped: the rest is preceded by a whole new packet, so a kept partial shows.
            second = full if above else rest
            m.feed(first)
            t1 = (await tb.source.send(first))[-1]
            t2 = (await tb.source.send(second, gap_cycles=tb.cycles_of(gap_s) - 1))[0]
            idle = t2 - t1 - 1 / P.clk_hz
            if above:
                assert idle >= limit + TICK_S + slack / 2, f"gap {idle * 1e6:.2f} us not above the window"
            else:
                assert idle <= limit - slack / 2, f"gap {idle * 1e6:.2f} us not below the limit"
            exp = m.feed(second, idle_before_s=idle)
            await tb.expect(exp, what=f"{_hex(first)} | {idle * 1e6:.2f} us idle | {_hex(second)}")
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("slow_fixed"))
async def test_fixed_pins(dut) -> None:
    """FIXED_MASK/FIXED_CFG: query shows bit 7 and the fixed bits, DIG_CFG set gives
    configErr and changes nothing (extra bytes: still only configErr), a fixed output drives
    and can be written, a fixed input with ENA is armed at reset on the present level."""
    need(bool(P.fixed_mask), "a fixed pin")
    fixed = [p for p in P.pins if P.is_fixed(p)]
    tb, m = await setup(dut, pins=0)
    tb.check_pins(m)
    for pin in fixed:
        await tb.command(m, packet(A, CMD_DIG_CFG, pin))
        for value in (0x01, 0x00, 0xFF, m.digcfg(pin), P.fixed_bits(pin)):
            await tb.command(m, packet(A, CMD_DIG_CFG, pin, value))
            await tb.command(m, packet(A, CMD_DIG_CFG, pin, value, 1, 2))
        await tb.command(m, packet(A, CMD_DIG_CFG, pin))
        tb.check_pins(m)
        await tb.command(m, packet(A, CMD_DIG_IO, pin, 1))
        await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_HOST | DEVCODE_RFLX | pin))
        await tb.command(m, packet(A, CMD_DIG_RST, pin))
        tb.check_pins(m)
    armed = [p for p in fixed if P.fixed_bits(p) & DIGCFG_ENA and P.fixed_bits(p) & DIGCFG_IODIR]
    for pin in armed:
        trg = int(bool(P.fixed_bits(pin) & DIGCFG_TRG))
        for start in (1 - trg, trg):
            # Reset with the pad at `start`: a level already present never fires.
            tb.set_pins(tb.pins & ~(1 << pin) | start << pin)
            await tb.cycles(4)
            await tb.reset()
            await tb.expect(m.reset(tb.pins), what="reset")
            lv = lambda level: tb.pins & ~(1 << pin) | (level << pin)  # noqa: E731
            await set_pins_checked(tb, m, lv(1 - start))
            await set_pins_checked(tb, m, lv(start))
            await set_pins_checked(tb, m, lv(1 - start))
            await tb.command(m, packet(A, CMD_DIG_RST, pin))
            await set_pins_checked(tb, m, lv(start))
            await set_pins_checked(tb, m, lv(1 - start))
    tb.check_no_errors()


@cocotb.test(skip=not runner.on("gp1", "slow_fixed"))
async def test_forms_by_pin_kind(dut) -> None:
    """Every form (N = 2..8) of every pin command on a pin of each kind: an input and an
    output with and without a timer, each fixed pin as it is, and pins out of range. Each
    PTIME_RD that starts its timer is run to its result (the pad at the non-target level
    first, then driven to the target); a busy timer gets tmrConflict in every form."""
    tb, m = await setup(dut, pins=0)
    free_timer = [p for p in P.free_pins if P.has_timer(p)]
    free_plain = [p for p in P.free_pins if not P.has_timer(p)]
    cases: list[tuple[int, int | None]] = []  # (pin, DIGCFG to set first, None: leave it)
    for pins in (free_timer, free_plain):
        if pins:
            cases += [(pins[0], DIGCFG_IODIR), (pins[0], 0x00)]
    cases += [(p, None) for p in P.pins if P.is_fixed(p)]
    cases += [(P.num_pins, None), (63, None)]
    for pin, cfg in cases:
        if cfg is not None:
            await configure(tb, m, pin, cfg)
        in_range = pin < P.num_pins
        for n in range(2, MAX_DATA + 1):
            extra = tuple(range(1, n - 2)) if n > 3 else ()
            keep = m.digcfg(pin) if in_range else 0x01
            if n == 2:
                await tb.command(m, packet(A, CMD_DIG_CFG, pin))
                await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_HOST | (pin & 0x3F)))
            else:
                await tb.command(m, packet(A, CMD_DIG_CFG, pin, keep, *extra))
                await tb.command(m, packet(A, CMD_DIG_IO, pin, n & 1, *extra))
            tb.check_pins(m)
            rst_extra = tuple(range(n - 2))
            await tb.command(m, packet(A, CMD_DIG_RST, pin, *rst_extra))
            timed = in_range and P.has_timer(pin) and m.is_input(pin)
            if not timed:
                await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | (pin & 0x3F), *rst_extra))
                continue
            target = int(bool(m.cfg[pin] & DIGCFG_TSTATE))
            await set_pins_checked(tb, m, tb.pins & ~(1 << pin) | (1 - target) << pin)
            got = await measure(tb, m, pin, DEVCODE_HOST, [(20e-6, target)], rst_extra)
            assert got, got
        if in_range and P.has_timer(pin) and m.is_input(pin):
            # Busy: tmrConflict in every form, then the running measurement ends normally.
            target = int(bool(m.cfg[pin] & DIGCFG_TSTATE))
            await set_pins_checked(tb, m, tb.pins & ~(1 << pin) | (1 - target) << pin)
            t0, wave = await start_timer(tb, m, pin, DEVCODE_HOST, [(1e-3, target)])
            for n in range(2, MAX_DATA + 1):
                await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | pin, *range(n - 2)))
            await finish_timers(tb, m, {pin: (t0, wave)})
    tb.check_no_errors()


@pytest.mark.parametrize("sim, build", runner.cases(["gp1", "slow_fixed", "gp2", "high_ids"], quick="verilator"))
def test_commands_top(sim: str, build: str) -> None:
    runner.run(sim, "brainstem_dio", __file__, BUILDS[build], build)


def test_commands_top_icarus_examples() -> None:
    """make test's run of the top on Icarus: the worked examples on GP 1.0 (test-full runs all)."""
    runner.run("icarus", "brainstem_dio", __file__, BUILDS["gp1"], "gp1", testcase="test_worked_examples")
