# SPDX-License-Identifier: Apache-2.0
"""cocotb tests for the runner's own tests: one fails, one is skipped (tb/runner/test_runner.py)."""

from __future__ import annotations

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, ReadOnly


async def count(dut, clocks: int) -> int:
    Clock(dut.clk, 10, unit="ns").start()
    dut.rst.value = 1
    await ClockCycles(dut.clk, 2)
    dut.rst.value = 0
    await ClockCycles(dut.clk, clocks)
    await ReadOnly()
    return int(dut.count_q.value)


@cocotb.test()
async def counts(dut) -> None:
    assert await count(dut, 5) == 5


@cocotb.test()
async def counts_wrong(dut) -> None:
    assert await count(dut, 5) == 6


@cocotb.test(skip=True)
async def skipped(dut) -> None:
    pass


@cocotb.test()
@cocotb.parametrize(clocks=[1, 3])
async def counts_each(dut, clocks: int) -> None:
    assert await count(dut, clocks) == clocks
