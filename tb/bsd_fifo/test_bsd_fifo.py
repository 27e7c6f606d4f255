# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_fifo (small, so full and empty come often, and at a power of two) against
a bounded queue of DEPTH + 1 words (the RAM and the output register), and their pytest entry.

Inputs are driven on the falling edge; every clock, right before the rising edge
(ReadOnly), the test records which handshakes happen at that edge. It also checks that
s_axis_tready and m_axis_tvalid come from flops: changing the other side's inputs in the
middle of a clock must not move them (tb/lib/stream_check.py).
"""

from __future__ import annotations

import pytest
from cocotb.triggers import ReadOnly

import stream_check
from runner import hdl_params
from suite import Suite, on

SUITE = Suite(__file__, "bsd_fifo", {"d2": {"WIDTH": 8, "DEPTH": 2}, "d16": {"WIDTH": 8, "DEPTH": 16}}, quick=on("icarus"))


def make_tb(dut) -> stream_check.StreamTB:
    p = hdl_params()
    return stream_check.StreamTB(dut, int(p["WIDTH"]), int(p["DEPTH"]) + 1)


@SUITE.test()
async def test_random_traffic(dut) -> None:
    """Every word comes out once, in order, never more inside than the capacity."""
    await stream_check.random_traffic(make_tb(dut))


@SUITE.test()
async def test_full_rate_and_capacity(dut) -> None:
    """One word a clock at full rate; exactly the capacity taken while stalled."""
    await stream_check.full_rate_and_capacity(make_tb(dut))

@SUITE.test()
async def test_fifo_empty_flag(dut) -> None:
    """empty_o is 1 exactly when no word is inside (the RAM and the output register)."""
    tb = make_tb(dut)
    rng, WIDTH = tb.rng, tb.width
    await tb.reset()
    for _ in range(600):
        await tb.step(int(rng.random() < 0.4), rng.randrange(1 << WIDTH), int(rng.random() < 0.6))
        await ReadOnly()
        assert int(dut.empty_o.value) == int(not tb.sent), f"empty_o with {len(tb.sent)} words inside"


@pytest.mark.parametrize("case", SUITE.cases())
def test_bsd_fifo(case) -> None:
    SUITE.run(case)
