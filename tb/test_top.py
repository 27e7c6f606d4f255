"""pytest entry for the top-level cocotb tests (tb/top_tests.py) on both simulators.

Each parameter set is a separate build (runner.py gives each its own directory). Tests that
need a feature only some builds have (an RX timeout worth waiting for, fixed pins, a
heartbeat, a low clock for 104 ms timeouts) run only there. One pytest case per cocotb test
keeps failures separate and lets pytest-xdist spread the work.
"""

from __future__ import annotations

import os

import pytest

from bsd_model import PARAMS_ENV, Params
from runner import SIMULATORS, run

BUILDS: dict[str, Params] = {
    # GP 1.0 defaults.
    "gp1": Params(),
    # 2 MHz (3.2 clocks per tick, not a multiple of 625 kHz) so the 104.86 ms timeout is
    # ~210k cycles; a 200 us RX timeout; pin 0 a fixed output, pin 3 a fixed input with ENA
    # armed for rising edges (timer pin too, edge mode towards 0).
    "slow_fixed": Params(clk_hz=2_000_000, rx_timeout_us=200, fixed_mask=0b01001,
                         fixed_cfg=(0x07 << 24) | 0x00),
    # GP 2.0-like: 7 pins, module 4, timers on pins 1-4, 12 MHz, latches sampled every clock,
    # no RX timeout.
    "gp2": Params(num_pins=7, module_addr=4, timer_id_base=11, trans_id_base=20,
                  timer_mask=0b0011110, clk_hz=12_000_000, poll_hz=0, rx_timeout_us=0),
    # Corners the contract allows: 8 pins, the highest module address, device IDs up to 63
    # (timers on pins 0 and 1 only, so their IDs 58 and 59 stay below 64).
    "high_ids": Params(num_pins=8, module_addr=254, timer_mask=0b00000011, timer_id_base=58,
                       pin_id_base=40, trans_id_base=50),
    # Heartbeat every 25.6 ms at 2 MHz.
    "heartbeat": Params(clk_hz=2_000_000, hb_rate=1),
}

COMMON = ["test_dig_cfg", "test_dig_io", "test_messages", "test_framing", "test_stress"]
TESTS: dict[str, list[str]] = {
    "gp1": COMMON + ["test_worked_examples", "test_dig_rst_latch", "test_throughput",
                     "test_timers", "test_order_stalled", "test_reset_mid", "test_reply_hold",
                     "test_reply_before_later_timer"],
    "slow_fixed": COMMON + ["test_rx_timeout", "test_long_stall", "test_timer_timeout",
                            "test_fixed_pins", "test_dig_rst_latch", "test_reset_mid"],
    "gp2": COMMON + ["test_worked_examples", "test_dig_rst_latch", "test_timers",
                     "test_order_stalled", "test_reply_before_later_timer"],
    "high_ids": ["test_dig_io", "test_timers", "test_stress"],
    "heartbeat": ["test_heartbeat"],
}

# The full 10 000-packet stress runs on the GP 1.0 build on both simulators (a few seconds
# each); the other builds take a smaller share.
STRESS_PACKETS = {
    ("verilator", "gp1"): 10_000,
    ("icarus", "gp1"): 10_000,
    ("verilator", "slow_fixed"): 3_000,
    ("icarus", "slow_fixed"): 2_000,
    ("verilator", "gp2"): 5_000,
    ("icarus", "gp2"): 3_000,
    ("verilator", "high_ids"): 2_000,
    ("icarus", "high_ids"): 1_000,
}

CASES = [(build, test) for build, tests in TESTS.items() for test in tests]


@pytest.mark.parametrize("build,test", CASES, ids=[f"{b}-{t}" for b, t in CASES])
@pytest.mark.parametrize("sim", SIMULATORS)
def test_top(sim: str, build: str, test: str) -> None:
    params = BUILDS[build]
    env = {PARAMS_ENV: params.to_json()}
    if test == "test_stress":
        # $BSD_STRESS_PACKETS overrides the table, e.g. for a long nightly run.
        env["BSD_STRESS_PACKETS"] = os.environ.get("BSD_STRESS_PACKETS", str(STRESS_PACKETS[(sim, build)]))
    run(sim, "brainstem_dio", "top_tests", parameters=params.to_hdl(), testcase=test, extra_env=env)
