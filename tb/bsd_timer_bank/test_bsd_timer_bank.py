# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_timer_bank, and their pytest entry.

BankModel is PROTOCOL.md §4.2 and DESIGN.md decisions 3 and 4 per timer, clock by clock: a
start (only of an idle timer) latches the mode, the target and the delivery bits; edge mode
completes on the first clock at the target after a clock elsewhere (the start clock's level
counts), width mode first sees the pulse begin (non-target -> target) and completes when it
ends; expire_i on a tick is the timeout, a completion on that clock wins. Events (registered:
of the previous clock): a reference (ev_r alone) at an edge-mode start and at a pulse's
beginning, a completion (ev_f alone), a timeout (both, also when a pulse begins on that
clock), only for timers whose result goes somewhere; T counts ticks.
A timer is busy from its start until host_done_i names it (HOST set) or rflx_done_i does
(RFLX alone: with both bits bsd_drain never names it, the packet always ends after the
strobe). Every output is compared with the model on every clock.
"""

from __future__ import annotations

import cocotb
import pytest

from clocked_tb import ClockedTB
import runner
from runner import hdl_params

BUILDS = {"t4": {"NUM_TIMERS": 4}, "t64": {"NUM_TIMERS": 64}}


class BankModel:
    def __init__(self, n: int) -> None:
        self.n = n
        self.reset()

    def reset(self) -> None:
        n = self.n
        self.t = 0
        self.run = [0] * n
        self.mode = [0] * n
        self.tgt = [0] * n
        self.inp = [0] * n
        self.prev = [0] * n
        self.host = [0] * n  # the last start's HOST and RFLX bits
        self.rflx = [0] * n
        self.pend = [0] * n  # a result owed
        self.started = [0] * n
        self.tmo = [0] * n   # the run ended by timeout (for the tests' tallies)
        self.ev_r = [0] * n
        self.ev_f = [0] * n

    @staticmethod
    def vec(bits: list[int]) -> int:
        return sum(b << i for i, b in enumerate(bits))

    def outputs(self) -> dict:
        v = self.vec
        return dict(busy_o=v([r | p for r, p in zip(self.run, self.pend)]),
                    run_o=v(self.run), run_host_o=v(self.host), run_rflx_o=v(self.rflx),
                    ev_r_o=v(self.ev_r), ev_f_o=v(self.ev_f),
                    ev_any_o=int(any(self.ev_r) or any(self.ev_f)), t_o=self.t)

    def edge(self, i: dict) -> None:
        bit = lambda name, k: i[name] >> k & 1
        tick = i["tick_i"]
        for k in range(self.n):
            lvl = bit("level_i", k)
            at, was = lvl == self.tgt[k], self.prev[k] == self.tgt[k]
            run, mode, inp = self.run[k], self.mode[k], self.inp[k]
            complete = run and ((not mode and at and not was) or (mode and inp and not at))
            begin = run and mode and not inp and at and not was
            timeout = run and tick and bit("expire_i", k)
            finish = complete or timeout
            start = bit("start_i", k)
            deliver = self.pend[k]
            self.ev_r[k] = int(bool((start and not bit("mode_i", k) and (i["host_i"] or i["rflx_i"]))
                                    or (begin and deliver) or (timeout and not complete and deliver)))
            self.ev_f[k] = int(bool(finish and deliver))
            self.tmo[k] = 0 if start else int(bool(self.tmo[k] or (timeout and not complete)))
            if i["host_done_i"] and i["host_idx_i"] == k:
                self.pend[k] = 0
            if i["rflx_done_i"] and i["rflx_idx_i"] == k:
                self.pend[k] = 0
            if begin:
                self.inp[k] = 1
            if finish:
                self.run[k] = 0
            if start:
                self.run[k], self.inp[k] = 1, 0
                self.mode[k], self.tgt[k] = bit("mode_i", k), bit("target_i", k)
                self.host[k], self.rflx[k] = i["host_i"], i["rflx_i"]
                self.pend[k] = int(bool(i["host_i"] or i["rflx_i"]))
                self.started[k] = 1
            self.prev[k] = lvl
        self.t = (self.t + tick) & 0xFFFF


class BankTB(ClockedTB):
    INPUTS = dict(tick_i=0, level_i=0, start_i=0, mode_i=0, target_i=0, host_i=0, rflx_i=0,
                  expire_i=0, host_done_i=0, host_idx_i=0, rflx_done_i=0, rflx_idx_i=0)
    PULSES = ("tick_i", "start_i", "host_done_i", "rflx_done_i")
    OUTPUTS = ("busy_o", "run_o", "run_host_o", "run_rflx_o", "ev_r_o", "ev_f_o",
               "ev_any_o", "t_o")

    def __init__(self, dut) -> None:
        super().__init__(dut, "timer_bank")
        self.n = int(hdl_params()["NUM_TIMERS"])
        self.model = BankModel(self.n)
        self.clocks = 0

    # The outputs whose flops have no reset.
    UNRESET = ("run_host_o", "run_rflx_o")

    def sample(self) -> dict[str, int]:
        """run_host_o and run_rflx_o have no reset (unknown until a timer's first start):
        their unresolved bits read as 0 and only started timers' bits are compared. Every
        other output must resolve (Icarus: an X there fails the test)."""
        out = {}
        for k in self.OUTPUTS:
            v = getattr(self.dut, k).value
            if v.is_resolvable:
                out[k] = int(v)
            else:
                assert k in self.UNRESET, f"{k} is unresolved: {v}"
                out[k] = int(str(v).lower().replace("x", "0").replace("z", "0"), 2)
        return out

    def check(self, inputs, outputs, rst) -> None:
        self.clocks += 1
        if rst:
            self.model.reset()
            return
        self.model.edge(inputs)
        exp = self.model.outputs()
        outputs = dict(outputs)
        for k in ("run_host_o", "run_rflx_o"):
            outputs[k] &= self.model.vec(self.model.started)
        assert outputs == exp, f"clock {self.clocks} {inputs}: DUT {outputs} != model {exp}"


async def random_run(tb: BankTB, clocks: int, p_level: float, p_expire: float) -> dict:
    """Random pads, starts of idle timers, ticks every 3rd clock, expiries and deliveries;
    returns how often each outcome happened."""
    rng, n, m = tb.rng, tb.n, tb.model
    seen = dict(edge=0, width=0, timeout=0, delivered=0, ref=0)
    level = 0
    for c in range(clocks):
        kw: dict = dict(tick_i=int(c % 3 == 0))
        for k in range(n):
            if rng.random() < p_level:
                level ^= 1 << k
        kw["level_i"] = level
        kw["mode_i"] = rng.getrandbits(n)
        kw["target_i"] = rng.getrandbits(n)
        idle = [k for k in range(n) if not (m.run[k] or m.pend[k])]
        if idle and rng.random() < 0.3:
            k = rng.choice(idle)
            kw.update(start_i=1 << k, host_i=int(rng.random() < 0.6), rflx_i=int(rng.random() < 0.5))
        kw["expire_i"] = rng.getrandbits(n) if rng.random() < p_expire else 0
        waiting_h = [k for k in range(n) if m.pend[k] and m.host[k] and not m.run[k]]
        if waiting_h and rng.random() < 0.3:
            kw.update(host_done_i=1, host_idx_i=rng.choice(waiting_h))
            seen["delivered"] += 1
        waiting_r = [k for k in range(n) if m.pend[k] and m.rflx[k] and not m.host[k] and not m.run[k]
                     and not (kw.get("host_done_i") and kw["host_idx_i"] == k)]
        if waiting_r and rng.random() < 0.3:
            kw.update(rflx_done_i=1, rflx_idx_i=rng.choice(waiting_r))
        out = await tb.step(**kw)
        for k in range(n):
            if out["ev_f_o"] >> k & 1:
                seen["timeout" if m.tmo[k] else ("width" if m.mode[k] else "edge")] += 1
        seen["ref"] += bin(out["ev_r_o"]).count("1")
    return seen


@cocotb.test()
async def test_random_vs_model(dut) -> None:
    """Random pads, starts, ticks, expiries and deliveries: every output equals the model
    on every clock, and every outcome (edge, width, timeout, delivery) happens."""
    tb = BankTB(dut)
    await tb.reset()
    seen = await random_run(tb, 3000, 0.05, 0.02)
    assert all(v > 5 for v in seen.values()), seen


@cocotb.test()
async def test_busy_until_delivered(dut) -> None:
    """A timer stays busy after it finishes until its packet has left (host_done_i; with RFLX
    too its strobe came before) or, RFLX alone, its strobe was given (rflx_done_i); with
    neither bit until it finishes."""
    tb = BankTB(dut)
    await tb.reset()
    for host, rflx in ((1, 1), (1, 0), (0, 1), (0, 0)):
        await tb.step(level_i=0, target_i=1, mode_i=0)
        await tb.step(start_i=1, host_i=host, rflx_i=rflx, target_i=1)
        await tb.steps(3)
        out = await tb.step(level_i=1)                  # completes: the finish event
        assert out["run_o"] & 1 == 0 and out["ev_f_o"] & 1 == int(bool(host or rflx))
        out = await tb.step()
        assert out["ev_f_o"] == 0 and out["busy_o"] & 1 == int(bool(host or rflx))
        if host:
            out = await tb.step()
            assert out["busy_o"] & 1 == 1 and out["run_host_o"] & 1 == 1
            assert out["run_rflx_o"] & 1 == rflx
            out = await tb.step(host_done_i=1, host_idx_i=0)
        elif rflx:
            out = await tb.step(rflx_done_i=1, rflx_idx_i=0)
        assert out["busy_o"] & 1 == 0
        await tb.step(level_i=0)


@cocotb.test()
async def test_completion_wins_on_timeout_clock(dut) -> None:
    """A completion on the clock its timeout expires is a completion (ev_f alone), a timeout
    is ev_r and ev_f together."""
    tb = BankTB(dut)
    await tb.reset()
    await tb.step(level_i=0, target_i=1)
    await tb.step(start_i=0b11, host_i=1, target_i=1)   # timers 0 and 1, edge mode to 1
    await tb.steps(2)
    out = await tb.step(tick_i=1, expire_i=0b11, level_i=0b01)  # 0 completes, 1 times out
    assert out["ev_f_o"] & 0b11 == 0b11 and out["ev_r_o"] & 0b11 == 0b10


@cocotb.test()
async def test_pulse_begin_on_timeout_clock(dut) -> None:
    """A width-mode pulse that begins on the timeout clock: the run times out (ev_r and
    ev_f together, result 0), not a reference that would leave the timer waiting forever."""
    tb = BankTB(dut)
    await tb.reset()
    await tb.step(level_i=0)
    await tb.step(start_i=1, host_i=1, mode_i=1, target_i=1)
    await tb.steps(2)
    out = await tb.step(tick_i=1, expire_i=1, level_i=1)  # the pulse begins as it expires
    assert out["ev_r_o"] & 1 and out["ev_f_o"] & 1 and out["run_o"] & 1 == 0


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="verilator"))
def test_bsd_timer_bank(sim: str, build: str) -> None:
    runner.run(sim, "bsd_timer_bank", __file__, BUILDS[build], build)
