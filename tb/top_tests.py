"""Top-level cocotb tests of brainstem_dio, every reply checked against bsd_model.

The parameter set comes from $BSD_PARAMS (set by test_top.py), so the same tests run on
every build; tests that need a feature the build lacks (a fixed pin, an RX timeout, a
heartbeat) are skipped by test_top.py's selection, and say so if run anyway.
"""

from __future__ import annotations

import os
import random

import cocotb
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from bsd_model import (
    CMD_DEV_VAL,
    CMD_DIG_CFG,
    CMD_DIG_IO,
    CMD_DIG_RST,
    CMD_HB,
    CMD_PTIME_RD,
    DEVCODE_HOST,
    DEVCODE_RFLX,
    DIGCFG_ENA,
    DIGCFG_IODIR,
    DIGCFG_TMODE,
    DIGCFG_TRG,
    DIGCFG_TSTATE,
    HB_ANSWER,
    MAX_DATA,
    RESYNC_ADDR,
    TICK_HZ,
    TICK_S,
    TIMER_MAX_TICKS,
    TIMER_TIMEOUT_S,
    Model,
    Output,
    Params,
    expected_ticks,
    packet,
    tick_tolerance,
    ticks_close,
    timer_completion,
    timer_interval,
)
from bsd_tb import TB, TBError, _hex

P = Params.from_env()
A = P.module_addr
FLAGS = (0, DEVCODE_HOST, DEVCODE_RFLX, DEVCODE_HOST | DEVCODE_RFLX)
OUT_OF_RANGE = sorted({P.num_pins, P.num_pins + 1, 63, 64, 0x80, 0xFF} - set(range(P.num_pins)))


async def setup(dut, pins: int | None = 0) -> tuple[TB, Model]:
    """A TB and a model after a checked reset; pins=None: random pad levels (from the TB's
    seed, so BSD_SEED replays them)."""
    tb = TB(dut, P)
    tb.log.info("params %s, seed %d", P.to_json(), tb.seed)
    if pins is None:
        pins = tb.rng.getrandbits(P.num_pins)
    model = Model(P, pins)
    await tb.start(model, pins)
    return tb, model


def need(cond: bool, what: str) -> None:
    if not cond:
        raise TBError(f"this build lacks {what}; test_top.py should not select this test here")


async def settle_pins(tb: TB) -> None:
    """Let a pad change reach the synchronized level and, with ENA, a poll sample."""
    poll = 1.0 / P.poll_hz if P.poll_hz else 0.0
    await tb.wait_s(poll + 10 / P.clk_hz)
    await tb.cycles(10)


async def set_pins_checked(tb: TB, m: Model, levels: int) -> None:
    tb.set_pins(levels)
    exp = m.set_pins(levels)
    await settle_pins(tb)
    await tb.expect(exp, settle_cycles=2, what=f"pins -> {levels:b}")


def input_pins(m: Model) -> list[int]:
    return [p for p in P.pins if m.is_input(p)]


# ------------------------------------------------------------------------------ timers

def timer_value(tb: TB, m: Model, pin: int) -> int | None:
    """The result of `pin`'s measurement among the packets/strobes not yet checked."""
    run = m.timer_run(pin)
    tid = P.timer_id(pin)
    if run.host:
        for pk in tb.packets[tb._n_pkt:]:
            d = pk.data
            if len(d) == 6 and d[2] == CMD_DEV_VAL and d[3] == tid:
                return d[4] << 8 | d[5]
    if run.rflx:
        for _, i, v in tb.rflx[tb._n_rflx:]:
            if i == tid:
                return v
    return None


def check_result(pin: int, got: int, interval: float | None) -> None:
    if interval is None:
        if got != 0:
            raise TBError(f"pin {pin}: timed out, expected result 0, got {got}")
        return
    exp = expected_ticks(0.0, [(0.0, 0), (interval, 1)], False, 1)
    fine = ticks_close(got, interval, P.clk_hz)
    if P.clk_hz >= 12_000_000:
        fine = fine and abs(got - exp) <= 1
    if not fine or got == 0:
        raise TBError(
            f"pin {pin}: result {got} ticks for {interval * 1e6:.3f} us "
            f"(expected {exp} within {tick_tolerance(P.clk_hz):.2f})"
        )


