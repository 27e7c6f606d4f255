# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_timeout_wheel, and their pytest entry.

Checked against PROTOCOL.md §4.2 (a measurement times out 65 535 ticks after its start) and
the block's header comment: on every tick, for every running timer, expire_o names it
exactly when that tick brings T to T_start - 1 (T_start: T including the start clock's
tick); never for a timer that finished and was started again (the restart race), whatever
the clock of the restart relative to the scan. Ticks come every 3rd clock (2 MHz, the
fewest clocks per tick the core allows), T is driven as bsd_timer_bank's count.
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from clocked_tb import ClockedTB
import runner
from runner import hdl_params

# t12: a scanner lap of 12 clocks, a multiple of the 3-clock tick period, so the same timers
# meet the slot-clearing clock on every lap (an insert that lost the write port must wait).
# t12-deep: the same build, for the runs make test leaves to make test-full.
# t40: three of the wheel's 16-timer RAMs, the last one 8 wide (an insert writes only its
# timer's RAM).
BUILDS = {"t4": {"NUM_TIMERS": 4}, "t12": {"NUM_TIMERS": 12}, "t12-deep": {"NUM_TIMERS": 12},
          "t40": {"NUM_TIMERS": 40}}
TIMEOUT = 65535


class WheelTB(ClockedTB):
    INPUTS = dict(tick_i=0, t_i=0, start_i=0, start_any_i=0, start_idx_i=0, run_i=0)
    OUTPUTS = ("expire_o",)

    def __init__(self, dut) -> None:
        super().__init__(dut, "wheel")
        self.n = int(hdl_params()["NUM_TIMERS"])
        self.t = 0
        self.run = [False] * self.n
        self.start_t = [0] * self.n
        self.clock = 0
        self.timeouts = 0
        self.races = 0

    async def clk1(self, start: int | None = None, finish: tuple[int, ...] = ()) -> None:
        """One clock: a tick every 3rd, `start` (an idle timer) starts, `finish` complete."""
        tick = int(self.clock % 3 == 0)
        run = sum(1 << k for k in range(self.n) if self.run[k])
        await FallingEdge(self.clk)
        self.drive(0, tick_i=tick, t_i=self.t, start_i=(1 << start) if start is not None else 0,
                   start_any_i=int(start is not None), start_idx_i=start or 0, run_i=run)
        await ReadOnly()
        exp = int(self.dut.expire_o.value)
        await RisingEdge(self.clk)
        now = (self.t + tick) & 0xFFFF
        for k in range(self.n if tick else 0):
            if not self.run[k]:
                continue
            due = now == (self.start_t[k] - 1) & 0xFFFF
            got = bool(exp >> k & 1)
            assert got == due, (f"clock {self.clock}: timer {k} started at T={self.start_t[k]}, "
                                f"tick to T={now}: expire {int(got)}, timeout due {int(due)}")
            if due:
                self.run[k] = False
                self.timeouts += 1
        for k in finish:
            self.run[k] = False
        if start is not None:
            assert not self.run[start]
            self.run[start] = True
            self.start_t[start] = now
        self.t = now
        self.clock += 1


# A long run simulates the ticks near its events only: T (an input here) jumps ahead while no
# timer is within MARGIN ticks of its timeout (none is marked: a running timer is marked 62 ticks
# before) and 100 ticks have passed since the last start, finish or timeout or a pending start. The core's T never jumps, so the wheel
# reads every slot once in 64 ticks; the last condition keeps that for the slots a jump would
# skip: a finished run's bit (due at most 60 ticks after its finish) has been read and cleared.
# An idle timer's bit (written near its last start's T, mod 65 536) may outlive a jump, but a
# mark follows at least MARGIN - 62 ticks without a jump, in which every slot is read and cleared.
MARGIN = 150


def skip_ahead(tb: WheelTB, last_event: int) -> int:
    """Jump T to MARGIN ticks before the next timeout, if the run allows (above); the ticks
    jumped."""
    if tb.clock % 3 != 1 or tb.clock - last_event < 3 * 100:
        return 0
    left = [((tb.start_t[k] - 1) - tb.t) & 0xFFFF for k in range(tb.n) if tb.run[k]]
    if not left or min(left) <= MARGIN:
        return 0
    jump = min(left) - MARGIN
    tb.t = (tb.t + jump) & 0xFFFF
    return jump


