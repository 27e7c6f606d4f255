# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_heartbeat, and their pytest entry.

Checked against PROTOCOL.md §3 (cmdHB: with HB_RATE != 0 an UP and a DOWN heartbeat
alternately, one every HB_RATE x 25.6 ms = HB_RATE x HB_UNIT_TICKS ticks, the first one
period after reset; link_up from an answer to the latest heartbeat until one falls due while
the previous is unanswered; 0 after reset and with HB_RATE = 0; a heartbeat due while the
previous is not yet sent is skipped) and DESIGN.md decision 8 (the answer must be the latest
heartbeat's type + 2; a skipped heartbeat does not toggle the type and counts as unanswered).

The TB drives tick_i itself. HbModel counts ticks: the heartbeat falls due on the
PERIOD-th tick after reset or after the previous due one; req_o/type_o/link_up_o are
compared after every clock. Long spans go by in one Timer (HbTB.skip) with the model
stepped as many clocks.
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge, Timer

from bsd_protocol import HB_DOWN, HB_UNIT_TICKS, HB_UP
from clocked_tb import ClockedTB
import runner
from runner import hdl_params

BUILDS = {"hb0": {"HB_RATE": 0}, "hb1": {"HB_RATE": 1},
                                           "hb3": {"HB_RATE": 3}}


class HbModel:
    def __init__(self, rate: int) -> None:
        self.period = rate * HB_UNIT_TICKS
        self.due_count = self.skipped = 0  # statistics over the whole test (kept by reset)
        self.reset()

    def reset(self) -> None:
        self.ticks = 0           # ticks since reset or the last due heartbeat
        self.latest: int | None = None  # type of the latest queued heartbeat
        self.answered = False
        self.req = False
        self.link_up = False

    def step(self, v: dict) -> None:
        due = False
        if self.period and v["tick_i"]:
            self.ticks += 1
            if self.ticks == self.period:
                due, self.ticks = True, 0
        answer_type = HB_DOWN if v["answer_down_i"] else HB_UP
        answer = bool(v["answer_i"]) and self.latest is not None and answer_type == self.latest
        unsent = self.req          # as the clock starts: not yet sent
        if v["done_i"]:
            self.req = False
        if answer:
            self.answered = self.link_up = True
        if due:
            self.due_count += 1
            if not self.answered or unsent:
                self.link_up = False
            if unsent:
                self.skipped += 1
            else:
                self.req = True
                self.latest = HB_UP if self.latest is None else (HB_UP + HB_DOWN) - self.latest
                self.answered = False

    def outputs(self) -> dict[str, int]:
        return dict(req_o=int(self.req), link_up_o=int(self.link_up),
                    type_o=self.latest if self.latest is not None else HB_UP)

    def to_due(self) -> int:
        """Ticks until the next heartbeat falls due."""
        return self.period - self.ticks


class HbTB(ClockedTB):
    INPUTS = dict(tick_i=0, answer_i=0, answer_down_i=0, done_i=0)
    PULSES = ("answer_i", "done_i")
    OUTPUTS = ("req_o", "type_o", "link_up_o")

    def __init__(self, dut) -> None:
        super().__init__(dut, "heartbeat")
        self.rate = int(hdl_params()["HB_RATE"])
        self.model = HbModel(self.rate)
        self.clocks = 0

    def check(self, inputs, outputs, rst) -> None:
        self.clocks += 1
        if rst:
            self.model.reset()
        else:
            self.model.step(inputs)
        exp = self.model.outputs()
        if not self.model.req and self.model.latest is None:
            exp["type_o"] = outputs["type_o"]  # no heartbeat yet: type means nothing
        assert dict(outputs) == exp, f"clock {self.clocks} {inputs}: DUT {outputs} != model {exp}"

    async def skip(self, n: int, **inputs: int) -> dict[str, int]:
        """n clocks with constant inputs (no pulses) in one Timer, checked at the end."""
        assert n >= 2
        await FallingEdge(self.clk)
        vals = self.drive(0, **inputs)
        await Timer((n - 1) * self.PERIOD_NS + self.PERIOD_NS // 4, unit="ns")
        await RisingEdge(self.clk)
        await ReadOnly()
        out = self.sample()
        for _ in range(n - 1):
            self.model.step(vals)
            self.clocks += 1
        self.check(vals, out, 0)
        return out

    async def to_due(self, before: int = 0) -> dict[str, int]:
        """Tick every clock until `before` ticks before the next due heartbeat."""
        n = self.model.to_due() - before
        if n >= 2:
            return await self.skip(n, tick_i=1)
        out = {}
        for _ in range(n):
            out = await self.step(tick_i=1)
        return out

    async def answer(self, typ: int, **kw: int) -> dict[str, int]:
        return await self.step(answer_i=1, answer_down_i=int(typ == HB_DOWN), **kw)


@cocotb.test(skip=not runner.on("hb1", "hb3"))
async def test_period_and_alternation(dut) -> None:
    """The first heartbeat one period (HB_RATE x 16 000 ticks) after reset, on that very
    tick and not before; then UP, DOWN, UP ... each a period later; ticks, not clocks, count."""
    tb = HbTB(dut)
    await tb.reset()
    period = tb.rate * HB_UNIT_TICKS
    out = await tb.to_due(1)
    assert out["req_o"] == 0
    out = await tb.step(tick_i=0)            # a clock without a tick: still not due
    assert out["req_o"] == 0
    out = await tb.step(tick_i=1)            # the period-th tick
    assert (out["req_o"], out["type_o"]) == (1, HB_UP)
    out = await tb.step(tick_i=0, done_i=1)
    assert out["req_o"] == 0
    for want in (HB_DOWN, HB_UP, HB_DOWN):
        # ticks every 2nd clock for part of the period: the period is in ticks
        for _ in range(20):
            await tb.step(tick_i=1)
            await tb.step(tick_i=0)
        out = await tb.to_due(1)
        assert out["req_o"] == 0
        out = await tb.step(tick_i=1)
        assert (out["req_o"], out["type_o"]) == (1, want), f"expected type {want}: {out}"
        await tb.step(done_i=1)
    assert tb.model.due_count == 4 and period == tb.model.period


@cocotb.test(skip=not runner.on("hb1"))
async def test_link_up_rules(dut) -> None:
    """link_up: 0 after reset; 1 from an answer of the latest heartbeat's type; an answer of
    the other type, or before any heartbeat, does nothing; 0 when a heartbeat falls due while
    the previous is unanswered; stays 1 while every heartbeat is answered in time."""
    tb = HbTB(dut)
    await tb.reset()
    out = await tb.answer(HB_UP)             # no heartbeat yet
    assert out["link_up_o"] == 0
    await tb.to_due()                        # UP due
    await tb.step(done_i=1)
    out = await tb.answer(HB_DOWN)           # wrong type
    assert out["link_up_o"] == 0
    out = await tb.answer(HB_UP)
    assert out["link_up_o"] == 1
    for typ in (HB_DOWN, HB_UP):
        out = await tb.to_due()
        assert out["link_up_o"] == 1 and out["type_o"] == typ, "answered in time: link stays up"
        await tb.step(done_i=1)
        out = await tb.answer(typ)
        assert out["link_up_o"] == 1
    out = await tb.to_due()                  # DOWN due, UP was answered
    await tb.step(done_i=1)
    assert out["link_up_o"] == 1
    out = await tb.to_due()                  # UP due, DOWN unanswered
    assert out["link_up_o"] == 0
    await tb.step(done_i=1)
    out = await tb.answer(HB_DOWN)           # the old one: too late
    assert out["link_up_o"] == 0
    out = await tb.answer(HB_UP)
    assert out["link_up_o"] == 1
    # an answer on the very clock the next heartbeat falls due still counts for the old one
    out = await tb.to_due(1)
    out = await tb.answer(HB_UP, tick_i=1)
    assert out["req_o"] == 1 and out["link_up_o"] == 1
    # reset drops it
    await tb.reset(1)
    assert (await tb.step())["link_up_o"] == 0


@cocotb.test(skip=not runner.on("hb1", "hb3"))
async def test_skip_when_unsent(dut) -> None:
    """A heartbeat that falls due while the previous one still waits (no done) is skipped:
    no second request, no type toggle, link_up goes to 0 even if answered."""
    tb = HbTB(dut)
    await tb.reset()
    await tb.to_due()                        # UP queued, never sent
    out = await tb.answer(HB_UP)             # (answered early, at block level)
    assert out["link_up_o"] == 1
    out = await tb.to_due()                  # due while UP still waits
    assert (out["req_o"], out["type_o"], out["link_up_o"]) == (1, HB_UP, 0)
    assert tb.model.skipped == 1
    out = await tb.step(done_i=1)            # UP finally leaves
    assert out["req_o"] == 0
    out = await tb.to_due()                  # next one: DOWN (the skipped one did not toggle)
    assert (out["req_o"], out["type_o"]) == (1, HB_DOWN)
    # done on the clock the next one falls due: that one is still skipped
    out = await tb.to_due(1)
    out = await tb.step(tick_i=1, done_i=1)
    assert out["req_o"] == 0 and tb.model.skipped == 2
    out = await tb.to_due()
    assert (out["req_o"], out["type_o"]) == (1, HB_UP)


@cocotb.test(skip=not runner.on("hb0"))
async def test_rate_zero(dut) -> None:
    """HB_RATE = 0: no heartbeat ever, link_up stays 0 whatever the answers."""
    tb = HbTB(dut)
    await tb.reset()
    for _ in range(3):
        out = await tb.skip(40_000, tick_i=1)
        assert out["req_o"] == 0 and out["link_up_o"] == 0
        for typ in (HB_UP, HB_DOWN):
            out = await tb.answer(typ, tick_i=1)
            assert out["link_up_o"] == 0


@cocotb.test()
async def test_random_vs_model(dut) -> None:
    """Around many due heartbeats: random ticks, answers of either type, done pulses (only
    while a heartbeat waits) and rare resets, the model checked on every clock; the long
    spans between go by with a Timer."""
    tb = HbTB(dut)
    rng = tb.rng
    await tb.reset()
    for _ in range(12):
        if tb.rate:
            await tb.to_due(rng.randrange(5, 40))
        else:
            await tb.skip(rng.randrange(100, 1000), tick_i=1)
        p_tick = rng.choice([1.0, 0.5])
        p_ans = rng.choice([0.05, 0.3])
        for _ in range(rng.randrange(60, 200)):
            await tb.step(rst=int(rng.random() < 0.003), tick_i=int(rng.random() < p_tick),
                          answer_i=int(rng.random() < p_ans), answer_down_i=rng.randrange(2),
                          done_i=int(tb.model.req and rng.random() < 0.3))
    if tb.rate:
        assert tb.model.due_count >= 6


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_heartbeat(sim: str, build: str) -> None:
    runner.run(sim, "bsd_heartbeat", __file__, BUILDS[build], build)