async def start_timer(tb: TB, m: Model, pin: int, flags: int, rel_wave: list[tuple[float, int]],
                      extra: tuple[int, ...] = ()) -> tuple[float, list[tuple[float, int]]]:
    """PTIME_RD `pin` and drive its pad `rel_wave` [(seconds after the start, level)...].
    Returns the start reference (the last byte's transfer) and the absolute waveform."""
    pkt = packet(A, CMD_PTIME_RD, flags | pin, *extra)
    exp = m.feed(pkt)
    t0 = (await tb.source.send(pkt))[-1]
    wave = [(0.0, tb.pins >> pin & 1)] + [(t0 + dt, lvl) for dt, lvl in rel_wave]
    tb.drive_waveform(pin, wave[1:])
    await tb.expect(exp, settle_cycles=4, what=_hex(pkt))
    return t0, wave


async def finish_timers(tb: TB, m: Model, runs: dict[int, tuple[float, list]], margin_s: float = 30e-6) -> dict[int, int]:
    """Wait for the measurements of `runs` {pin: (start, waveform)} to finish, check each
    result against the waveform and the packets/strobes (their order included) against the
    model. Completions must be well apart in time (ties are a separate test)."""
    done = {}
    for pin, (t0, wave) in runs.items():
        run = m.timer_run(pin)
        c = timer_completion(t0, wave, run.width, run.target)
        t_end = c[0] if c is not None and (c[0] - t0) * TICK_HZ <= TIMER_MAX_TICKS else t0 + TIMER_TIMEOUT_S
        done[pin] = (t_end, timer_interval(t0, wave, run.width, run.target))
    order = sorted(done, key=lambda p: done[p][0])
    for pin in order:
        run = m.timer_run(pin)
        tb.log.info("timer pin %d %s target %d host %d rflx %d: start %.3f us, wave %s -> %s", pin,
                    "width" if run.width else "edge", run.target, run.host, run.rflx, runs[pin][0] * 1e6,
                    [(round((t - runs[pin][0]) * 1e6, 3), lv) for t, lv in runs[pin][1][1:]],
                    "timeout" if done[pin][1] is None else f"{done[pin][1] * 1e6:.3f} us")
    # Wait for the waveforms' ends too, so no edge of this run falls into the next one.
    t_wave_end = max(wave[-1][0] for _, wave in runs.values())
    await tb.until_s(max([t for t, _ in done.values()] + [t_wave_end]) + margin_s)
    exp = Output()
    results = {}
    for pin in order:
        run = m.timer_run(pin)
        if run.host or run.rflx:
            got = timer_value(tb, m, pin)
            if got is None:
                raise TBError(f"pin {pin}: no timer result by {done[pin][0] * 1e3:.4f} ms + margin")
            check_result(pin, got, done[pin][1])
            results[pin] = got
            exp.extend(m.timer_complete(pin, got))
        else:
            m.timer_done(pin)
    await tb.expect(exp, what=f"timer results of pins {order}")
    for pin, (t0, wave) in runs.items():
        m.set_pin(pin, wave[-1][1])
    return results


async def measure(tb: TB, m: Model, pin: int, flags: int, rel_wave: list[tuple[float, int]],
                  extra: tuple[int, ...] = ()) -> int | None:
    t0, wave = await start_timer(tb, m, pin, flags, rel_wave, extra)
    return (await finish_timers(tb, m, {pin: (t0, wave)})).get(pin)


async def configure(tb: TB, m: Model, pin: int, cfg: int) -> None:
    await tb.command(m, packet(A, CMD_DIG_CFG, pin, cfg))


# ============================================================================== tests

@cocotb.test()
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
    tb.check_no_errors()


@cocotb.test()
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


@cocotb.test()
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


@cocotb.test()
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