# The 12-timer build's run of it is deep (make test-full): make test keeps the 4-timer one.
@cocotb.test(skip=not runner.on("t4", "t12-deep"))
async def test_timeouts_and_restarts(dut) -> None:
    """Timers started at random clocks time out exactly on their 65 535th tick; others
    complete early, some a few ticks before their timeout (inside the wheel's window, after
    their insertion); either kind starts again at once or a few clocks later, and the new run
    never times out at the old one's time. Eight timeouts' worth of ticks, most of them jumped
    (skip_ahead)."""
    tb = WheelTB(dut)
    await tb.reset()
    rng, n = tb.rng, tb.n
    # In the first round timers 0 and 1 time out and every other one ends shortly before its
    # timeout (so every seed has both kinds); later rounds choose at random.
    early = {k: k >= 2 for k in range(n)}
    first = [True] * n
    cut = {k: rng.randrange(1, 60) for k in range(n)}
    next_start = [rng.randrange(0, 3000) for _ in range(n)]
    ticks = last_event = timeouts = 0
    while ticks < 8 * (TIMEOUT + 2000):
        c = tb.clock
        ticks += c % 3 == 0
        start = None
        finish = []
        for k in range(n):
            if tb.run[k]:
                left = ((tb.start_t[k] - 1) - tb.t) & 0xFFFF
                if early[k] and 0 < left <= cut[k] and tb.clock % 3 == 1:
                    finish.append(k)
                    tb.races += 1
                    next_start[k] = c + rng.choice([1, 2, 3, 5, 40])
            elif start is None and c >= next_start[k]:
                start = k
                early[k] = k >= 2 if first[k] else rng.random() < 0.5
                first[k] = False
                cut[k] = rng.randrange(1, 60)
                next_start[k] = 1 << 40
        # the exec starts at most one timer a clock, and a finished one only on a later clock
        if start is not None and start in finish:
            start = None
        waiting = any(next_start[k] < 1 << 40 for k in range(n) if not tb.run[k])
        if start is not None or finish or waiting or tb.timeouts > timeouts:
            last_event, timeouts = c, tb.timeouts
        ticks += skip_ahead(tb, last_event)
        running = list(tb.run)
        await tb.clk1(start, tuple(finish))
        for k in range(n):
            if running[k] and not tb.run[k] and k not in finish:       # timed out
                next_start[k] = tb.clock + rng.choice([1, 2, 3, 5, 40])
    tb.log.info("%d timeouts, %d finished in the window, %d clocks", tb.timeouts, tb.races, tb.clock)
    assert tb.timeouts >= 2 and tb.races >= 2, (tb.timeouts, tb.races)


@cocotb.test()
async def test_all_at_once(dut) -> None:
    """Every timer started on consecutive clocks (so several share a tick): all of them
    time out, each on its own tick, none early or late. The 4-timer build runs every tick of
    the 65 535 (a timer that fires early anywhere is caught); the others jump T (skip_ahead)."""
    tb = WheelTB(dut)
    await tb.reset()
    n = tb.n
    for k in range(n):
        await tb.clk1(k)
    last_start = tb.clock
    while any(tb.run):
        if not runner.on("t4"):
            skip_ahead(tb, last_start)
        await tb.clk1()
    assert tb.timeouts == n


@cocotb.test(skip=not runner.on("t4", "t12"))
async def test_every_slot_every_timer(dut) -> None:
    """Every timer is inserted into (and cleared from) each of the 64 wheel slots: 64 rounds,
    round r starts every timer on consecutive clocks from T = 64 * r + r (so round r's
    timers land in slots r, r + 1, ...), then (the starts stored) T jumps (t_i is an input) to 80 ticks before
    their timeouts, and every timer must time out on its own tick (checked by clk1).
    Deterministic: each slot's bit of each timer is set and cleared whatever the seed."""
    tb = WheelTB(dut)
    await tb.reset()
    n = tb.n
    for r in range(64):
        while tb.clock % 3 != 0:                       # start on a tick's clock
            await tb.clk1()
        tb.t = (64 * r + r - 1) & 0xFFFF                # this clock's tick makes T = 65 r
        for k in range(n):
            await tb.clk1(k)
        for _ in range(6):                              # the last start's T is stored
            await tb.clk1()
        tb.t = (min(tb.start_t) - 1 - 80) & 0xFFFF
        for _ in range(3 * 200):
            await tb.clk1()
            if not any(tb.run):
                break
        assert not any(tb.run), f"round {r}: timers {[k for k in range(n) if tb.run[k]]} never timed out"
    assert tb.timeouts == 64 * n, tb.timeouts


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="verilator", deep=["t12-deep"]))
def test_bsd_timeout_wheel(sim: str, build: str) -> None:
    runner.run(sim, "bsd_timeout_wheel", __file__, BUILDS[build], build)
