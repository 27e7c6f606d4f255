"""pytest entry for the serial link: unit tests of bsd_uart_rx / bsd_uart_tx (tb/uart_tests.py) and
the tests of brainstem_dio_uart with cocotbext-uart as the host (tb/uart_link_tests.py), on
Verilator and Icarus.

    .venv/bin/python -m pytest -n 2 tb/test_uart.py

Builds (each in its own sim_build/ folder):
- bsd_uart_rx, bsd_uart_tx at 12 MHz / 115200 baud (104 clocks per bit, the iCEBreaker's case);
- brainstem_dio_uart at 9600 baud from 2 MHz (208 clocks per bit; 2 MHz is the core's lowest
  clock) with the wrapper's default heartbeat (HB_RATE 10 = 256 ms) and an 8-byte FIFO;
- brainstem_dio_uart at 115200 baud from 2.304 MHz (20 clocks per bit) with a 25.6 ms
  heartbeat (HB_RATE 1) and a 16-byte FIFO.
Small FIFOs make overflow cheap to reach; the board keeps the default 512.

Verilator runs every case. Icarus is several times slower on the whole module, and a 9600-baud
byte is 2083 clocks, so on Icarus the 9600-baud build runs only the worked examples; the
115200-baud build runs everything on both.
"""

from __future__ import annotations

import json

import pytest

from bsd_model import PARAMS_ENV, Params
from runner import SIMULATORS, run

UNIT = {"CLK_HZ": 12_000_000, "BAUD": 115_200}
UNIT_TESTS = {
    "bsd_uart_rx": ["test_rx_bytes", "test_rx_baud_mismatch", "test_rx_glitch", "test_rx_framing"],
    "bsd_uart_tx": ["test_tx_back_to_back", "test_tx_gaps", "test_tx_baud_mismatch",
                "test_tx_reset_mid_frame"],
}
UNIT_CASES = [(top, t) for top, tests in UNIT_TESTS.items() for t in tests]

# (core parameters, baud, FIFO depth, HB_RATE) per link build.
LINK_BUILDS = {
    "b9600": (Params(clk_hz=2_000_000, hb_rate=10), 9600, 8),
    "b115200": (Params(clk_hz=2_304_000, hb_rate=1), 115_200, 16),
}
LINK_COMMON = ["test_worked_examples", "test_back_to_back", "test_framing_error",
               "test_fifo_overflow"]
LINK_TESTS = {
    "b9600": LINK_COMMON + ["test_heartbeat_default_rate"],
    "b115200": LINK_COMMON + ["test_heartbeat_host"],
}
ICARUS_9600 = {"test_worked_examples"}
LINK_CASES = [(sim, b, t) for sim in SIMULATORS for b, tests in LINK_TESTS.items() for t in tests
              if not (sim == "icarus" and b == "b9600" and t not in ICARUS_9600)]


@pytest.mark.parametrize("top,test", UNIT_CASES, ids=[f"{a}-{b}" for a, b in UNIT_CASES])
@pytest.mark.parametrize("sim", SIMULATORS)
def test_uart_unit(sim: str, top: str, test: str) -> None:
    env = {"UART_CLK_HZ": str(UNIT["CLK_HZ"]), "UART_BAUD": str(UNIT["BAUD"])}
    run(sim, top, "uart_tests", parameters=UNIT, testcase=test, extra_env=env)


@pytest.mark.parametrize("sim,build,test", LINK_CASES, ids=["-".join(c) for c in LINK_CASES])
def test_uart_link(sim: str, build: str, test: str) -> None:
    params, baud, depth = LINK_BUILDS[build]
    hdl = {**params.to_hdl(), "BAUD": baud, "FIFO_DEPTH": depth}
    env = {PARAMS_ENV: params.to_json(), "UART_LINK": json.dumps({"baud": baud, "fifo_depth": depth})}
    run(sim, "brainstem_dio_uart", "uart_link_tests", parameters=hdl, testcase=test, extra_env=env)
