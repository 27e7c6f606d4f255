# SPDX-License-Identifier: Apache-2.0
"""A suite whose cases share one simulator run (tb/runner/test_runner.py's group tests)."""

from __future__ import annotations

from pathlib import Path

from runner_cases import count
from suite import Suite

HERE = Path(__file__).resolve().parent
SUITE = Suite(__file__, "runner_dut", {"a": {}}, sims=("icarus",), sources=[HERE / "runner_dut.v"])


@SUITE.test()
async def first(dut) -> None:
    assert await count(dut, 3) == 3


@SUITE.test()
async def fails(dut) -> None:
    assert await count(dut, 3) == 4


@SUITE.test()
async def last(dut) -> None:
    assert await count(dut, 2) == 2
