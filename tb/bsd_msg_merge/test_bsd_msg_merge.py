# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_msg_merge, and their pytest entry.

Checked against the block's header comment (the serial wrapper's cmdQOverflow merge,
docs/fpga.md) and AXI-Stream's rules: the message `A, MSG_N, CMD_MSG, CODE` goes out only
between packets of the stream (never after a packet's first byte has left and before its
tlast), whole once its first byte is offered, with the stream held (s_axis_tready 0) while
it goes; at a packet boundary a waiting message goes first unless a stream byte is already
offered and stalled (an offered byte stays offered until taken); done_o pulses with the
handshake of the message's last byte.

All outputs are combinational in the inputs, so the TB samples them in ReadOnly right after
driving (the values the next rising edge sees) and compares them with MergeModel on every
clock. Independently of the model it checks the output stream: m_axis stable while stalled,
every output packet either the next stream packet or the message, one done_o per message.
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from bsd_protocol import CMD_MSG, MSG_CMD_Q_OVERFLOW, MSG_CONFIG_ERR, MSG_N
from clocked_tb import ClockedTB
import runner
from runner import hdl_params

BUILDS = {
    "a2-qovf": {"MODULE_ADDR": 2, "CODE": f"8'd{MSG_CMD_Q_OVERFLOW}"},
    "a254-cfgerr": {"MODULE_ADDR": 254, "CODE": f"8'd{MSG_CONFIG_ERR}"},
}


class MergeModel:
    def __init__(self, addr: int, code: int) -> None:
        self.msg = [addr, MSG_N, CMD_MSG, code]
        self.reset()

    def reset(self) -> None:
        self.in_packet = False   # a stream packet is part-way out
        self.stalled = False     # a stream byte was offered on m_axis and not taken
        self.pos: int | None = None  # message byte on offer, once the message has started

    def outputs(self, v: dict) -> dict[str, int]:
        start = v["req_i"] and not self.in_packet and not self.stalled and self.pos is None
        if self.pos is not None or start:
            pos = self.pos or 0
            return dict(m_axis_tvalid=1, m_axis_tdata=self.msg[pos], m_axis_tlast=int(pos == 3),
                        s_axis_tready=0, done_o=int(v["m_axis_tready"] and pos == 3))
        return dict(m_axis_tvalid=v["s_axis_tvalid"], m_axis_tdata=v["s_axis_tdata"],
                    m_axis_tlast=v["s_axis_tlast"], s_axis_tready=v["m_axis_tready"], done_o=0)

    def edge(self, v: dict, out: dict) -> None:
        msg = self.pos is not None or self._started(v)
        self.stalled = not msg and bool(v["s_axis_tvalid"]) and not v["m_axis_tready"]
        if msg:
            pos = self.pos or 0
            if v["m_axis_tready"]:
                pos += 1
            self.pos = None if pos == 4 else pos
        elif v["s_axis_tvalid"] and v["m_axis_tready"]:
            self.in_packet = not v["s_axis_tlast"]

    def _started(self, v: dict) -> bool:
        return bool(v["req_i"]) and not self.in_packet and not self.stalled and self.pos is None


class MergeTB(ClockedTB):
    INPUTS = dict(req_i=0, s_axis_tdata=0, s_axis_tvalid=0, s_axis_tlast=0, m_axis_tready=1)
    OUTPUTS = ("done_o", "s_axis_tready", "m_axis_tdata", "m_axis_tvalid", "m_axis_tlast")

    def __init__(self, dut) -> None:
        super().__init__(dut, "msg_merge")
        p = hdl_params()
        self.model = MergeModel(int(p["MODULE_ADDR"]), int(str(p["CODE"]).split("d")[-1]))
        self.clocks = 0
        self.packets: list[list[int]] = []   # stream packets offered, in order
        self.queue: list[list[int]] = []     # bytes still to offer, per packet
        self.p_valid = 1.0
        self.req = 0
        self.out_bytes: list[int] = []
        self.out_packets: list[list[int]] = []
        self.dones = 0
        self.prev: dict | None = None
        self.prev_out: dict = {}
        self.prev_taken = False

    def add_packet(self, pkt: list[int]) -> None:
        self.packets.append(list(pkt))
        self.queue.append(list(pkt))

    async def step(self, rst: int = 0, **inputs: int) -> dict[str, int]:
        """One clock; the stream source and req_i follow the handshakes (AXI: an offered
        byte stays until taken; req_i stays up until done_o)."""
        await FallingEdge(self.clk)
        offering = self.prev is not None and self.prev["s_axis_tvalid"] and not self.prev_taken
        if offering:
            s = dict(s_axis_tvalid=1)
        elif self.queue and self.rng.random() < self.p_valid:
            s = dict(s_axis_tvalid=1, s_axis_tdata=self.queue[0][0],
                     s_axis_tlast=int(len(self.queue[0]) == 1))
        else:
            s = dict(s_axis_tvalid=0)
        s["req_i"] = self.req
        s.update(inputs)
        vals = self.drive(rst, **s)
        await ReadOnly()
        self.clocks += 1
        if rst:
            out = {}
            self.model.reset()
            self.prev, self.prev_taken = None, False
        else:
            out = self.sample()
            exp = self.model.outputs(vals)
            assert out == exp, f"clock {self.clocks} {vals}: DUT {out} != model {exp}"
            self.observe(vals, out)
            self.model.edge(vals, out)
        await RisingEdge(self.clk)
        return out

    def observe(self, v: dict, out: dict) -> None:
        p = self.prev_out if self.prev is not None else None
        if p is not None and p["m_axis_tvalid"] and not self.prev["m_axis_tready"]:
            held = {k: out[k] for k in ("m_axis_tvalid", "m_axis_tdata", "m_axis_tlast")}
            was = {k: p[k] for k in held}
            assert held == was, f"clock {self.clocks}: m_axis moved while stalled: {was} -> {held}"
        taken = bool(v["s_axis_tvalid"] and out["s_axis_tready"])
        if taken:
            self.queue[0].pop(0)
            if not self.queue[0]:
                self.queue.pop(0)
        if out["m_axis_tvalid"] and v["m_axis_tready"]:
            self.out_bytes.append(out["m_axis_tdata"])
            if out["m_axis_tlast"]:
                self.out_packets.append(self.out_bytes)
                self.out_bytes = []
        if out["done_o"]:
            self.dones += 1
            self.req = 0
        self.prev, self.prev_out, self.prev_taken = dict(v), dict(out), taken

    def check_stream(self) -> int:
        """Output packets = the stream's packets in order with whole messages between."""
        msgs = [p for p in self.out_packets if p == self.model.msg]
        rest = [p for p in self.out_packets if p != self.model.msg]
        assert rest == self.packets[:len(rest)], f"stream packets changed: {rest[:4]}"
        assert len(msgs) == self.dones, f"{len(msgs)} messages, {self.dones} done pulses"
        return len(msgs)


