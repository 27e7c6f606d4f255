# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_tick_gen, and their pytest entry.

Clock-index convention (the "fixed offset" of the phase check): edge 0 is the rising
edge at which `rst` is last sampled 1; edge n is the n-th rising edge after it. The k-th
strobe (k = 1, 2, ...) must be the value of `tick_o` right after edge n_k with

    0 <= n_k - k * CLK_HZ / RATE_HZ < 1        (i.e. n_k = ceil(k * CLK_HZ / RATE_HZ))

which is checked exactly, in integers, for every strobe of the run; every strobe must be
exactly one clock wide. RATE_HZ = 0 must give tick_o = 1 on every clock after reset.

Each (CLK_HZ, RATE_HZ) pair is a build of its own. 625 kHz is the 1.6 us timer tick, 10 kHz
the default POLL_HZ; 33_333_333 and 2_000_003 share no factor with 625_000 (gcd 1). The
long-run drift check (1 s of clock time) is test_bsd_tick_gen_drift.py.
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.clock import Clock
from cocotb.simtime import get_sim_time
from cocotb.triggers import (
    ClockCycles,
    FallingEdge,
    ReadOnly,
    RisingEdge,
    with_timeout,
)

import runner
from runner import hdl_params, test_args
from seeding import make_rng

PERIOD_NS = 10

# (CLK_HZ, RATE_HZ, strobes to check)
CASES = [
    (48_000_000, 625_000, 3000),
    (32_000_000, 625_000, 3000),
    (12_000_000, 625_000, 3000),
    (2_000_000, 625_000, 4000),
    (33_333_333, 625_000, 3000),
    (2_000_003, 625_000, 4000),
    (48_000_000, 10_000, 60),
    (12_000_000, 10_000, 60),     # GP 1.0's poll; RATE divides CLK here and around: the LFSR divider
    (2_000_000, 1_000_000, 4000),  # MOD 2
    (2_000_003, 10_000, 600),
    (48_000_000, 0, 0),
    (2_000_000, 0, 0),
]
BUILDS = {f"clk{c}-rate{r}": {"CLK_HZ": c, "RATE_HZ": r} for c, r, _ in CASES}
STROBES = {f"clk{c}-rate{r}": n for c, r, n in CASES}
RATED = [b for b, p in BUILDS.items() if p["RATE_HZ"]]
UNRATED = [b for b, p in BUILDS.items() if not p["RATE_HZ"]]


def now_ns() -> int:
    return int(round(get_sim_time("ns")))


class TickGenTB:
    def __init__(self, dut):
        self.dut = dut
        self.clk_hz = int(hdl_params()["CLK_HZ"])
        self.rate_hz = int(hdl_params()["RATE_HZ"])
        self.ticks = int(test_args().get("strobes", 0))
        self.clock = Clock(dut.clk, PERIOD_NS, unit="ns", impl="gpi")
        dut.rst.value = 1
        self.clock.start(start_high=False)  # first rising edge at PERIOD/2, rst already 1

    async def reset(self, cycles: int = 3) -> int:
        """Hold rst for `cycles` rising edges (tick_o must be 0 after each), release it
        on the following falling edge; return the sim time (ns) of edge 0, the last
        rising edge that sampled rst = 1."""
        dut = self.dut
        dut.rst.value = 1
        for _ in range(cycles):
            await RisingEdge(dut.clk)
            await ReadOnly()
            assert int(dut.tick_o.value) == 0, "tick_o must be 0 while in reset"
        await FallingEdge(dut.clk)
        dut.rst.value = 0
        return now_ns() - PERIOD_NS // 2

    @staticmethod
    def edge_index(t: int, t0: int) -> int:
        d = t - t0
        assert d % PERIOD_NS == 0, f"tick_o changed off a clock edge (t={t} ns)"
        return d // PERIOD_NS

    async def collect(self, t0: int, count: int) -> None:
        """Wait for `count` strobes after edge 0 = t0 and check phase and width of each."""
        dut = self.dut
        clk, rate = self.clk_hz, self.rate_hz
        # Generous guard: 2 nominal tick periods per strobe.
        guard_ns = PERIOD_NS * (2 * clk // rate + 4)
        for k in range(1, count + 1):
            await with_timeout(RisingEdge(dut.tick_o), guard_ns, "ns")
            n = self.edge_index(now_ns(), t0)
            lag = n * rate - k * clk  # (n_k - k*CLK/RATE) * RATE
            assert 0 <= lag < rate, (
                f"strobe {k} at edge {n}: expected edge ceil({k}*{clk}/{rate}) = "
                f"{-(-k * clk // rate)} (phase error {lag / rate:+.4f} clocks)"
            )
            await with_timeout(FallingEdge(dut.tick_o), 4 * PERIOD_NS, "ns")
            m = self.edge_index(now_ns(), t0)
            assert m == n + 1, f"strobe {k} is {m - n} clocks wide, expected 1"


@cocotb.test(skip=not runner.on(*RATED))
async def test_phase_every_strobe(dut):
    """Every strobe one clock wide, at clock ceil(k*CLK/RATE) for all k of the run."""
    tb = TickGenTB(dut)
    t0 = await tb.reset()
    await tb.collect(t0, tb.ticks)
    dut._log.info(
        "%d strobes checked (CLK_HZ=%d RATE_HZ=%d)", tb.ticks, tb.clk_hz, tb.rate_hz
    )


@cocotb.test(skip=not runner.on(*RATED))
async def test_reset_mid_run_restarts_phase(dut):
    """A reset at a random clock restarts the phase grid from the new edge 0."""
    tb = TickGenTB(dut)
    rng = make_rng(dut, "reset_mid_run")
    t0 = await tb.reset()
    await tb.collect(t0, 3)
    per_tick = tb.clk_hz // tb.rate_hz
    for _ in range(3):
        await ClockCycles(dut.clk, rng.randrange(1, 3 * per_tick + 3))
        t0 = await tb.reset(rng.randrange(1, 5))
        await tb.collect(t0, 20)


@cocotb.test(skip=not runner.on(*UNRATED))
async def test_rate_zero_every_clock(dut):
    """RATE_HZ = 0: tick_o is 1 on every clock from edge 1 on, 0 in reset."""
    tb = TickGenTB(dut)
    rng = make_rng(dut, "rate_zero")
    for _ in range(3):
        await tb.reset(rng.randrange(1, 5))
        for n in range(1, 200):
            await RisingEdge(dut.clk)
            await ReadOnly()
            assert int(dut.tick_o.value) == 1, f"tick_o 0 at edge {n} with RATE_HZ=0"
        await RisingEdge(dut.clk)


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_tick_gen(sim: str, build: str) -> None:
    runner.run(sim, "bsd_tick_gen", __file__, BUILDS[build], build, args={"strobes": STROBES[build]})
