# SPDX-License-Identifier: Apache-2.0
"""The iCEBreaker board top with a timer on every pin of its three PMODs (synth/icebreaker_top.v
at NUM_PINS 24, TIMER_MASK 24'hFFFFFF: `make bitstream BOARD=icebreaker24`), in simulation at the
board's 12 MHz clock over its UART pins: the power-up message, a pin read on PMOD 1B, and a
width measurement on the last pin of PMOD 2 (P2_10), a sensor's low pulse of 2 ms on the header
pin, each packet checked against the model. The pad model (tb/lib/pads/SB_IO.v) takes the
outside level of an undriven pin from its `ext` register, which the test sets. Runs in `make
test`: at 9600 baud (the bitstream's build) on Verilator, at 115 200 baud on Icarus.
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import ClockCycles, Timer

from board_top import Board, BoardLink
from bsd_model import (CMD_DIG_CFG, CMD_DIG_IO, CMD_PTIME_RD, DEVCODE_HOST, DIGCFG_IODIR, DIGCFG_TMODE, Params,
                       packet, tick_tolerance, ticks_of)
import runner
from runner import hdl_params
from uart_line import now_ps

BOARD = Board(top="icebreaker_top", clk_hz=12_000_000, clk="CLK", rx="RX", tx="TX", btn="BTN_N",
              pads="P1A", pad_model="SB_IO", led_link=("LEDG_N", 0), led_act=None,
              led_active_low=True, extra_sources=("ice40_pads.v",))
PINS = 24
# Build names of their own: the 5-pin top's tests build the same toplevel.
BUILDS = {f"p24b{baud}": {"CLK_HZ": BOARD.clk_hz, "BAUD": baud, "NUM_PINS": PINS, "TIMER_MASK": f"{PINS}'hffffff"}
          for baud in (9600, 115_200)}
READ_PIN = 12          # P1B3
TIMED_PIN = 23         # P2_10
PULSE_S = 2e-3


@cocotb.test()
async def test_board24_session(dut) -> None:
    """Power-up, a DIG_IO read on PMOD 1B, a width timer on PMOD 2 against a 2 ms pulse."""
    hdl = hdl_params()
    clk_hz, baud = int(hdl["CLK_HZ"]), int(hdl["BAUD"])
    p = Params(clk_hz=clk_hz, num_pins=PINS, timer_mask=(1 << PINS) - 1, hb_rate=10)
    pull_ups = (1 << PINS) - 1
    link = BoardLink(dut, BOARD, p, baud, pull_ups)
    model, sink, frame_ps = link.model, link.sink, link.frame_ps
    # The pad of the timed pin: PMOD 2, bit 7 (its shim u_p2, generate block g_pad[7]).
    header = dut.u_p2.g_pad[TIMED_PIN - 16].u_io.ext

    await ClockCycles(dut.CLK, 2)
    await link.expect(model.reset(pull_ups).packets, "power-up")
    await link.command(packet(p.module_addr, CMD_DIG_IO, READ_PIN))
    # Input, width mode, target level 0: the timer measures how long the pin stays low.
    await link.command(packet(p.module_addr, CMD_DIG_CFG, TIMED_PIN, DIGCFG_IODIR | DIGCFG_TMODE))
    await link.command(packet(p.module_addr, CMD_PTIME_RD, DEVCODE_HOST | TIMED_PIN))
    assert model.timer_busy(TIMED_PIN)
    header.value = 0
    assert not model.set_pin(TIMED_PIN, 0)
    await Timer(round(PULSE_S * 1e12), unit="ps")
    header.value = 1
    assert not model.set_pin(TIMED_PIN, 1)
    # The result: the model's packet for the value the core measured, which must be the
    # pulse's length in ticks within the contract's tolerance.
    got = bytearray()     # A, 4, cmdDEV_VAL, timer ID, hi, lo
    deadline = now_ps() + 12 * frame_ps
    while len(got) < 6 and now_ps() < deadline:
        await Timer(frame_ps, unit="ps")
        got += sink.read_nowait(sink.count())
    assert len(got) == 6, f"no timer result after the pulse: {bytes(got).hex(' ')}"
    result = (got[4] << 8) | got[5]
    nominal = ticks_of(PULSE_S)
    assert abs(result - nominal) <= tick_tolerance(clk_hz), \
        f"pin {TIMED_PIN}: {result} ticks for a {PULSE_S * 1e3:g} ms pulse, expected {nominal}"
    want = b"".join(model.timer_complete(TIMED_PIN, result).packets)
    assert bytes(got) == want, f"timer result: expected {want.hex(' ')}, got {bytes(got).hex(' ')}"
    await link.expect([], "the timer result")
    dut._log.info("pin %d (P2_10): %d ticks for a %g ms pulse; %.1f ms simulated", TIMED_PIN, result,
                  PULSE_S * 1e3, now_ps() / 1e9)


@pytest.mark.parametrize("sim, build", runner.cases(
    BUILDS, only=lambda sim, build: (sim, build) in (("verilator", "p24b9600"), ("icarus", "p24b115200"))))
def test_icebreaker24_top(sim: str, build: str) -> None:
    runner.run(sim, BOARD.top, __file__, BUILDS[build], build, sources=BOARD.sources())
