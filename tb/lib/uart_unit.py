# SPDX-License-Identifier: Apache-2.0
"""Clock, reset and bit timing shared by the unit tests of bsd_uart_rx and bsd_uart_tx
(tb/bsd_uart_rx/, tb/bsd_uart_tx/): both build at 12 MHz / 115 200 baud (104 clocks per
bit, the iCEBreaker's case).

The host side is cocotbext-uart (UartSource into the receiver, UartSink on the
transmitter's line); the strict tb/lib/uart_line.py LineMonitor checks what cocotbext-uart's
receiver does not (stop bits, frame timing), and malformed frames and glitches are driven by
hand. Random data is seeded from cocotb's seed (printed at the start of each test;
COCOTB_RANDOM_SEED=<seed> replays it).
"""

from __future__ import annotations

import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge, Timer

from runner import hdl_params

BUILDS = {"clk12M-b115200": {"CLK_HZ": 12_000_000, "BAUD": 115_200}}
CLK_HZ = int(hdl_params().get("CLK_HZ", 12_000_000))
BAUD = int(hdl_params().get("BAUD", 115_200))
DIV = (CLK_HZ + BAUD // 2) // BAUD  # clocks per bit, as the RTL rounds it
PERIOD_PS = round(1e12 / CLK_HZ)
BIT_PS = DIV * PERIOD_PS  # the DUT's bit time
FRAME_PS = 10 * BIT_PS


def rng_for(dut) -> random.Random:
    seed = cocotb.RANDOM_SEED
    dut._log.info("CLK_HZ %d, BAUD %d (%d clocks per bit), seed %d", CLK_HZ, BAUD, DIV, seed)
    return random.Random(seed)


async def start_clock_and_reset(dut) -> None:
    cocotb.start_soon(Clock(dut.clk, PERIOD_PS, unit="ps", impl="gpi", period_high=PERIOD_PS // 2).start())
    dut.rst.value = 1
    await ClockCycles(dut.clk, 4)
    dut.rst.value = 0
    await RisingEdge(dut.clk)


async def idle(frames: float = 1.0) -> None:
    await Timer(round(frames * FRAME_PS), unit="ps")
