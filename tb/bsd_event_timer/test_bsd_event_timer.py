# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_event_timer, and their pytest entry.

The test drives tick_i itself, so every count is exact. Inputs are driven on the
falling edge of clk; outputs are sampled in ReadOnly() after the rising edge that used
them. Clock numbering: S is the rising edge that samples start_i = 1; clock S+j is the
j-th edge after it. DESIGN.md decision 4: a result is the number of tick_i strobes on
clocks S+1 .. c (edge mode; c = the clock whose level_i is the first non-target ->
target move) or c1+1 .. c2 (width mode; c1 = pulse start, c2 = the first clock back at
non-target), at least 1; 65 535 ticks on clocks S+1 .. without completion is a timeout
(result 0), and a completion on that very clock wins. The result, host_req_o and
rflx_req_o appear right after the completing edge.

Every step() also compares all outputs with TimerModel, a clock-level model of that
text (result_o only once the run has ended: while running it is not meaningful);
directed tests additionally assert explicit numbers computed from the stimulus.
"""

from __future__ import annotations


import cocotb
import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge, Timer

from clocked_tb import ClockedTB
from seeding import make_rng
from suite import Suite, on

SUITE = Suite(__file__, "bsd_event_timer", quick=on("icarus"))

PERIOD_NS = 10
TIMEOUT = 65_535


class TimerModel:
    def __init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        self.running = False
        self.host_req = self.rflx_req = 0
        self.result = 0

    @property
    def busy(self) -> int:
        return int(self.running or self.host_req or self.rflx_req)

    def step(self, v: dict) -> None:
        lvl, tick = v["level_i"], v["tick_i"]
        busy = self.busy
        if v["start_i"] and not busy:
            self.running = True
            self.mode, self.target = v["mode_i"], v["target_i"]
            self.host, self.rflx = v["host_i"], v["rflx_i"]
            self.prev, self.in_pulse, self.elapsed, self.count = lvl, False, 0, 0
        elif self.running:
            to_target = self.prev != self.target and lvl == self.target
            from_target = self.prev == self.target and lvl != self.target
            self.prev = lvl
            self.elapsed += tick
            complete = False
            if self.mode == 0:
                self.count += tick
                complete = to_target
            elif not self.in_pulse:
                if to_target:
                    self.in_pulse, self.count = True, 0
            else:
                self.count += tick
                complete = from_target
            if complete or self.elapsed == TIMEOUT:
                self.running = False
                self.host_req, self.rflx_req = self.host, self.rflx
                self.result = max(self.count, 1) if complete else 0
        if v["host_done_i"]:
            self.host_req = 0
        if v["rflx_done_i"]:
            self.rflx_req = 0

    def outputs(self) -> dict:
        return dict(
            busy_o=self.busy, host_req_o=self.host_req, rflx_req_o=self.rflx_req,
            result_o=self.result,
        )  # fmt: skip


class TimerTB(ClockedTB):
    INPUTS = {k: 0 for k in ("tick_i", "level_i", "start_i", "mode_i", "target_i", "host_i",
                             "rflx_i", "host_done_i", "rflx_done_i")}
    PULSES = ("start_i", "host_done_i", "rflx_done_i")  # back to 0 unless given again
    OUTPUTS = ("busy_o", "host_req_o", "rflx_req_o", "result_o")
    PERIOD_NS = PERIOD_NS

    def __init__(self, dut):
        super().__init__(dut, "event_timer")
        self.model = TimerModel()
        self.edge = 0  # rising edges stepped so far

    def _model(self, rst: int, vals: dict) -> None:
        if rst:
            self.model.reset()
        else:
            self.model.step(vals)

    def _check(self, what: str, got: dict | None = None) -> dict:
        got, exp = got or self.sample(), self.model.outputs()
        if self.model.running:
            # result_o means something only once the measurement has ended.
            exp["result_o"] = got["result_o"]
        assert got == exp, f"edge {self.edge} ({what}): DUT {got} != model {exp}"
        return got

    def check(self, inputs: dict, outputs: dict, rst: int) -> None:
        """Every step: the model takes the same clock and must agree."""
        self.edge += 1
        self._model(rst, inputs)
        self._check(str(inputs), outputs)

    async def skip(self, n: int, **inputs) -> dict:
        """n clocks with constant inputs (no pulses), fast: one Timer, checked at the end."""
        assert n >= 2
        await FallingEdge(self.dut.clk)
        vals = self.drive(0, **inputs)
        assert not any(vals[k] for k in self.PULSES)
        await Timer((n - 1) * PERIOD_NS + PERIOD_NS // 4, unit="ns")
        await RisingEdge(self.dut.clk)
        await ReadOnly()
        self.edge += n
        for _ in range(n):
            self.model.step(vals)
        return self._check(f"after {n} clocks of {vals}")

    async def start(self, mode: int, target: int, host: int = 1, rflx: int = 0,
                    **inputs) -> dict:  # fmt: skip
        out = await self.step(start_i=1, mode_i=mode, target_i=target, host_i=host,
                              rflx_i=rflx, **inputs)  # fmt: skip
        assert out["busy_o"] == 1, "start on an idle timer must make it busy"
        return out


class TickPattern:
    """tick_i for clock j: 1 every `every` clocks, at phase `phase`."""

    def __init__(self, every: int, phase: int) -> None:
        self.every, self.phase, self.j = every, phase, 0

    def next(self) -> int:
        self.j += 1
        return int(self.j % self.every == self.phase)


BOTH = cocotb.parametrize(target=[0, 1])


@SUITE.test()
@BOTH
@cocotb.parametrize(every=[1, 3, 7])
async def test_edge_mode(dut, target, every):
    """Edge mode: ticks on S+1 .. c counted, c = the clock the pin reaches target."""
    tb = TimerTB(dut)
    rng = make_rng(dut, f"edge every={every}")
    await tb.reset()
    for _ in range(4):
        ticks = TickPattern(every, rng.randrange(every))
        d = rng.randrange(1, 60)
        await tb.step(level_i=1 - target, tick_i=ticks.next())
        await tb.start(0, target, level_i=1 - target, tick_i=ticks.next())
        expected = 0
        for j in range(1, d + 1):
            t = ticks.next()
            expected += t
            out = await tb.step(tick_i=t, level_i=target if j == d else 1 - target)
            if j < d:
                assert out["host_req_o"] == 0 and out["busy_o"] == 1
        assert out["host_req_o"] == 1, "no completion on the clock the pin reached target"
        assert out["result_o"] == max(expected, 1), f"result {out['result_o']}, expected {expected}"
        assert out["busy_o"] == 1
        out = await tb.step(host_done_i=1, tick_i=ticks.next())
        assert out["busy_o"] == 0 and out["host_req_o"] == 0


@SUITE.test()
@BOTH
async def test_edge_mode_tick_every_clock_exact(dut, target):
    """With a tick on every clock, a target reached d clocks after the start reads d."""
    tb = TimerTB(dut)
    await tb.reset()
    for d in (1, 2, 5, 100, 1000):
        await tb.start(0, target, level_i=1 - target, tick_i=1)
        if d > 2:
            await tb.skip(d - 1, tick_i=1, level_i=1 - target)
        elif d == 2:
            await tb.step(tick_i=1)
        out = await tb.step(tick_i=1, level_i=target)
        assert (out["host_req_o"], out["result_o"]) == (1, d), f"d={d}: {out}"
        await tb.step(host_done_i=1, level_i=1 - target)


@SUITE.test()
@BOTH
@cocotb.parametrize(every=[1, 4])
async def test_width_mode(dut, target, every):
    """Width mode: waits for non-target -> target (c1), counts ticks c1+1 .. c2."""
    tb = TimerTB(dut)
    rng = make_rng(dut, f"width every={every}")
    await tb.reset()
    for _ in range(4):
        ticks = TickPattern(every, rng.randrange(every))
        await tb.step(level_i=1 - target, tick_i=ticks.next())
        await tb.start(1, target, level_i=1 - target, tick_i=ticks.next())
        for _ in range(rng.randrange(0, 20)):  # waiting for the pulse: no counting
            out = await tb.step(tick_i=ticks.next())
            assert out["host_req_o"] == 0
        out = await tb.step(tick_i=ticks.next(), level_i=target)  # c1: tick here not counted
        assert out["busy_o"] == 1 and out["host_req_o"] == 0
        width = rng.randrange(1, 50)
        expected = 0
        for j in range(1, width + 1):
            t = ticks.next()
            expected += t
            out = await tb.step(tick_i=t, level_i=1 - target if j == width else target)
        assert out["host_req_o"] == 1, "no completion when the pin left target"
        assert out["result_o"] == max(expected, 1), f"result {out['result_o']} != {expected}"
        await tb.step(host_done_i=1, tick_i=ticks.next())


@SUITE.test()
@BOTH
@cocotb.parametrize(mode=[0, 1])
async def test_pin_already_at_target(dut, target, mode):
    """A pin at target when the measurement starts must leave it first: neither the
    present level nor its end (width mode) completes anything."""
    tb = TimerTB(dut)
    await tb.reset()
    await tb.step(level_i=target, tick_i=1)
    await tb.start(mode, target, level_i=target, tick_i=1)
    await tb.steps(10, tick_i=1)  # at target all along
    out = await tb.step(level_i=1 - target, tick_i=1)  # leaves (ends a pulse)
    assert out["host_req_o"] == 0, "already-at-target pin completed on leaving"
    await tb.steps(5, tick_i=1)
    out = await tb.step(level_i=target, tick_i=1)  # clock S+17
    if mode == 0:
        assert (out["host_req_o"], out["result_o"]) == (1, 17), out
    else:
        assert out["host_req_o"] == 0
        await tb.steps(8, tick_i=1)
        out = await tb.step(level_i=1 - target, tick_i=1)
        assert (out["host_req_o"], out["result_o"]) == (1, 9), out


@SUITE.test()
@cocotb.parametrize(mode=[0, 1])
async def test_timeout(dut, mode):
    """65 535 ticks after the start without completion: result 0, exactly on the clock
    of the 65 535th tick (here tick_i = 1 on every clock: clock S+65535)."""
    tb = TimerTB(dut)
    await tb.reset()
    target = 1
    await tb.step(level_i=0, tick_i=1)
    await tb.start(mode, target, level_i=0, tick_i=1)
    if mode == 1:  # a pulse begins but never ends
        await tb.step(level_i=1, tick_i=1)
        done = 1
    else:
        done = 0
    await tb.skip(TIMEOUT - 3 - done, tick_i=1)  # up to clock S+65532
    for j in range(TIMEOUT - 2, TIMEOUT):
        out = await tb.step(tick_i=1)
        assert out["host_req_o"] == 0, f"timed out early, at clock S+{j}"
    out = await tb.step(tick_i=1)
    assert (out["host_req_o"], out["result_o"]) == (1, 0), f"at S+65535: {out}"
    # The timeout counts ticks, not clocks: 70 000 clocks without a tick do nothing;
    # then 65 500 ticks on consecutive clocks and 35 more, one every 3rd clock.
    await tb.step(host_done_i=1, level_i=0)
    await tb.start(0, target, level_i=0, tick_i=0)
    out = await tb.skip(70_000, tick_i=0)
    assert out["busy_o"] == 1 and out["host_req_o"] == 0
    out = await tb.skip(65_500, tick_i=1)
    assert out["busy_o"] == 1 and out["host_req_o"] == 0
    ticks = TickPattern(3, 0)
    counted = 65_500
    while counted < TIMEOUT:
        t = ticks.next()
        out = await tb.step(tick_i=t)
        counted += t
        assert out["host_req_o"] == int(counted == TIMEOUT), f"{counted} ticks: {out}"
    assert out["result_o"] == 0


@SUITE.test()
@cocotb.parametrize(mode=[0, 1])
@cocotb.parametrize(offset=[0, 1])
async def test_completion_on_timeout_clock(dut, mode, offset):
    """Completion on the timeout clock itself wins (DESIGN.md decision 4); one clock
    later is a timeout (result 0)."""
    tb = TimerTB(dut)
    await tb.reset()
    # tick on every clock; the completing edge lands on clock S+65535+offset
    await tb.step(level_i=0, tick_i=1)
    await tb.start(mode, 1, level_i=0, tick_i=1)
    if mode == 1:
        # pulse begins at S+1; its end at S+65535+offset
        await tb.step(level_i=1, tick_i=1)
        await tb.skip(TIMEOUT - 2 + offset, tick_i=1, level_i=1)
        out = await tb.step(level_i=0, tick_i=1)
        exp = (1, TIMEOUT - 1) if offset == 0 else None
    else:
        await tb.skip(TIMEOUT - 1 + offset, tick_i=1, level_i=0)
        out = await tb.step(level_i=1, tick_i=1)
        exp = (1, TIMEOUT) if offset == 0 else None
    if exp is None:
        assert out["host_req_o"] == 1 and out["result_o"] == 0 and tb.model.result == 0
    else:
        assert (out["host_req_o"], out["result_o"]) == exp, out


@SUITE.test()
@cocotb.parametrize(mode=[0, 1])
async def test_zero_ticks_reports_one(dut, mode):
    """A completion with no tick counted reports 1, never 0."""
    tb = TimerTB(dut)
    await tb.reset()
    await tb.step(level_i=0)
    await tb.start(mode, 1, level_i=0, tick_i=0)
    if mode == 0:
        out = await tb.step(level_i=1, tick_i=0)
    else:
        await tb.step(level_i=1, tick_i=1)  # tick on the pulse-begin clock: not counted
        await tb.steps(3, tick_i=0)
        out = await tb.step(level_i=0, tick_i=0)
    assert (out["host_req_o"], out["result_o"]) == (1, 1), out
    # and the very next clock after the start, with a tick there: 1 as well
    await tb.step(host_done_i=1, level_i=0)
    if mode == 0:
        await tb.start(0, 1, level_i=0, tick_i=1)  # tick on S: not counted
        out = await tb.step(level_i=1, tick_i=0)
        assert (out["host_req_o"], out["result_o"]) == (1, 1), out


@SUITE.test()
@cocotb.parametrize(host=[0, 1], rflx=[0, 1])
async def test_busy_until_delivered(dut, host, rflx):
    """busy_o stays high after completion until every requested delivery is done;
    with neither requested it drops on the completing clock."""
    tb = TimerTB(dut)
    rng = make_rng(dut, f"busy host={host} rflx={rflx}")
    await tb.reset()
    for order in ("host_first", "rflx_first", "same_clock"):
        await tb.step(level_i=0)
        await tb.start(0, 1, host=host, rflx=rflx, level_i=0, tick_i=1)
        await tb.steps(3)
        out = await tb.step(level_i=1)
        assert (out["host_req_o"], out["rflx_req_o"]) == (host, rflx), out
        assert out["result_o"] == 4
        assert out["busy_o"] == int(host or rflx)
        # busy holds for a while with no done pulse
        for o in await tb.steps(rng.randrange(1, 10)):
            assert o["busy_o"] == int(host or rflx)
        if host or rflx:  # a start now is ignored (result and requests unchanged)
            o = await tb.step(start_i=1, host_i=1 - host, rflx_i=1 - rflx, level_i=0)
            assert (o["host_req_o"], o["rflx_req_o"], o["result_o"]) == (host, rflx, 4)
            assert o["busy_o"] == 1
        if order == "same_clock":
            o = await tb.step(host_done_i=host, rflx_done_i=rflx)
            assert o["busy_o"] == 0
        else:
            first, second = ("host", "rflx") if order == "host_first" else ("rflx", "host")
            want = {"host": host, "rflx": rflx}
            o = await tb.step(**{f"{first}_done_i": want[first]})
            assert o[f"{first}_req_o"] == 0
            assert o["busy_o"] == want[second], f"busy after {first} done: {o}"
            for o in await tb.steps(3):
                assert o["busy_o"] == want[second]
            o = await tb.step(**{f"{second}_done_i": want[second]})
            assert o["busy_o"] == 0
        assert o["result_o"] == 4, "result must stay after delivery"


@SUITE.test()
@cocotb.parametrize(mode=[0, 1])
async def test_start_while_busy_ignored(dut, mode):
    """A start while running keeps the running measurement (its mode, target, start)."""
    tb = TimerTB(dut)
    await tb.reset()
    await tb.step(level_i=0, tick_i=1)
    await tb.start(mode, 1, host=1, level_i=0, tick_i=1)
    await tb.steps(5)
    # restart attempt with the other mode and target, and a level that would
    # complete the attempted edge-mode/target-0 run
    await tb.step(start_i=1, mode_i=1 - mode, target_i=0, host_i=0, rflx_i=1, level_i=0)
    await tb.steps(3)
    out = await tb.step(level_i=1)  # S+10: completes an edge run; begins a width run
    if mode == 0:
        assert (out["host_req_o"], out["rflx_req_o"], out["result_o"]) == (1, 0, 10), out
    else:
        assert out["busy_o"] == 1 and out["host_req_o"] == 0
        await tb.steps(6)
        out = await tb.step(level_i=0)
        assert (out["host_req_o"], out["rflx_req_o"], out["result_o"]) == (1, 0, 7), out


@SUITE.test()
async def test_reset_during_run(dut):
    tb = TimerTB(dut)
    await tb.reset()
    for mode in (0, 1):
        await tb.step(level_i=0, tick_i=1)
        await tb.start(mode, 1, host=1, rflx=1, level_i=0, tick_i=1)
        await tb.steps(5, level_i=mode)  # width: pulse under way
        await tb.step(rst=1)
        out = await tb.step(rst=1)
        assert out == dict(busy_o=0, host_req_o=0, rflx_req_o=0, result_o=0), out
        # the abandoned run completes nothing
        for o in await tb.steps(5, level_i=1 - mode) + await tb.steps(5, level_i=mode):
            assert o["busy_o"] == 0 and o["host_req_o"] == 0
    # reset while a result waits for delivery drops it; a new start works
    await tb.step(level_i=0)
    await tb.start(0, 1, host=1, level_i=0)
    out = await tb.step(level_i=1)
    assert out["host_req_o"] == 1
    await tb.reset()
    await tb.step(level_i=0)
    await tb.start(0, 1, host=0, rflx=1, level_i=0)
    await tb.steps(2)
    out = await tb.step(level_i=1)
    assert (out["rflx_req_o"], out["result_o"]) == (1, 3), out


@SUITE.test()
async def test_random_vs_model(dut):
    """Random level waveform, ticks, starts (also while busy), done pulses and resets,
    every output compared with TimerModel on every clock."""
    tb = TimerTB(dut)
    rng = make_rng(dut, "event_timer random")
    await tb.reset()
    completions = 0
    for _ in range(10):
        p_tick = rng.choice([1.0, 0.5, 0.1])
        p_lvl = rng.choice([0.02, 0.1, 0.4])
        p_start = rng.choice([0.02, 0.2])
        p_done = rng.choice([0.05, 0.3])
        for _ in range(600):
            kw = dict(
                tick_i=int(rng.random() < p_tick),
                level_i=tb.cur["level_i"] ^ int(rng.random() < p_lvl),
                start_i=int(rng.random() < p_start),
                mode_i=rng.randrange(2), target_i=rng.randrange(2),
                host_i=rng.randrange(2), rflx_i=rng.randrange(2),
                # done only for a pending request, as the top gives it
                host_done_i=int(tb.model.host_req and rng.random() < p_done),
                rflx_done_i=int(tb.model.rflx_req and rng.random() < p_done),
            )  # fmt: skip
            was_running = tb.model.running
            await tb.step(rst=int(rng.random() < 0.002), **kw)
            completions += int(was_running and not tb.model.running)
    dut._log.info("random: %d completions", completions)
    assert completions > 30, "random stimulus too weak"


@pytest.mark.parametrize("case", SUITE.cases())
def test_bsd_event_timer(case) -> None:
    SUITE.run(case)
