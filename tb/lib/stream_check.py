# SPDX-License-Identifier: Apache-2.0
"""Checks shared by the stream buffers' tests (tb/bsd_axis_skid/, tb/bsd_fifo/).

Both are checked against the same reference: a queue of at most `capacity` words (2 for the
skid buffer, DEPTH + 2 for the FIFO) in which words leave in order, none lost or repeated.

Inputs are driven on the falling edge; every clock, right before the rising edge
(ReadOnly), the test records which handshakes happen at that edge. It also checks that
s_axis_tready and m_axis_tvalid come from flops: changing the other side's inputs in the
middle of a clock must not move them.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Mapping

from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge, Timer

from clocked_tb import ClockedTB


class StreamTB(ClockedTB):
    """step() also pokes m_axis_tready within its clock (the flop-only check), so it is its
    own; the base class gives the clock, the reset and the seeded rng."""

    INPUTS: Mapping[str, int] = {"s_axis_tvalid": 0, "s_axis_tdata": 0, "m_axis_tready": 0}

    def __init__(self, dut, width: int, capacity: int) -> None:
        super().__init__(dut, f"{dut._name} w{width} c{capacity}")
        self.width = width
        self.capacity = capacity
        self.sent: deque[int] = deque()  # accepted, not yet delivered
        self.delivered = 0

    async def reset(self, cycles: int = 2) -> None:
        for _ in range(cycles):
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
        assert len(self.sent) <= self.capacity, (f"{len(self.sent)} words inside, "
                                                 f"capacity {self.capacity}")
        await RisingEdge(d.clk)
        return took, gave


async def random_traffic(tb: StreamTB) -> None:
    """Random tvalid/tready: every word comes out once, in order, and the buffer never
    holds more than its capacity."""
    rng, WIDTH = tb.rng, tb.width
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


async def full_rate_and_capacity(tb: StreamTB) -> None:
    """With the output always ready a word moves every clock; with the output stalled the
    buffer takes exactly its capacity, then holds tready low until a word leaves."""
    dut, CAPACITY = tb.dut, tb.capacity
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
