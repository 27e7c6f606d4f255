# SPDX-License-Identifier: Apache-2.0
"""The parameter sets the top-level tests of brainstem_dio build, by name.

Every top-level test file draws its builds from this one table, so two files that need the
same parameters share one build (sim_build/brainstem_dio/<sim>-<name>/).
"""

from __future__ import annotations

from bsd_model import Params

PARAMS: dict[str, Params] = {
    # GP 1.0 defaults (48 MHz, 5 pins, timers on 1-4).
    "gp1": Params(),
    # 2 MHz (3.2 clocks per tick, not a multiple of 625 kHz) so the 104.86 ms timeout is
    # ~210k cycles; a 200 us RX timeout; pin 0 a fixed output, pin 3 a fixed input with ENA
    # armed for rising edges (timer pin too, edge mode towards 0). 20 pins (timers on 1-4):
    # from 17 pins on bsd_cfg_regs keeps ENA, TSTATE and TMODE in a memory, so every
    # command test runs on both forms; pin 18 a fixed input with every bit but TRG.
    "slow_fixed": Params(clk_hz=2_000_000, rx_timeout_us=200, num_pins=20,
                         fixed_mask=(1 << 18) | 0b01001, fixed_cfg=(0x1B << 144) | (0x07 << 24) | 0x00),
    # GP 2.0-like: 7 pins, module 4, timers on pins 1-4, 12 MHz, latches sampled every clock,
    # no RX timeout.
    "gp2": Params(num_pins=7, module_addr=4, timer_id_base=11, trans_id_base=20,
                  timer_mask=0b0011110, clk_hz=12_000_000, poll_hz=0, rx_timeout_us=0),
    # Corners the contract allows: 8 pins, the highest module address, device IDs up to 63
    # (timers on pins 0 and 1 only, so their IDs 58 and 59 stay below 64).
    "high_ids": Params(num_pins=8, module_addr=254, timer_mask=0b00000011, timer_id_base=58,
                       pin_id_base=40, trans_id_base=50),
    # Heartbeat every 25.6 ms at 2 MHz (51 200 clocks a period).
    "heartbeat": Params(clk_hz=2_000_000, hb_rate=1),
    # Timer accuracy at 32 MHz (51.2 clocks per tick).
    "clk32": Params(clk_hz=32_000_000),
    # GP 1.0 at the lowest clock: long intervals up to the 104.86 ms limit are cheap here;
    # HB_RATE 0.
    "clk2": Params(clk_hz=2_000_000),
    # The transition latch with the default 10 kHz polling, and sampled every clock, at a
    # clock low enough that many 0.1 ms polls are cheap.
    "clk8": Params(clk_hz=8_000_000),
    "clk8_poll0": Params(clk_hz=8_000_000, poll_hz=0),
    # 64 pins with a timer on every one (device IDs 0..63 for levels and timers alike), at
    # the lowest clock (3.2 clocks a tick: 64 timeouts and a 200 ms stall are cheap) and at
    # 2.5, 12 and 48 MHz for the accuracy of 64 timers at once.
    "t64_2": Params(clk_hz=2_000_000, num_pins=64, timer_mask=(1 << 64) - 1, pin_id_base=0,
                    timer_id_base=0, trans_id_base=0),
    "t64_2p5": Params(clk_hz=2_500_000, num_pins=64, timer_mask=(1 << 64) - 1, pin_id_base=0,
                      timer_id_base=0, trans_id_base=0),
    "t64_12": Params(clk_hz=12_000_000, num_pins=64, timer_mask=(1 << 64) - 1, pin_id_base=0,
                     timer_id_base=0, trans_id_base=0),
    "t64_48": Params(clk_hz=48_000_000, num_pins=64, timer_mask=(1 << 64) - 1, pin_id_base=0,
                     timer_id_base=0, trans_id_base=0),
}

BUILDS: dict[str, dict[str, object]] = {name: p.to_hdl() for name, p in PARAMS.items()}
