# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_sync (the two-flop pad synchronizer), and their pytest entry.

docs/DESIGN.md "Latencies": a pad level is seen 2 clocks later. Checked against a two-stage
shift register model on every clock, with levels driven on the falling edge and, in a second
test, at random instants between edges (the synchronizer's real use: pads are asynchronous).
"""

from __future__ import annotations

from collections import deque

import cocotb
import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge, Timer

from clocked_tb import ClockedTB
import runner
from runner import hdl_params

BUILDS = {"w1": {"WIDTH": 1}, "w7": {"WIDTH": 7}}


class SyncTB(ClockedTB):
    INPUTS = {"d_i": 0}
    OUTPUTS = ("q_o",)

    def __init__(self, dut) -> None:
        super().__init__(dut, "sync")
        self.width = int(hdl_params()["WIDTH"])
        # A level driven before edge k is in the first flop after edge k and on q_o after
        # edge k + 1: two clocks. Unknown until then (no reset).
        self.pipe: deque[int | None] = deque([None])

    def sample(self) -> dict:
        v = self.dut.q_o.value  # X until two clocks have passed (no reset: Icarus shows it)
        return {"q_o": int(v) if v.is_resolvable else None}

    def check(self, inputs, outputs, rst) -> None:
        self.pipe.append(inputs["d_i"])
        want = self.pipe.popleft()
        if want is not None:
            assert outputs["q_o"] == want, f"q_o {outputs['q_o']:#x}, expected {want:#x} (2 clocks late)"


@cocotb.test()
async def test_two_clock_latency(dut) -> None:
    """Random levels every clock: q_o shows each level from the second edge after it."""
    tb = SyncTB(dut)
    for _ in range(300):
        await tb.step(d_i=tb.rng.getrandbits(tb.width))


@cocotb.test()
async def test_asynchronous_changes(dut) -> None:
    """A level that changes at any instant within a clock is on q_o from the second rising
    edge after the change, and the old level until then."""
    tb = SyncTB(dut)
    await tb.steps(3)
    period = tb.PERIOD_NS * 1000  # ps
    prev = tb.cur["d_i"]
    for _ in range(100):
        value = tb.rng.getrandbits(tb.width)
        await RisingEdge(tb.clk)
        await Timer(tb.rng.randrange(1, period), unit="ps")
        dut.d_i.value = value
        seen = []
        for _ in range(4):
            await RisingEdge(tb.clk)
            await ReadOnly()
            seen.append(int(dut.q_o.value))
        assert seen == [prev, value, value, value], f"{prev:#x} -> {value:#x}: q_o {seen}"
        prev = value
        await FallingEdge(tb.clk)


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_sync(sim: str, build: str) -> None:
    runner.run(sim, "bsd_sync", __file__, BUILDS[build], build)