@cocotb.test()
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
    for cmd in (CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST, CMD_PTIME_RD):
        await tb.command(m, packet(A, cmd))
    # cmdIndexErr, each reason, with and without extra bytes (no cmdTooLong after an error).
    outs = P.free_pins[:1]
    for pin in outs:
        await configure(tb, m, pin, 0x00)
    ins = input_pins(m)
    no_timer = [p for p in P.pins if not P.has_timer(p)]
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
    # cmdHB from the host: silent for any N, any type.
    for data in ([CMD_HB], [CMD_HB, 2], [CMD_HB, 3], [CMD_HB, 0], [CMD_HB, 2, 1, 2, 3, 4, 5, 6]):
        await tb.command(m, packet(A, *data))
    await ReadOnly()
    assert int(dut.link_up.value) == 0, "link_up must be 0 while HB_RATE = 0"
    await RisingEdge(dut.clk)
    # serialError: N > 8 to our address.
    for n in (9, 10, 0x80, 0xFF):
        await tb.command(m, bytes([A, n]))
    tb.check_no_errors()


@cocotb.test()
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


@cocotb.test()
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


@cocotb.test()
async def test_timers(dut) -> None:
    """Edge and width mode for each timer pin and both targets, ±1 tick of the model; HOST,
    RFLX, both, neither; a pin already at target must leave it first; a sub-tick pulse gives
    1, never 0; busy (tmrConflict) until delivered; concurrent timers; commands served
    meanwhile; cmdTooLong after a PTIME_RD; a DIG_CFG set mid-measurement keeps the mode."""
    need(bool(P.timer_pins), "a timer pin")
    tb, m = await setup(dut, pins=0)
    rng = tb.rng
    jit = lambda: rng.random() * 1e-6  # noqa: E731  pad changes asynchronous to clk
    tpins = [p for p in P.timer_pins if m.is_input(p)]
    for i, pin in enumerate(tpins):
        for width in (False, True):
            for target in (0, 1):
                cfg = DIGCFG_IODIR | (DIGCFG_TMODE if width else 0) | (DIGCFG_TSTATE if target else 0)
                if not P.is_fixed(pin):
                    await configure(tb, m, pin, cfg)
                run_cfg = m.cfg[pin]
                w, tg = bool(run_cfg & DIGCFG_TMODE), int(bool(run_cfg & DIGCFG_TSTATE))
                nt = 1 - tg
                await set_pins_checked(tb, m, tb.pins & ~(1 << pin) | (nt << pin))
                flags = FLAGS[(i + 2 * width + target) % 4] or DEVCODE_HOST
                if w:
                    wave = [(40e-6 + jit(), tg), (40e-6 + rng.uniform(20e-6, 400e-6), nt)]
                else:
                    wave = [(rng.uniform(10e-6, 600e-6), tg), (650e-6, nt)]
                await measure(tb, m, pin, flags, wave)
    pin = tpins[0]
    # Neither HOST nor RFLX: busy until the measurement ends, then free again.
    await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_TSTATE)  # edge to 1
    await set_pins_checked(tb, m, tb.pins & ~(1 << pin))
    t0, wave = await start_timer(tb, m, pin, 0, [(100e-6 + jit(), 1), (150e-6, 0)])
    await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | pin))  # tmrConflict
    await finish_timers(tb, m, {pin: (t0, wave)})
    await measure(tb, m, pin, DEVCODE_HOST | DEVCODE_RFLX, [(30e-6 + jit(), 1), (40e-6, 0)], extra=(0x55,))
    # Already at target: the first edge away from it does not complete; the next one does.
    await set_pins_checked(tb, m, tb.pins | 1 << pin)
    await measure(tb, m, pin, DEVCODE_HOST, [(50e-6 + jit(), 0), (300e-6 + jit(), 1), (320e-6, 0)])
    # Width mode: a pulse under one tick is still a completed result: 1, never 0.
    await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_TMODE | DIGCFG_TSTATE)
    for width_s in (0.2e-6, 0.5e-6, 1.0e-6):
        t = 50e-6 + jit()
        got = await measure(tb, m, pin, DEVCODE_HOST, [(t, 1), (t + width_s, 0)])
        assert got is not None and got >= 1
    # A DIG_CFG set during a measurement does not change the running mode (width here).
    t0, wave = await start_timer(tb, m, pin, DEVCODE_HOST, [(100e-6 + jit(), 1), (400e-6 + jit(), 0)])
    await configure(tb, m, pin, DIGCFG_IODIR)  # edge mode, target 0, from now on
    await finish_timers(tb, m, {pin: (t0, wave)})
    # DESIGN.md 3: a HOST result keeps its timer busy until its packet has left m_axis.
    await configure(tb, m, pin, DIGCFG_IODIR | DIGCFG_TSTATE)  # edge to 1
    await set_pins_checked(tb, m, tb.pins & ~(1 << pin))
    tb.sink.paused = True
    t0, wave = await start_timer(tb, m, pin, DEVCODE_HOST, [(50e-6 + jit(), 1), (80e-6, 0)])
    await tb.until_s(t0 + 100e-6)
    again = packet(A, CMD_PTIME_RD, DEVCODE_HOST | pin)
    sent = tb.source.send_nowait(again)
    await tb.cycles(50)
    assert timer_value(tb, m, pin) is None, "a packet left a paused m_axis"
    conflict = m.feed(again)
    tb.sink.paused = False
    await tb.source.wait_sent(sent)
    await tb.sink.wait_count(tb._n_pkt + 2, 1e-3)
    got = timer_value(tb, m, pin)
    assert got is not None
    check_result(pin, got, timer_interval(t0, wave, False, 1))
    await tb.expect(m.timer_complete(pin, got).extend(conflict), what="PTIME_RD on an undelivered result")
    m.set_pin(pin, 0)
    await measure(tb, m, pin, DEVCODE_HOST, [(20e-6 + jit(), 1), (30e-6, 0)])
    # DESIGN.md 7: a pin turned output mid-measurement is still watched at the pad; timing
    # it meanwhile is cmdIndexErr (an output), which comes before tmrConflict.
    t0, wave = await start_timer(tb, m, pin, DEVCODE_HOST | DEVCODE_RFLX, [(200e-6 + jit(), 1), (250e-6, 0)])
    await configure(tb, m, pin, DIGCFG_TSTATE)  # output
    await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | pin))
    await finish_timers(tb, m, {pin: (t0, wave)})
    await configure(tb, m, pin, DIGCFG_IODIR)
    # All timers at once, commands served meanwhile, conflicts while busy.
    for p in tpins:
        if not P.is_fixed(p):
            await configure(tb, m, p, DIGCFG_IODIR | DIGCFG_TSTATE)  # edge to 1
    targets = {p: int(bool(m.cfg[p] & DIGCFG_TSTATE)) for p in tpins}
    levels = tb.pins
    for p in tpins:
        levels = levels & ~(1 << p) | (1 - targets[p]) << p
    await set_pins_checked(tb, m, levels)
    runs = {}
    for k, p in enumerate(tpins):
        rel = [(500e-6 - 60e-6 * k + jit(), targets[p]), (700e-6, 1 - targets[p])]
        runs[p] = await start_timer(tb, m, p, FLAGS[1 + k % 3], rel)
    for p in tpins:
        await tb.command(m, packet(A, CMD_PTIME_RD, DEVCODE_HOST | p))
    await tb.command(m, packet(A, CMD_DIG_CFG, 0))
    await tb.command(m, packet(A, CMD_DIG_IO, DEVCODE_HOST | input_pins(m)[0]))
    await finish_timers(tb, m, runs)
    tb.check_no_errors()


