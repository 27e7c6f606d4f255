# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_idx_onehot (a 6-bit number, or none, as a one-hot vector), and their
pytest entry.

The timer bank's delivery clears and the wheel's insert mask rely on it: with en_i the output
has exactly the numbered bit set (none for a number at or above N), without en_i no bit. Checked
for every number 0..63 with and without en_i on a small, an odd and a full-width (64) build, the
numbers in a seeded random order.
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
async def test_every_number(dut) -> None:
    """Each number with en_i gives its bit alone (none past N); without en_i, no bit."""
    n = int(hdl_params()["N"])
    rng = random.Random(cocotb.RANDOM_SEED)
    cases = [(en, idx) for en in (0, 1) for idx in range(64)]
    rng.shuffle(cases)
    for en, idx in cases:
        dut.en_i.value = en
        dut.idx_i.value = idx
        await Timer(1, unit="ns")
        got = int(dut.onehot_o.value)
        want = (1 << idx) if en and idx < n else 0
        assert got == want, f"en_i {en} idx_i {idx}: onehot_o {got:#x}, want {want:#x}"


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="verilator"))
def test_bsd_idx_onehot(sim: str, build: str) -> None:
    runner.run(sim, "bsd_idx_onehot", __file__, BUILDS[build], build)
