# SPDX-License-Identifier: Apache-2.0
"""The board top synth/icebreaker_top.v, iCEBreaker (iCE40UP5K), 12 MHz, FT2232H serial, in simulation: power-up, packets over its
UART pins at the board's real clock, each reply checked against the model, the header pad and
the link LED (tb/lib/board_top.py; this top has no activity LED). The vendor pad primitive SB_IO is simulated by
tb/lib/pads/SB_IO.v. Runs in `make test`: at 9600 baud (the bitstream's build) on Verilator, at 115 200 baud on
Icarus.
"""

from __future__ import annotations

import cocotb
import pytest

from board_top import Board, builds, session, one_build_per_sim
import runner

BOARD = Board(top="icebreaker_top", clk_hz=12_000_000, clk="CLK", rx="RX", tx="TX", btn="BTN_N",
              pads="P1A", pad_model="SB_IO", led_link=("LEDG_N", 0), led_act=None,
              led_active_low=True, extra_sources=("ice40_pads.v",))
BUILDS = builds(BOARD)


@cocotb.test()
async def test_board_session(dut) -> None:
    """Power-up message, a pin read, pin 0 driven low/high/low through its pad, LEDs."""
    await session(dut, BOARD)


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, only=one_build_per_sim))
def test_icebreaker_top(sim: str, build: str) -> None:
    runner.run(sim, BOARD.top, __file__, BUILDS[build], build, sources=BOARD.sources())
