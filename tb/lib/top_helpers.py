# SPDX-License-Identifier: Apache-2.0
"""Steps shared by the top-level tests of brainstem_dio (tb/brainstem_dio/): set-up with a
checked reset, pad changes checked against the model, timer runs and their results.

`P` is the parameter set the simulation was built with (runner.hdl_params()); each test
names the builds it needs (`@cocotb.test(skip=not runner.on(...))`), and `need` fails loudly if one runs anyway on a
build that lacks what it needs.
"""

from __future__ import annotations

from bsd_model import (
    CMD_DEV_VAL,
    CMD_DIG_CFG,
    CMD_PTIME_RD,
    DEVCODE_HOST,
    DEVCODE_RFLX,
    TICK_HZ,
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
from bsd_tb import TB, TBError, hex_bytes

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
        raise TBError(f"this build lacks {what}: the test names a build it cannot run on")


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
        for pk in tb.peek_packets():
            d = pk.data
            if len(d) == 6 and d[2] == CMD_DEV_VAL and d[3] == tid:
                return d[4] << 8 | d[5]
    if run.rflx:
        for _, i, v in tb.peek_rflx():
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
    await tb.expect(exp, settle_cycles=4, what=hex_bytes(pkt))
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