@cocotb.test()
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


@cocotb.test()
async def test_reply_before_later_timer(dut) -> None:
    """DESIGN.md 1 at clock level: a command's reply or message is an event of the clock
    the command executes. PTIME_RD with an extra byte starts the timer and answers
    cmdTooLong; a pad edge the clock after its last byte ends the measurement a clock
    after that start, so the message leaves first, then the result (1 tick)."""
    tpins = [p for p in P.timer_pins if not P.is_fixed(p)]
    need(len(tpins) >= 1, "a configurable timer pin")
    pin = tpins[0]
    tb, m = await setup(dut, pins=1 << pin)
    await configure(tb, m, pin, DIGCFG_IODIR)  # edge mode, target 0; the pad is high
    pkt = packet(A, CMD_PTIME_RD, DEVCODE_HOST | pin, 0)
    exp = m.feed(pkt)
    sent = tb.source.send_nowait(pkt)
    while len(sent.times) < len(pkt):
        await RisingEdge(dut.clk)
        await ReadOnly()  # every coroutine of this edge has run: the times are final
    await FallingEdge(dut.clk)  # right after the edge that took the last byte
    tb.set_pin(pin, 0)
    await tb.cycles(40)
    got = timer_value(tb, m, pin)
    assert got == 1, f"result {got} for an edge 1 clock after the start"
    exp.extend(m.timer_complete(pin, got))
    m.set_pin(pin, 0)
    await tb.expect(exp, what="cmdTooLong, then the result")
    tb.check_no_errors()


