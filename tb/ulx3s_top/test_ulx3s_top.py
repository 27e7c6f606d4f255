# SPDX-License-Identifier: Apache-2.0
"""The board top synth/ulx3s_top.v, ULX3S (ECP5 LFE5U-85F), 25 MHz, FT231X serial, in simulation: power-up, packets over its
UART pins at the board's real clock, each reply checked against the model, the header pad and
the LEDs (tb/lib/board_top.py). The vendor pad primitive BB is simulated by
tb/lib/pads/BB.v. Runs in `make test` at 115 200 baud on Icarus; `make test-full` adds
9600 baud (the bitstream's build) on Verilator.
"""

from __future__ import annotations

import cocotb
import pytest

from board_top import Board, builds, session, one_build_per_sim
import runner

BOARD = Board(top="ulx3s_top", clk_hz=25_000_000, clk="clk_25mhz", rx="ftdi_txd", tx="ftdi_rxd", btn="btn_pwr_n",
              pads="gp", pad_model="BB", led_link=("led", 0), led_act=("led", 1),
              led_active_low=False, extra_sources=("board_status.v", "ecp5_pads.v"))
BUILDS = builds(BOARD)


@cocotb.test()
async def test_board_session(dut) -> None:
    """Power-up message, a pin read, pin 0 driven low/high/low through its pad, LEDs."""
    await session(dut, BOARD)


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus", only=one_build_per_sim))
def test_ulx3s_top(sim: str, build: str) -> None:
    runner.run(sim, BOARD.top, __file__, BUILDS[build], build, sources=BOARD.sources())
