# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_axis_skid (the register slice: 8 bits, and 9 as used with tlast around
the core) against a bounded queue of 2 words, and their pytest entry.

Inputs are driven on the falling edge; every clock, right before the rising edge
(ReadOnly), the test records which handshakes happen at that edge. It also checks that
s_axis_tready and m_axis_tvalid come from flops: changing the other side's inputs in the
middle of a clock must not move them (tb/lib/stream_check.py).
"""

from __future__ import annotations

import cocotb
import pytest


import stream_check
import runner
from runner import hdl_params

BUILDS = {"w8": {"WIDTH": 8}, "w9": {"WIDTH": 9}}


def make_tb(dut) -> stream_check.StreamTB:
    p = hdl_params()
    return stream_check.StreamTB(dut, int(p["WIDTH"]), 2)


@cocotb.test()
async def test_random_traffic(dut) -> None:
    """Every word comes out once, in order, never more inside than the capacity."""
    await stream_check.random_traffic(make_tb(dut))


@cocotb.test()
async def test_full_rate_and_capacity(dut) -> None:
    """One word a clock at full rate; exactly the capacity taken while stalled."""
    await stream_check.full_rate_and_capacity(make_tb(dut))


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_axis_skid(sim: str, build: str) -> None:
    runner.run(sim, "bsd_axis_skid", __file__, BUILDS[build], build)