@cocotb.test()
async def test_message_alone(dut) -> None:
    """With an idle stream the message goes out at once, whole, the stream held meanwhile;
    done_o with its last handshake; stalls in the middle hold it."""
    tb = MergeTB(dut)
    await tb.reset()
    tb.req = 1
    for ready in (1, 1, 0, 0, 1, 0, 1):
        out = await tb.step(m_axis_tready=ready)
        assert out["m_axis_tvalid"] == 1 and out["s_axis_tready"] == 0
    assert tb.out_packets == [tb.model.msg] and tb.dones == 1
    assert (await tb.step(m_axis_tready=1))["m_axis_tvalid"] == 0
    tb.check_stream()


@cocotb.test()
async def test_between_packets(dut) -> None:
    """A message requested while a stream packet is part-way out waits for its tlast, then
    goes before the next packet; a byte gap inside the packet does not let it in."""
    tb = MergeTB(dut)
    await tb.reset()
    tb.add_packet([2, 3, 0x1A, 3, 1])
    tb.add_packet([2, 0])
    await tb.step()                              # first byte of packet 1 leaves
    tb.req = 1
    await tb.step(s_axis_tvalid=0)               # gap: still inside the packet
    out = await tb.step(s_axis_tvalid=0)
    assert out["m_axis_tvalid"] == 0, "message started inside a packet"
    for _ in range(12):
        await tb.step()
    assert tb.out_packets == [[2, 3, 0x1A, 3, 1], tb.model.msg, [2, 0]]
    tb.check_stream()


@cocotb.test()
async def test_stalled_byte_not_switched(dut) -> None:
    """A stream byte offered while m_axis_tready is 0 stays on m_axis: a message requested
    meanwhile waits for the next boundary."""
    tb = MergeTB(dut)
    await tb.reset()
    tb.add_packet([2, 2, 0x80, 9])
    tb.add_packet([2, 1, 0x17])
    out = await tb.step(m_axis_tready=0)         # first byte offered, stalled
    assert out["m_axis_tdata"] == 2
    tb.req = 1
    for _ in range(3):
        out = await tb.step(m_axis_tready=0)
        assert (out["m_axis_tvalid"], out["m_axis_tdata"]) == (1, 2)
    for _ in range(12):
        await tb.step(m_axis_tready=1)
    assert tb.out_packets == [[2, 2, 0x80, 9], tb.model.msg, [2, 1, 0x17]]
    # at a boundary with no stalled byte the message goes before an offered one
    tb.add_packet([2, 0])
    tb.req = 1
    for _ in range(8):
        await tb.step()
    assert tb.out_packets[-2:] == [tb.model.msg, [2, 0]]
    tb.check_stream()


@cocotb.test()
async def test_random_vs_model(dut) -> None:
    """Random packets, gaps, back-pressure and message requests, model checked every clock."""
    tb = MergeTB(dut)
    rng = tb.rng
    await tb.reset()
    for _ in range(150):
        n = rng.randrange(0, 5)
        tb.add_packet([rng.randrange(256) for _ in range(n + 2)])
    requests = 0
    # Runs until the stream is drained and at least 10 messages were asked for, so no seed
    # leaves the message path unexercised.
    for _ in range(20000):
        if tb.req == 0 and rng.random() < 0.02:
            tb.req = 1
            requests += 1
        tb.p_valid = rng.choice([1.0, 1.0, 0.5])
        await tb.step(m_axis_tready=int(rng.random() < 0.7))
        if not tb.queue and requests >= 10:
            break
    assert not tb.queue and requests >= 10, "stream not drained in 20000 clocks"
    while tb.req:
        await tb.step(m_axis_tready=1)
    await tb.step(m_axis_tready=1)
    msgs = tb.check_stream()
    assert len(tb.out_packets) - msgs == len(tb.packets)
    assert msgs == requests, f"{requests} requests, {msgs} messages"


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_msg_merge(sim: str, build: str) -> None:
    runner.run(sim, "bsd_msg_merge", __file__, BUILDS[build], build)
