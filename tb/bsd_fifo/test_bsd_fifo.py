# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_fifo (small, so full and empty come often, and at a power of two) against
a bounded queue of DEPTH + 2 words (the RAM, its read register and the skid register), and their pytest entry.

Inputs are driven on the falling edge; every clock, right before the rising edge
(ReadOnly), the test records which handshakes happen at that edge. It also checks that
s_axis_tready and m_axis_tvalid come from flops: changing the other side's inputs in the
middle of a clock must not move them (tb/lib/stream_check.py).
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import ReadOnly

import stream_check
import runner
from runner import hdl_params

# d512: the serial wrapper's RX FIFO (brainstem_dio_uart's FIFO_DEPTH default, the board
# tops' build), for its upper pointer bits; it runs only test_deep_fill_and_wrap.
BUILDS = {"d2": {"WIDTH": 8, "DEPTH": 2}, "d16": {"WIDTH": 8, "DEPTH": 16},
                                     "d512": {"WIDTH": 8, "DEPTH": 512}}
SMALL = ("d2", "d16")


def make_tb(dut) -> stream_check.StreamTB:
    p = hdl_params()
    return stream_check.StreamTB(dut, int(p["WIDTH"]), int(p["DEPTH"]) + 2)


@cocotb.test(skip=not runner.on(*SMALL))
async def test_random_traffic(dut) -> None:
    """Every word comes out once, in order, never more inside than the capacity."""
    await stream_check.random_traffic(make_tb(dut))


@cocotb.test(skip=not runner.on(*SMALL))
async def test_full_rate_and_capacity(dut) -> None:
    """One word a clock at full rate; exactly the capacity taken while stalled."""
    await stream_check.full_rate_and_capacity(make_tb(dut))


@cocotb.test(skip=not runner.on(*SMALL))
async def test_fifo_empty_flag(dut) -> None:
    """empty_o is 1 exactly when no word is inside (the RAM and the output register)."""
    tb = make_tb(dut)
    rng, WIDTH = tb.rng, tb.width
    await tb.reset()
    for _ in range(600):
        await tb.step(int(rng.random() < 0.4), rng.randrange(1 << WIDTH), int(rng.random() < 0.6))
        await ReadOnly()
        assert int(dut.empty_o.value) == int(not tb.sent), f"empty_o with {len(tb.sent)} words inside"


@cocotb.test(skip=not runner.on("d512"))
async def test_deep_fill_and_wrap(dut) -> None:
    """The 512-word RAM filled to the capacity (DEPTH + 2) with the output stalled, drained,
    then over 1024 words at full rate (both pointers wrap past their top bit and back), and
    filled and drained once more: every word once, in order, tready low exactly when full,
    empty_o exactly when nothing is inside."""
    tb = make_tb(dut)
    cap = tb.capacity
    await tb.reset()
    word = 0

    async def fill_and_drain() -> None:
        nonlocal word
        taken = 0
        for _ in range(cap + 3):
            took, gave = await tb.step(1, word & 0xFF, 0)
            assert not gave
            if took:
                taken += 1
                word += 1
        assert taken == cap, f"took {taken} words with the output stalled, capacity {cap}"
        assert int(dut.s_axis_tready.value) == 0 and int(dut.empty_o.value) == 0
        while tb.sent:
            await tb.step(0, 0, 1)
        await ReadOnly()
        assert int(dut.empty_o.value) == 1

    await fill_and_drain()
    for _ in range(1100):
        took, _ = await tb.step(1, word & 0xFF, 1)
        assert took, "input refused while the output is always ready"
        word += 1
    while tb.sent:
        await tb.step(0, 0, 1)
    await fill_and_drain()
    assert tb.delivered == word == 2 * cap + 1100


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_fifo(sim: str, build: str) -> None:
    runner.run(sim, "bsd_fifo", __file__, BUILDS[build], build)
