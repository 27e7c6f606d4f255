"""Time-based behaviour of the whole core on both simulators: timer accuracy across clock
rates, the heartbeat and link_up, and the transition latch with and without polling.

    .venv/bin/python -m pytest -n 2 tb/test_timing.py -q
"""

from __future__ import annotations

import pytest

import runner
from bsd_model import PARAMS_ENV, Params

SIMS = pytest.mark.parametrize("sim", runner.SIMULATORS)


def run_top(sim: str, module: str, params: Params, **env: str) -> None:
    runner.run(sim, "brainstem_dio", module, params.to_hdl(),
               extra_env={PARAMS_ENV: params.to_json(), **env})


# (CLK_HZ, intervals, longest interval): 220 intervals in all on Verilator; the long ones
# (to the 104.86 ms limit) at the low clock, where they cost the fewest cycles. Icarus,
# some ten times slower, runs half as many at the high clocks.
ACCURACY = [
    (48_000_000, 80, 3e-3),
    (32_000_000, 60, 3e-3),
    (2_000_000, 80, 104e-3),
]
ICARUS_SHARE = {48_000_000: 0.5, 32_000_000: 0.5, 2_000_000: 1.0}


@SIMS
@pytest.mark.parametrize("clk_hz,count,max_s", ACCURACY, ids=[f"clk{c}" for c, _, _ in ACCURACY])
def test_timer_accuracy(sim: str, clk_hz: int, count: int, max_s: float) -> None:
    if sim == "icarus":
        count = round(count * ICARUS_SHARE[clk_hz])
    run_top(sim, "timer_accuracy_tests", Params(clk_hz=clk_hz),
            BSD_TIMER_COUNT=str(count), BSD_TIMER_MAX_S=str(max_s))


@SIMS
@pytest.mark.parametrize("hb_rate", [1, 0], ids=["hb1", "hb_off"])
def test_heartbeat(sim: str, hb_rate: int) -> None:
    run_top(sim, "heartbeat_tests", Params(clk_hz=2_000_000, hb_rate=hb_rate))


@SIMS
@pytest.mark.parametrize("poll_hz", [10_000, 0], ids=["poll10k", "poll_every_clock"])
def test_transition_latch(sim: str, poll_hz: int) -> None:
    run_top(sim, "latch_tests", Params(clk_hz=8_000_000, poll_hz=poll_hz))