@cocotb.test()
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


# ------------------------------------------------------------------------------ stress

def random_packet(rng: random.Random, m: Model) -> bytes:
    """One random host packet: mostly well-formed commands to us, plus every kind of
    invalid, foreign, probe, N = 0 and N > 8 packet."""
    n_pins = P.num_pins

    def pin_byte() -> int:
        if rng.random() < 0.8:
            return rng.randrange(n_pins)
        return rng.choice(OUT_OF_RANGE + [rng.randrange(256)])

    def devcode() -> int:
        return rng.choice(FLAGS) | (pin_byte() & 0x3F)

    r = rng.random()
    if r < 0.62:
        cmd = rng.choice([CMD_DIG_CFG] * 4 + [CMD_DIG_IO] * 4 + [CMD_DIG_RST, CMD_PTIME_RD, CMD_PTIME_RD,
                                                                 CMD_HB, rng.randrange(256)])
        if cmd == CMD_DIG_CFG:
            if rng.random() < 0.5:
                data = [cmd, pin_byte()]
            else:
                cfg = rng.randrange(256)
                if rng.random() < 0.6:
                    cfg |= DIGCFG_IODIR  # keep plenty of inputs to read and time
                data = [cmd, pin_byte(), cfg]
        elif cmd == CMD_DIG_IO:
            data = [cmd, devcode()] if rng.random() < 0.6 else [cmd, pin_byte(), rng.choice([0, 1, 0xFF])]
        elif cmd in (CMD_DIG_RST, CMD_PTIME_RD):
            data = [cmd, devcode() if cmd == CMD_PTIME_RD else pin_byte()]
        else:
            data = [cmd] + [rng.randrange(256) for _ in range(rng.randint(0, 3))]
        u = rng.random()
        if u < 0.08:
            data = data[:1]
        elif u < 0.16:
            data += [rng.randrange(256) for _ in range(rng.randint(1, MAX_DATA - len(data)))] if len(data) < MAX_DATA else []
        return packet(A, *data)
    if r < 0.74:
        addr = rng.choice([a for a in (rng.randrange(256), (A + 1) & 0xFF, (A + 2) & 0xFF, 0) if a not in (A, RESYNC_ADDR)] or [0])
        n = rng.randint(0, MAX_DATA)
        pool = [A, 0, 2, RESYNC_ADDR, CMD_DIG_CFG, CMD_DIG_IO, 9]
        return bytes([addr, n] + [rng.choice(pool) if rng.random() < 0.5 else rng.randrange(256) for _ in range(n)])
    if r < 0.79:
        return packet(RESYNC_ADDR)
    if r < 0.82:
        n = rng.randint(1, MAX_DATA)
        return bytes([RESYNC_ADDR, n] + [rng.choice([A, 0, 2, 26]) for _ in range(n)])
    if r < 0.88:
        return bytes([rng.choice([A, A, RESYNC_ADDR, rng.randrange(256)]), rng.randint(MAX_DATA + 1, 255)])
    if r < 0.91:
        return packet(A)
    if r < 0.94:
        # Raw garbage: the framing may land anywhere; the model follows it byte by byte.
        return bytes(rng.randrange(256) for _ in range(rng.randint(1, 4)))
    n = rng.randint(1, MAX_DATA)
    return bytes([A, n] + [rng.randrange(256) for _ in range(n)])


