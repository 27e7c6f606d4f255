"""Event timer accuracy (PROTOCOL.md §4.2): seeded random edge intervals and pulse widths,
several timers running at once, every result checked against the true interval.

The bound: a result counts the tick strobes between the timer's two reference clocks, so it
is within one tick of the reference span; each reference lags its event by a fixed number
of clocks (docs/DESIGN.md, "Latencies"): the start by 2 clocks after the last byte's
handshake, an edge by 2 to 3 clocks (synchronizer + edge detection). So
|result - true / 1.6 us| < 1 tick + 1 clock in both modes (the allowance below keeps one
more clock of margin for the edge mode).
"""

from __future__ import annotations

import math
import os

import cocotb

import figures
from bsd_model import (
    CMD_DIG_CFG,
    CMD_PTIME_RD,
    DEVCODE_HOST,
    DIGCFG_IODIR,
    DIGCFG_TMODE,
    DIGCFG_TSTATE,
    TICK_HZ,
    TIMER_TIMEOUT_S,
    Model,
    Params,
    packet,
)
from bsd_tb import TB, TBError

# Reference lag difference in clocks (see the module docstring).
LAG_CLOCKS = {False: 2, True: 1}


def _count() -> int:
    return int(os.environ.get("BSD_TIMER_COUNT", "40"))


def _max_interval_s() -> float:
    return float(os.environ.get("BSD_TIMER_MAX_S", "2e-3"))


class TimerJob:
    """One measurement: pin, mode, target and the pad waveform relative to its start."""

    def __init__(self, rng, pin: int, max_s: float) -> None:
        self.pin = pin
        self.width = rng.random() < 0.5
        self.target = rng.randint(0, 1)
        # Log-uniform from a few microseconds to max_s.
        self.interval = math.exp(rng.uniform(math.log(4e-6), math.log(max_s)))
        # Edge mode: sometimes the pad starts at target and must leave it first.
        self.starts_at_target = not self.width and rng.random() < 0.25
        self.lead = rng.uniform(3e-6, 40e-6)  # width: time to the pulse; edge: to leaving target
        if self.width:
            self.interval = min(self.interval, TIMER_TIMEOUT_S - self.lead - 100e-6)
        self.start_s = 0.0

    @property
    def cfg(self) -> int:
        return (DIGCFG_IODIR | (DIGCFG_TMODE if self.width else 0)
                | (DIGCFG_TSTATE if self.target else 0))

    @property
    def initial_level(self) -> int:
        return self.target if self.starts_at_target else 1 - self.target

    def waveform(self) -> list[tuple[float, int]]:
        """Pad changes in absolute core seconds, and the true interval they define."""
        t0, tgt, non = self.start_s, self.target, 1 - self.target
        if self.width:
            return [(t0 + self.lead, tgt), (t0 + self.lead + self.interval, non)]
        if self.starts_at_target:
            # Leave the target well before the edge that ends the measurement.
            leave = min(self.lead, self.interval / 2)
            return [(t0 + leave, non), (t0 + self.interval, tgt)]
        return [(t0 + self.interval, tgt)]


