# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_onehot_idx (a one-hot vector's set bit as a 6-bit number), and their
pytest entry.

The drain's pick (the lowest waiting timer) and the wheel's start index rely on it: for every
one-hot input the number is the set bit's position, and 0 for no bit set. Checked for every
position of a small and a full-width (64) build, the positions in a seeded random order.
"""

from __future__ import annotations

import random

import cocotb
import pytest
from cocotb.triggers import Timer

import runner
from runner import hdl_params

BUILDS = {"n4": {"N": 4}, "n5": {"N": 5}, "n64": {"N": 64}}


@cocotb.test()
async def test_every_position(dut) -> None:
    """Each one-hot value (and zero) gives its bit's position (zero: 0)."""
    n = int(hdl_params()["N"])
    rng = random.Random(cocotb.RANDOM_SEED)
    cases = [None, *rng.sample(range(n), n)]
    for pos in cases:
        dut.onehot_i.value = 0 if pos is None else 1 << pos
        await Timer(1, unit="ns")
        got = int(dut.idx_o.value)
        assert got == (0 if pos is None else pos), f"one-hot bit {pos}: idx_o {got}"
    assert len(cases) == n + 1


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="verilator"))
def test_bsd_onehot_idx(sim: str, build: str) -> None:
    runner.run(sim, "bsd_onehot_idx", __file__, BUILDS[build], build)