async def stress_chunk(tb: TB, count: int, rng: random.Random, chunk: int) -> None:
    pins = rng.getrandbits(P.num_pins)
    m = Model(P, pins)
    await tb.start(m, pins)
    tb.source.gap_prob = rng.choice([0.0, 0.2, 0.5])
    tb.sink.ready_prob = rng.choice([1.0, 0.7, 0.3])
    sent: list[bytes] = []
    exp = Output()
    origin: list[int] = []  # which sent packet produced each expected packet
    rflx_origin: list[int] = []
    for i in range(count):
        pk = random_packet(rng, m)
        sent.append(pk)
        out = m.feed(pk)
        exp.extend(out)
        origin += [i] * len(out.packets)
        rflx_origin += [i] * len(out.rflx)
    t_start = tb.now_s()
    for pk in sent:
        tb.source.send_nowait(pk)
    await tb.source.wait_idle()
    await tb.sink.wait_count(tb._n_pkt + len(exp.packets), 50e-3)
    await tb.cycles(100)
    elapsed = tb.now_s() - t_start
    # Timers started here never finish (static pads) unless the chunk outlived a timeout.
    assert elapsed < 0.9 * TIMER_TIMEOUT_S, f"stress chunk took {elapsed * 1e3:.1f} ms: too long for the model"
    tb.check_no_errors()
    got = [p.data for p in tb.new_packets()]
    if got != exp.packets:
        k = next((i for i, (a, b) in enumerate(zip(got, exp.packets)) if a != b), min(len(got), len(exp.packets)))
        src = origin[k] if k < len(origin) else (origin[-1] if origin else 0)
        ctx = "; ".join(_hex(s) for s in sent[max(0, src - 4):src + 1])
        raise TBError(
            f"stress seed {tb.seed} chunk {chunk}: packet #{k} differs: expected "
            f"{_hex(exp.packets[k]) if k < len(exp.packets) else '(none)'} got "
            f"{_hex(got[k]) if k < len(got) else '(none)'}; counts {len(exp.packets)}/{len(got)}; "
            f"host packets up to the one responsible: {ctx}"
        )
    rflx = [(i, d) for _, i, d in tb.new_rflx()]
    if rflx != exp.rflx:
        k = next((i for i, (a, b) in enumerate(zip(rflx, exp.rflx)) if a != b), min(len(rflx), len(exp.rflx)))
        src = rflx_origin[min(k, len(rflx_origin) - 1)] if rflx_origin else 0
        raise TBError(f"stress seed {tb.seed} chunk {chunk}: RFLX #{k} differs near host packet "
                      f"{_hex(sent[src])}: expected {exp.rflx[k:k + 3]} got {rflx[k:k + 3]}")
    if tb.new_trans():
        raise TBError("raw_trans fired with static pads")
    tb.check_pins(m)
    tb.check_no_errors()
    tb.log.info("stress chunk %d: %d packets, %d replies, %d strobes, %.2f ms", chunk, count,
                len(got), len(rflx), elapsed * 1e3)


@cocotb.test()
async def test_stress(dut) -> None:
    """Seeded random packets (valid, invalid, foreign, garbage lengths, N > 8, probes) with
    random m_axis_tready and random s_axis_tvalid gaps, static pads, checked byte for byte
    against the model. Replay with BSD_SEED=<seed in the log> (or the run's COCOTB_RANDOM_SEED)."""
    total = int(os.environ.get("BSD_STRESS_PACKETS", "10000"))
    tb = TB(dut, P)
    tb.log.info("stress: %d packets, seed %d (replay: BSD_SEED=%d), params %s", total, tb.seed, tb.seed,
                P.to_json())
    rng = random.Random(tb.seed)
    chunk, done = 0, 0
    while done < total:
        n = min(1000, total - done)
        await stress_chunk(tb, n, rng, chunk)
        done += n
        chunk += 1


# ------------------------------------------------------------------------------ slow build

@cocotb.test()
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


@cocotb.test()
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


@cocotb.test()
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