@cocotb.test()
async def random_intervals(dut):
    """Random edge intervals and widths on every timer pin at once, in batches."""
    p = Params.from_env()
    tb = TB(dut, p)
    count, max_s = _count(), _max_interval_s()
    tb.log.info("seed %d: %d intervals up to %.3f ms at %.3f MHz", tb.seed, count, max_s * 1e3,
                p.clk_hz / 1e6)
    await tb.start(Model(p))
    a = p.module_addr
    worst = 0.0        # |result - true ticks|
    worst_net = 0.0    # the same less the documented latency allowance
    done = 0
    while done < count:
        jobs = [TimerJob(tb.rng, pin, max_s) for pin in p.timer_pins][: count - done]
        for job in jobs:
            tb.set_pin(job.pin, job.initial_level)
            await tb.source.send(packet(a, CMD_DIG_CFG, job.pin, job.cfg))
        await tb.cycles(4)  # the synchronizer sees the initial levels
        drivers = []
        for job in jobs:
            times = await tb.source.send(packet(a, CMD_PTIME_RD, DEVCODE_HOST | job.pin))
            job.start_s = times[-1]
            drivers.append(tb.drive_waveform(job.pin, job.waveform()))
        longest = max(j.start_s + (j.lead if j.width else 0) + j.interval for j in jobs)
        if not await tb.wait_new_packets(len(jobs), longest - tb.now_s() + 1e-3):
            raise TBError(f"missing timer results: {[pk.data.hex() for pk in tb.new_packets()]}")
        await tb.cycles(20)
        got = {pk.data[3] - p.timer_id_base: pk.data for pk in tb.new_packets()}
        if len(got) != len(jobs):
            raise TBError(f"expected {len(jobs)} results, got {list(got.values())}")
        for job in jobs:
            pk = got.get(job.pin)
            if pk is None or pk[:4] != bytes([a, 4, 4, p.timer_id(job.pin)]):
                raise TBError(f"pin {job.pin}: bad or missing result packet {pk!r}")
            result = pk[4] << 8 | pk[5]
            exact = job.interval * TICK_HZ
            err = result - exact
            allowance = 1 + LAG_CLOCKS[job.width] * TICK_HZ / p.clk_hz
            tb.log.debug("pin %d %s tgt %d: %.2f us -> %d ticks (%.3f)", job.pin,
                         "width" if job.width else "edge", job.target, job.interval * 1e6, result,
                         err)
            if result == 0 or abs(err) >= allowance:
                raise TBError(
                    f"pin {job.pin} {'width' if job.width else 'edge'} target {job.target}: "
                    f"true {job.interval * 1e6:.3f} us = {exact:.3f} ticks, result {result} "
                    f"(error {err:+.3f}, allowed < {allowance:.3f})")
            worst = max(worst, abs(err))
            worst_net = max(worst_net, abs(err) - (allowance - 1))
        for d in drivers:
            await d
        done += len(jobs)
    tb.check_no_errors()
    tb.log.info("%d intervals at %.3f MHz: worst error %.3f ticks (%.3f ticks less the fixed "
                "latency allowance)", done, p.clk_hz / 1e6, worst, worst_net)
    figures.record(
        f"timer_accuracy-{cocotb.SIM_NAME.split()[0]}-{p.clk_hz}",
        f"timer accuracy, {cocotb.SIM_NAME.split()[0]:9s} {p.clk_hz / 1e6:6.2f} MHz: "
        f"{done} intervals (seed {tb.seed}), worst |error| {worst:.3f} ticks, "
        f"{worst_net:.3f} ticks less the fixed latency allowance")


@cocotb.test()
async def timeout_reports_zero(dut):
    """An edge that never comes: result 0, 65 535 ticks after the start (± a tick)."""
    p = Params.from_env()
    tb = TB(dut, p)
    await tb.start(Model(p))
    a = p.module_addr
    pin = p.timer_pins[-1]
    tb.set_pin(pin, 0)
    await tb.source.send(packet(a, CMD_DIG_CFG, pin, DIGCFG_IODIR | DIGCFG_TSTATE))
    times = await tb.source.send(packet(a, CMD_PTIME_RD, DEVCODE_HOST | pin))
    if not await tb.wait_new_packets(1, TIMER_TIMEOUT_S + 2e-3):
        raise TBError("no timeout result")
    pk = tb.new_packets()[0]
    if pk.data != packet(a, 4, p.timer_id(pin), 0, 0):
        raise TBError(f"timeout result {pk.data.hex()}")
    late = (pk.t_first - times[-1]) * TICK_HZ - 65_535
    # The result leaves a few clocks after the timeout clock.
    if not -1 <= late <= 1 + 10 * TICK_HZ / p.clk_hz:
        raise TBError(f"timeout came {late:+.3f} ticks off 65 535")
    tb.log.info("timeout after 65 535 %+.3f ticks", late)
