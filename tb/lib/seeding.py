# SPDX-License-Identifier: Apache-2.0
"""Seeded randomness for the block-level cocotb tests."""

from __future__ import annotations

import os
import random

import cocotb


def make_rng(dut, name: str) -> random.Random:
    """Per-test RNG. cocotb derives cocotb.RANDOM_SEED from the regression seed
    (COCOTB_RANDOM_SEED, chosen and printed by tb/lib/runner.py) and the test name."""
    regression_seed = os.environ.get("COCOTB_RANDOM_SEED", "?")
    dut._log.info("%s: rerun with COCOTB_RANDOM_SEED=%s", name, regression_seed)
    return random.Random(cocotb.RANDOM_SEED)
