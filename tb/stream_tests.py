"""cocotb tests of the stream buffers bsd_axis_skid and bsd_fifo (run from tb/test_blocks.py).

Both are checked against the same reference: a queue of at most CAPACITY words (2 for the
skid buffer, DEPTH + 1 for the FIFO) in which words leave in order, none lost or repeated.
The environment gives the block (BSD_STREAM = skid | fifo), WIDTH and for the FIFO DEPTH.

Inputs are driven on the falling edge; every clock, right before the rising edge
(ReadOnly), the test records which handshakes happen at that edge. It also checks that
s_axis_tready and m_axis_tvalid come from flops: changing the other side's inputs in the
middle of a clock must not move them.
"""

from __future__ import annotations

import os
from collections import deque

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge, Timer

from seeding import make_rng

PERIOD_NS = 10
BLOCK = os.environ.get("BSD_STREAM", "skid")
WIDTH = int(os.environ.get("BSD_WIDTH", "8"))
DEPTH = int(os.environ.get("BSD_DEPTH", "4"))
CAPACITY = 2 if BLOCK == "skid" else DEPTH + 1


class StreamTB:
    def __init__(self, dut) -> None:
        self.dut = dut
        self.sent: deque[int] = deque()  # accepted, not yet delivered
        self.delivered = 0
        dut.rst.value = 1
        dut.s_axis_tvalid.value = 0
        dut.s_axis_tdata.value = 0
        dut.m_axis_tready.value = 0
        Clock(dut.clk, PERIOD_NS, unit="ns", impl="gpi").start(start_high=False)

    async def reset(self) -> None:
        for _ in range(2):
            await FallingEdge(self.dut.clk)
        self.dut.rst.value = 0
        self.sent.clear()

    async def step(self, tvalid: int, tdata: int, tready: int) -> tuple[bool, bool]:
        """One clock: drive, check the flop-only outputs, apply the handshakes."""
        d = self.dut
        await FallingEdge(d.clk)
        d.s_axis_tvalid.value = tvalid
        d.s_axis_tdata.value = tdata
        d.m_axis_tready.value = 1 - tready
        await Timer(1, unit="ns")
        before = (int(d.s_axis_tready.value), int(d.m_axis_tvalid.value))
        d.m_axis_tready.value = tready
        await Timer(1, unit="ns")
        after = (int(d.s_axis_tready.value), int(d.m_axis_tvalid.value))
        assert before == after, "s_axis_tready / m_axis_tvalid follow m_axis_tready combinationally"
        await ReadOnly()
        s_ready = int(d.s_axis_tready.value)
        m_valid = int(d.m_axis_tvalid.value)
        took = bool(tvalid and s_ready)
        gave = bool(m_valid and tready)
        if gave:
            assert self.sent, "a word came out that was never put in"
            want = self.sent.popleft()
            got = int(d.m_axis_tdata.value)
            assert got == want, f"word {self.delivered}: got {got:#x}, expected {want:#x}"
            self.delivered += 1
        if took:
            self.sent.append(tdata)
        assert len(self.sent) <= CAPACITY, f"{len(self.sent)} words inside, capacity {CAPACITY}"
        await RisingEdge(d.clk)
        return took, gave


@cocotb.test()
async def test_random_traffic(dut) -> None:
    """Random tvalid/tready: every word comes out once, in order, and the buffer never
    holds more than its capacity."""
    tb = StreamTB(dut)
    rng = make_rng(dut, f"{BLOCK} random traffic")
    await tb.reset()
    word = 0
    for p_valid, p_ready in ((0.9, 0.9), (0.9, 0.2), (0.2, 0.9), (0.5, 0.5), (1.0, 1.0)):
        for _ in range(400):
            v = int(rng.random() < p_valid)
            took, _ = await tb.step(v, word & ((1 << WIDTH) - 1), int(rng.random() < p_ready))
            if took:
                word += rng.randrange(1, 1 << WIDTH)
    while tb.sent:
        await tb.step(0, 0, 1)
    assert tb.delivered > 500


@cocotb.test()
async def test_full_rate_and_capacity(dut) -> None:
    """With the output always ready a word moves every clock; with the output stalled the
    buffer takes exactly CAPACITY words, then holds tready low until a word leaves."""
    tb = StreamTB(dut)
    await tb.reset()
    # Let the buffer settle empty, then stream: after the first word appears, one per clock.
    gaps, last = [], None
    for i in range(60):
        took, gave = await tb.step(1, i, 1)
        assert took, f"clock {i}: input refused while the output is always ready"
        if gave:
            if last is not None:
                gaps.append(i - last)
            last = i
    assert gaps and set(gaps) == {1}, f"output gaps {sorted(set(gaps))}"
    while tb.sent:
        await tb.step(0, 0, 1)
    taken = 0
    for i in range(CAPACITY + 5):
        took, _ = await tb.step(1, 0x40 + i, 0)
        taken += took
    assert taken == CAPACITY, f"took {taken} words with the output stalled, capacity {CAPACITY}"
    assert int(dut.s_axis_tready.value) == 0
    took, gave = await tb.step(1, 0x40 + taken, 1)
    assert gave
    while tb.sent:
        await tb.step(0, 0, 1)


@cocotb.test(skip=BLOCK != "fifo")
async def test_fifo_empty_flag(dut) -> None:
    """empty_o is 1 exactly when no word is inside (the RAM and the output register)."""
    tb = StreamTB(dut)
    rng = make_rng(dut, "fifo empty flag")
    await tb.reset()
    for _ in range(600):
        await tb.step(int(rng.random() < 0.4), rng.randrange(1 << WIDTH), int(rng.random() < 0.6))
        await ReadOnly()
        assert int(dut.empty_o.value) == int(not tb.sent), f"empty_o with {len(tb.sent)} words inside"
