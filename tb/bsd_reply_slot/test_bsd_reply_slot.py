# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_reply_slot, and their pytest entry.

Checked against DESIGN.md decision 2 (one command reply/message can wait at a time; while
it waits, or a packet is on its way through the executor, the parser must hold),
PROTOCOL.md §6 (the power-up message `A, 2, 0x80, statePowerReset` is the first packet out)
and the block's header comment: stage 2's reply becomes the request on the next clock (3
clocks after the last byte) and stays until rep_done_i; rep_new_o (the event queue's reply
bit) is the clock the request rises; a DIG_IO RFLX value is an event of the clock after
dio_rflx_i (dio_new_o with its ID and level) and never holds anything; hold_o (a flop) = a
packet in stage 2, or the slot full, or the clock after soft_reset_i (a cmdRESET in stage 2:
the core's reset, which fills the slot, comes on that clock); the packet's own clock needs no
hold, as the parser hands packets over at least two clocks apart (its proof asserts it).

SlotModel is that text; all outputs are sampled before each rising edge and compared with
it on every clock. The system test plays the parser (a packet only after a clock with hold_o
0 and no packet), bsd_exec (stage 2 one clock after the packet, with a random decision) and
the consumers (random done pulses), and checks that no reply or value is ever overwritten or lost.
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from bsd_protocol import CMD_MSG, MSG_N, MSG_STATE_POWER_RESET
from clocked_tb import ClockedTB
import runner

BUILDS = {"default": {}}
POWER_UP = (MSG_N, [CMD_MSG, MSG_STATE_POWER_RESET])


def word(data: list[int]) -> int:
    return sum(b << (24 - 8 * j) for j, b in enumerate(data))


class SlotModel:
    def __init__(self) -> None:
        self.reset()

    def reset(self, swap: bool = False) -> None:
        self.decided = False          # stage 2 chose a reply last clock
        self.waiting = True           # the reply slot is full (the power-up message)
        # the clock after reset: the power-up message's event, unless the transmitter
        # sends it already (swap_i with the reset: a cmdRESET met a packet on offer)
        self.boot = not swap
        self.reply: tuple[int, list[int]] = POWER_UP
        self.dio: tuple[int, int] | None = None   # a DIG_IO RFLX event this clock
        self.in_stages = True         # hold after reset until the power-up message left

    @property
    def rep_req(self) -> bool:
        return self.decided or self.waiting

    def outputs(self, v: dict) -> dict:
        o = dict(hold_o=int(self.in_stages), rep_req_o=int(self.rep_req),
                 rep_new_o=int(self.decided or self.boot), dio_new_o=int(self.dio is not None))
        if self.rep_req:
            o.update(rep_n_o=self.reply[0], _rep=self.reply[1][:self.reply[0]])
        if self.dio is not None:
            o.update(dio_id_o=self.dio[0], dio_val_o=self.dio[1])
        return o

    def edge(self, v: dict) -> None:
        waiting = self.rep_req and not v["rep_done_i"]
        if v["s2_valid_i"] and not self.rep_req:
            n = v["reply_n_i"]
            self.reply = (n, [(v["reply_data_i"] >> (24 - 8 * j)) & 0xFF for j in range(4)])
        self.decided, self.waiting, self.boot = bool(v["reply_i"]), waiting, False
        self.dio = (v["dio_id_i"], v["dio_val_i"]) if v["dio_rflx_i"] else None
        self.in_stages = bool(v["pkt_valid_i"] or v["reply_i"] or waiting or v["soft_reset_i"])


class SlotTB(ClockedTB):
    INPUTS = dict(pkt_valid_i=0, soft_reset_i=0, swap_i=0, s2_valid_i=0, reply_i=0, reply_n_i=0, reply_data_i=0,
                  dio_rflx_i=0, dio_id_i=0, dio_val_i=0, rep_done_i=0)
    PULSES = ("pkt_valid_i", "soft_reset_i", "swap_i", "s2_valid_i", "reply_i", "dio_rflx_i", "rep_done_i")
    OUTPUTS = ("hold_o", "rep_req_o", "rep_new_o", "rep_n_o", "rep_data_o", "dio_new_o",
               "dio_id_o", "dio_val_o")

    def __init__(self, dut) -> None:
        super().__init__(dut, "reply_slot")
        self.model = SlotModel()
        self.clocks = 0

    async def step(self, rst: int = 0, **inputs: int) -> dict:
        await FallingEdge(self.clk)
        vals = self.drive(rst, **inputs)
        await ReadOnly()
        self.clocks += 1
        if rst:
            self.model.reset(bool(vals["swap_i"]))
            out: dict = {}
        else:
            out = self.sample()
            exp = self.model.outputs(vals)
            got = {k: out[k] for k in exp if not k.startswith("_")}
            if "_rep" in exp:
                got["_rep"] = [(out["rep_data_o"] >> (24 - 8 * j)) & 0xFF
                               for j in range(exp["rep_n_o"])]
            assert got == exp, f"clock {self.clocks} {vals}: DUT {got} != model {exp}"
            self.model.edge(vals)
        await RisingEdge(self.clk)
        return out

    def rep(self, out: dict) -> list[int]:
        return [(out["rep_data_o"] >> (24 - 8 * j)) & 0xFF for j in range(out["rep_n_o"])]


@cocotb.test()
async def test_power_up_message(dut) -> None:
    """After reset the slot holds `0x80, statePowerReset` and requests it, hold_o is 1 until
    it has left; then the slot is free and hold_o 0."""
    tb = SlotTB(dut)
    await tb.reset()
    for _ in range(5):
        out = await tb.step()
        assert out["rep_req_o"] == 1 and out["hold_o"] == 1
        assert (out["rep_n_o"], tb.rep(out)) == POWER_UP
    out = await tb.step(rep_done_i=1)
    assert out["rep_req_o"] == 1 and out["hold_o"] == 1
    out = await tb.step()
    assert out["rep_req_o"] == 0 and out["hold_o"] == 0


async def free(tb: SlotTB) -> None:
    await tb.reset()
    await tb.step(rep_done_i=1)
    await tb.step()
    await tb.step()


@cocotb.test()
async def test_reply_latency_and_hold(dut) -> None:
    """pkt_valid_i raises hold_o on the next clock (stage 2); stage 2's reply is requested on
    the next clock with its packet, held (and hold_o with it) until rep_done_i; a packet
    without a reply holds for stage 2 only."""
    tb = SlotTB(dut)
    await free(tb)
    out = await tb.step(pkt_valid_i=1)
    assert out["hold_o"] == 0
    out = await tb.step(s2_valid_i=1, reply_i=1, reply_n_i=3, reply_data_i=word([4, 5, 1, 0x55]))
    assert out["hold_o"] == 1 and out["rep_req_o"] == 0
    for _ in range(4):
        out = await tb.step()
        assert (out["rep_req_o"], out["hold_o"], out["rep_n_o"]) == (1, 1, 3)
        assert tb.rep(out) == [4, 5, 1]
    await tb.step(rep_done_i=1)
    out = await tb.step()
    assert out["rep_req_o"] == 0
    assert (await tb.step())["hold_o"] == 0
    # no reply: hold for stage 2, then free
    holds = [(await tb.step(pkt_valid_i=1))["hold_o"], (await tb.step(s2_valid_i=1))["hold_o"],
             (await tb.step())["hold_o"]]
    assert holds == [0, 1, 0], holds


@cocotb.test()
async def test_soft_reset_holds(dut) -> None:
    """A cmdRESET in stage 2 (soft_reset_i, no reply) holds the parser on the next clock,
    the clock of the core's reset, and only then."""
    tb = SlotTB(dut)
    await free(tb)
    holds = [(await tb.step(pkt_valid_i=1))["hold_o"],
             (await tb.step(s2_valid_i=1, soft_reset_i=1))["hold_o"],
             (await tb.step())["hold_o"], (await tb.step())["hold_o"]]
    assert holds == [0, 1, 1, 0], holds


@cocotb.test()
async def test_soft_reset_swap(dut) -> None:
    """A reset with swap_i (a cmdRESET whose flush made the packet on offer the power-up
    message) refills the slot with the power-up message, requested as after any reset, but
    gives it no event (rep_new_o 0): the transmitter sends it already. Without swap_i the
    same reset gives the event."""
    tb = SlotTB(dut)
    for swap in (1, 0, 1):
        await free(tb)
        await tb.step(pkt_valid_i=1)
        await tb.step(s2_valid_i=1, soft_reset_i=1)
        await tb.step(rst=1, swap_i=swap)
        out = await tb.step()
        assert (out["rep_new_o"], out["rep_req_o"]) == (1 - swap, 1), (swap, out)
        assert (out["rep_n_o"], tb.rep(out)) == POWER_UP


@cocotb.test()
async def test_rflx_value(dut) -> None:
    """A DIG_IO RFLX value is an event of exactly the clock after dio_rflx_i, with its ID
    and level, and holds nothing: hold_o only for the packet's stage 2."""
    tb = SlotTB(dut)
    await free(tb)
    for dio_id, val in ((0, 1), (9, 0), (40, 1), (63, 1)):
        assert (await tb.step(pkt_valid_i=1))["hold_o"] == 0
        out = await tb.step(s2_valid_i=1, dio_rflx_i=1, dio_id_i=dio_id, dio_val_i=val)
        assert out["dio_new_o"] == 0
        out = await tb.step()
        assert (out["dio_new_o"], out["dio_id_o"], out["dio_val_o"], out["hold_o"]) == \
            (1, dio_id, val, 0)
        assert (await tb.step())["dio_new_o"] == 0


@cocotb.test()
async def test_system_random(dut) -> None:
    """The parser hands a packet over only after a clock with hold_o 0 and no packet, stage 2 follows a clock later with
    a random reply and/or RFLX value, the transmitter takes replies after random delays:
    every reply comes out once, in order, none overwritten, and every RFLX value is an
    event once, in order."""
    tb = SlotTB(dut)
    rng = tb.rng
    await tb.reset()
    expect_rep: list[tuple[int, list[int]]] = [POWER_UP]
    expect_dio: list[tuple[int, int]] = []
    got_rep: list[tuple[int, list[int]]] = []
    got_dio: list[tuple[int, int]] = []
    pkt = s2 = False
    hist: list = []
    out = await tb.step()
    for _ in range(4000):
        kw: dict = {}
        s2, pkt = pkt, False   # stage 2 on the clock after the packet
        if s2:
            kw["s2_valid_i"] = 1
            if rng.random() < 0.6:
                n = rng.randrange(5)
                data = [rng.randrange(256) for _ in range(4)]
                kw.update(reply_i=1, reply_n_i=n, reply_data_i=word(data))
                assert not tb.model.rep_req, f"a reply decided while the slot is full {hist[-6:]}"
                expect_rep.append((n, data[:n]))
            if rng.random() < 0.3:
                v = (rng.randrange(64), rng.randrange(2))
                kw.update(dio_rflx_i=1, dio_id_i=v[0], dio_val_i=v[1])
                expect_dio.append(v)
        # the consumers, from the state of this clock (the model, checked equal to the DUT)
        m = tb.model
        if m.rep_req and rng.random() < 0.25:
            kw["rep_done_i"] = 1
            got_rep.append((m.reply[0], m.reply[1][:m.reply[0]]))
        if out.get("dio_new_o"):
            got_dio.append((out["dio_id_o"], out["dio_val_o"]))
        # the parser: a packet only on a clock after one with hold_o 0 and no packet
        if not out["hold_o"] and not s2 and rng.random() < 0.7:
            kw["pkt_valid_i"] = 1
            pkt = True
        out = await tb.step(rst=0, **kw)
        hist.append((tb.clocks, kw, out))
    assert got_rep == expect_rep[:len(got_rep)] and len(expect_rep) - len(got_rep) <= 1
    assert got_dio == expect_dio[:len(got_dio)] and len(expect_dio) - len(got_dio) <= 1
    assert len(got_rep) > 150 and len(got_dio) > 50, (len(got_rep), len(got_dio))


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_reply_slot(sim: str, build: str) -> None:
    runner.run(sim, "bsd_reply_slot", __file__, BUILDS[build], build)