@cocotb.test()
async def test_timer_timeout(dut) -> None:
    """No completion within 65 535 ticks of the start: result 0 (HOST and RFLX), at the
    right time; the timeout counts from the start in width mode too; a completion just
    before the limit gives its count."""
    need(len(P.timer_pins) >= 2, "two timer pins")
    tb, m = await setup(dut, pins=0)
    tp = [p for p in P.timer_pins if m.is_input(p)]
    runs = {}
    # Edge mode, pad never moves.
    pa = tp[0]
    runs[pa] = await start_timer(tb, m, pa, DEVCODE_HOST | DEVCODE_RFLX, [])
    t_timeout = runs[pa][0] + TIMER_TIMEOUT_S
    await tb.wait_s(50e-6)
    # Width mode: the pulse starts in time but ends after the limit.
    pb = tp[1]
    if not P.is_fixed(pb):
        await configure(tb, m, pb, DIGCFG_IODIR | DIGCFG_TMODE | DIGCFG_TSTATE)
    tg = int(bool(m.cfg[pb] & DIGCFG_TSTATE))
    await set_pins_checked(tb, m, tb.pins & ~(1 << pb) | (1 - tg) << pb)
    runs[pb] = await start_timer(tb, m, pb, DEVCODE_HOST, [(50e-3, tg), (106e-3, 1 - tg)])
    if len(tp) > 2:
        pc = tp[2]
        tgc = int(bool(m.cfg[pc] & DIGCFG_TSTATE))
        await set_pins_checked(tb, m, tb.pins & ~(1 << pc) | (1 - tgc) << pc)
        runs[pc] = await start_timer(tb, m, pc, DEVCODE_HOST, [(TIMER_TIMEOUT_S - 1e-3, tgc)])
    results = await finish_timers(tb, m, runs, margin_s=200e-6)
    assert results[pa] == 0 and results[pb] == 0, results
    # The timeout fires 65 535 ticks after the start (plus the documented few clocks).
    first = next(p for p in tb.packets if len(p.data) == 6 and p.data[3] == P.timer_id(pa))
    late = first.t_first - t_timeout
    assert -TICK_S <= late <= 2 * TICK_S + 40 / P.clk_hz, f"timeout result {late * 1e6:.2f} us off"
    tb.check_no_errors()


@cocotb.test()
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


# ------------------------------------------------------------------------------ heartbeat

@cocotb.test()
async def test_heartbeat(dut) -> None:
    """cmdHB: first heartbeat one period after reset, UP/DOWN alternating; link_up rises on
    the right answer and falls when a heartbeat falls due unanswered; wrong answers and
    other cmdHB packets are silent; a heartbeat due while the previous is unsent is skipped."""
    need(P.hb_rate > 0, "a heartbeat")
    period = P.hb_period_s
    tb, m = await setup(dut, pins=0)
    t_reset = tb.t_reset
    tol = 2 * TICK_S + 20 / P.clk_hz

    async def link_up() -> int:
        await ReadOnly()
        v = int(dut.link_up.value)
        await RisingEdge(dut.clk)
        return v

    async def next_heartbeat(k: int, exp: Output) -> None:
        await tb.until_s(t_reset + k * period + tol)
        got = await tb.expect(exp, what=f"heartbeat {k}")
        late = got[0].t_first - (t_reset + k * period)
        assert abs(late) <= tol, f"heartbeat {k} {late * 1e6:.1f} us off its time"

    assert await link_up() == 0
    await next_heartbeat(1, m.heartbeat_due())  # UP, unanswered
    for data in ([CMD_HB, HB_ANSWER + 1], [CMD_HB], [CMD_HB, 9, 9]):
        await tb.command(m, packet(A, *data))
    assert await link_up() == m.link_up == 0
    await next_heartbeat(2, m.heartbeat_due())  # DOWN
    await tb.command(m, packet(A, CMD_HB, HB_ANSWER + 0))  # answers the previous one: no
    assert await link_up() == m.link_up == 0
    await tb.command(m, packet(A, CMD_HB, HB_ANSWER + 1))
    assert await link_up() == m.link_up == 1
    await next_heartbeat(3, m.heartbeat_due())  # UP; the previous was answered
    assert await link_up() == m.link_up == 1
    await next_heartbeat(4, m.heartbeat_due())  # DOWN; UP never answered
    assert await link_up() == m.link_up == 0
    await tb.command(m, packet(A, CMD_HB, HB_ANSWER + 1, 0, 0))
    assert await link_up() == m.link_up == 1
    # Output stalled across two due times: the second is skipped.
    await tb.until_s(t_reset + 4.5 * period)
    tb.sink.paused = True
    exp = m.heartbeat_due()  # due 5: queued, not sent
    await tb.until_s(t_reset + 6 * period + tol)
    exp.extend(m.heartbeat_skipped())  # due 6: skipped
    assert await link_up() == m.link_up == 0
    tb.sink.paused = False
    await tb.expect(exp, what="stalled heartbeats")
    await next_heartbeat(7, m.heartbeat_due())
    tb.check_no_errors()
