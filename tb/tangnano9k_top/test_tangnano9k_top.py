# SPDX-License-Identifier: Apache-2.0
"""The board top synth/tangnano9k_top.v, Tang Nano 9K (Gowin GW1NR-9), 27 MHz, BL702 serial, in simulation: power-up, packets over its
UART pins at the board's real clock, each reply checked against the model, the header pad and
the LEDs (tb/lib/board_top.py). The vendor pad primitive IOBUF is simulated by
tb/lib/pads/IOBUF.v. Runs in `make test` at 115 200 baud on Icarus; `make test-full` adds
9600 baud (the bitstream's build) on Verilator.
"""

from __future__ import annotations

import cocotb
import pytest

from board_top import Board, builds, session, one_build_per_sim
import runner

BOARD = Board(top="tangnano9k_top", clk_hz=27_000_000, clk="clk", rx="uart_rx", tx="uart_tx", btn="btn_n",
              pads="io", pad_model="IOBUF", led_link=("led_n", 0), led_act=("led_n", 1),
              led_active_low=True, extra_sources=("board_status.v", "gowin_pads.v"))
BUILDS = builds(BOARD)


@cocotb.test()
async def test_board_session(dut) -> None:
    """Power-up message, a pin read, pin 0 driven low/high/low through its pad, LEDs."""
    await session(dut, BOARD)


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus", only=one_build_per_sim))
def test_tangnano9k_top(sim: str, build: str) -> None:
    runner.run(sim, BOARD.top, __file__, BUILDS[build], build, sources=BOARD.sources())
