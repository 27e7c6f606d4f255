# SPDX-License-Identifier: Apache-2.0
"""Base class of the block testbenches: one clock, a synchronous reset, one-clock steps.

Sampling discipline (reading right after a rising edge races with the design's update):
inputs are driven on the falling edge of `clk`; outputs are sampled in ReadOnly() right
after the rising edge that used those inputs. So `await tb.step(a_i=1)` returns what the
block shows after the clock that saw a_i = 1.
"""

from __future__ import annotations

import random
from typing import Mapping

from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from seeding import make_rng


class ClockedTB:
    """Subclasses name their inputs (with idle values), outputs and one-clock inputs, and
    may override `check(inputs, outputs, rst)` to compare every step with a model."""

    INPUTS: Mapping[str, int] = {}   # input port -> value it has until a step sets it
    PULSES: tuple[str, ...] = ()     # inputs that go back to 0 unless a step sets them
    OUTPUTS: tuple[str, ...] = ()    # ports that step() samples
    PERIOD_NS = 10

    def __init__(self, dut, name: str = "tb") -> None:
        self.dut = dut
        self.log = dut._log
        self.clk = dut.clk
        self.rng: random.Random = make_rng(dut, name)
        self.cur: dict[str, int] = dict(self.INPUTS)
        self.has_rst = hasattr(dut, "rst")  # a synchronizer has none
        if self.has_rst:
            dut.rst.value = 1
        for k, v in self.cur.items():
            getattr(dut, k).value = v
        Clock(dut.clk, self.PERIOD_NS, unit="ns", impl="gpi").start(start_high=False)

    def drive(self, rst: int = 0, **inputs: int) -> dict[str, int]:
        """Put `inputs` (the others keep their value, pulses go to 0) on the ports now."""
        vals = dict(self.cur, **{p: 0 for p in self.PULSES})
        vals.update(inputs)
        self.cur = vals
        if self.has_rst:
            self.dut.rst.value = rst
        for k, v in vals.items():
            getattr(self.dut, k).value = int(v)
        return vals

    def sample(self) -> dict[str, int]:
        return {k: int(getattr(self.dut, k).value) for k in self.OUTPUTS}

    def check(self, inputs: Mapping[str, int], outputs: Mapping[str, int], rst: int) -> None:
        """Compare one clock with a model; the default checks nothing."""

    async def step(self, rst: int = 0, **inputs: int) -> dict[str, int]:
        """One clock: drive on the falling edge, sample after the rising edge, check."""
        await FallingEdge(self.clk)
        vals = self.drive(rst, **inputs)
        await RisingEdge(self.clk)
        await ReadOnly()
        out = self.sample()
        self.check(vals, out, rst)
        return out

    async def steps(self, n: int, **inputs: int) -> list[dict[str, int]]:
        return [await self.step(**inputs) for _ in range(n)]

    async def reset(self, cycles: int = 2) -> None:
        """`cycles` clocks with rst high; rst drops at the next step()."""
        for _ in range(cycles):
            await self.step(rst=1)
