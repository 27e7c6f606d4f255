"""Block-level regression: each RTL block's cocotb module on Verilator and Icarus.

    .venv/bin/python -m pytest -n 2 tb/test_blocks.py -q

Every (simulator, block, HDL parameter set) is built once in its own directory
(tb/runner.py). Random stimulus comes from one regression seed per session, printed
by every test (shown with a failure) and logged by each random cocotb test; rerun
with COCOTB_RANDOM_SEED=<seed> in the environment to repeat it.
"""

from __future__ import annotations

import hashlib
import os
import random

import pytest

import runner

SIMS = pytest.mark.parametrize("sim", runner.SIMULATORS)

# One regression seed per pytest session (or the one given), printed with every test.
# pytest-xdist workers share PYTEST_XDIST_TESTRUNUID, so they derive the same seed.
def _session_seed() -> int:
    if os.environ.get("COCOTB_RANDOM_SEED"):
        return int(os.environ["COCOTB_RANDOM_SEED"])
    uid = os.environ.get("PYTEST_XDIST_TESTRUNUID")
    if uid:
        return int(hashlib.sha1(uid.encode()).hexdigest(), 16) % (1 << 31)
    return random.SystemRandom().randrange(1 << 31)


SEED = _session_seed()


def run(sim, toplevel, module, parameters=None, env=None):
    """runner.run with the session seed; `env` passes HDL parameters to the test module."""
    print(f"COCOTB_RANDOM_SEED={SEED}")
    extra_env = {"COCOTB_RANDOM_SEED": str(SEED), **(env or {})}
    runner.run(sim, toplevel, module, parameters, extra_env=extra_env)


# --------------------------------------------------------------------------- tick_gen
# (CLK_HZ, RATE_HZ, strobes to check). 625 kHz is the 1.6 us timer tick, 10 kHz the
# default POLL_HZ; 33_333_333 and 2_000_003 share no factor with 625_000 (gcd 1).
TICK_CASES = [
    (48_000_000, 625_000, 3000),
    (32_000_000, 625_000, 3000),
    (12_000_000, 625_000, 3000),
    (2_000_000, 625_000, 4000),
    (33_333_333, 625_000, 3000),
    (2_000_003, 625_000, 4000),
    (48_000_000, 10_000, 60),
    (2_000_003, 10_000, 600),
    (48_000_000, 0, 0),
    (2_000_000, 0, 0),
]


@SIMS
@pytest.mark.parametrize(
    "clk_hz,rate_hz,ticks", TICK_CASES, ids=[f"clk{c}-rate{r}" for c, r, _ in TICK_CASES]
)
def test_tick_gen(sim, clk_hz, rate_hz, ticks):
    run(
        sim,
        "bsd_tick_gen",
        "tick_gen_tests",
        {"CLK_HZ": clk_hz, "RATE_HZ": rate_hz},
        {"BSD_CLK_HZ": str(clk_hz), "BSD_RATE_HZ": str(rate_hz), "BSD_TICKS": str(ticks)},
    )


# ------------------------------------------------------------------------ trans_latch
@SIMS
def test_trans_latch(sim):
    run(sim, "bsd_trans_latch", "trans_latch_tests")


# ------------------------------------------------------------------------ event_timer
@SIMS
def test_event_timer(sim):
    run(sim, "bsd_event_timer", "event_timer_tests")


# ----------------------------------------------------------------------------- parser
# (MODULE_ADDR, RX_TIMEOUT_US): 20 us = 12.5 ticks (13 -> 14 idle ticks), 16 us = exactly
# 10 ticks (-> 11), 0 = no timeout, 25_600 = the default (16 000 -> 16 001).
PARSER_CASES = [(2, 20), (254, 16), (0x40, 0), (2, 25_600)]


@SIMS
@pytest.mark.parametrize(
    "addr,timeout_us", PARSER_CASES, ids=[f"addr{a}-to{t}us" for a, t in PARSER_CASES]
)
def test_parser(sim, addr, timeout_us):
    run(
        sim,
        "bsd_parser",
        "parser_tests",
        {"MODULE_ADDR": addr, "RX_TIMEOUT_US": timeout_us},
        {"BSD_MODULE_ADDR": str(addr), "BSD_RX_TIMEOUT_US": str(timeout_us)},
    )


# ---------------------------------------------------------------------- stream buffers
# (block, WIDTH, FIFO DEPTH): the register slice as used around the core (8 and 9 bits),
# the FIFO small (so full and empty come often) and at a power of two in between.
STREAM_CASES = [("skid", 8, 0), ("skid", 9, 0), ("fifo", 8, 2), ("fifo", 8, 16)]


@SIMS
@pytest.mark.parametrize(
    "block,width,depth", STREAM_CASES, ids=[f"{b}-w{w}" + (f"-d{d}" if d else "") for b, w, d in STREAM_CASES]
)
def test_stream(sim, block, width, depth):
    top = {"skid": "bsd_axis_skid", "fifo": "bsd_fifo"}[block]
    params = {"WIDTH": width, **({"DEPTH": depth} if depth else {})}
    env = {"BSD_STREAM": block, "BSD_WIDTH": str(width), "BSD_DEPTH": str(depth)}
    run(sim, top, "stream_tests", params, env)
