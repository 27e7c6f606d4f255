# SPDX-License-Identifier: Apache-2.0
"""A cocotb test that suits one build only (tb/runner/test_runner.py)."""

from __future__ import annotations

import cocotb

import runner


@cocotb.test(skip=not runner.on("a"))
async def only_on_a(dut) -> None:
    assert runner.test_args() == {"knob": 3}
