# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_tx, and their pytest entry.

Checked against PROTOCOL.md §2 and §5 (packets `A, N, d0..` leave whole, tlast on the last
byte, bytes of two packets never interleave, nothing dropped), DESIGN.md decision 1 (the
oldest waiting source first, same-clock ties by index), DESIGN.md "Latencies" (a packet
starts 3 clocks after its request rises at the earliest: the grant from registers, the
staging register, the output register; while one packet goes out the next is staged and
follows with no idle clock) and the block's header comment (a source keeps req and its
packet until done_o, which pulses with the handshake of its last byte).

The TB plays K sources as the top has them (a request from a register: up until done_o,
then down for at least a clock) and a sink with random back-pressure. TxModel is the
documented pipeline (age arbiter -> staged source -> output shift register); m_axis and
done_o are sampled before each rising edge and compared with it on every clock. The output
is also checked on its own: stable while stalled, each packet the whole packet of a source
that was waiting, packets in (birth clock, index) order.
"""

from __future__ import annotations

import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from bsd_protocol import CMD_MSG, MSG_STATE_POWER_RESET
from clocked_tb import ClockedTB
from runner import hdl_params
from suite import Suite, on

SUITE = Suite(__file__, "bsd_tx", {"k2": {"MODULE_ADDR": 2, "K": 2},
                                   "k7-a254-pu5": {"MODULE_ADDR": 254, "K": 7, "POWERUP_SRC": 5}},
              quick=on("icarus"))

POWER_UP = (CMD_MSG, MSG_STATE_POWER_RESET)  # the data bytes of the power-up message


class TxModel:
    def __init__(self, addr: int, k: int, powerup_src: int | None = None) -> None:
        self.addr, self.k, self.powerup_src = addr, k, powerup_src
        self.reset()

    def reset(self) -> None:
        self.out: list[int] = []          # bytes of the packet going out, first on offer
        self.cur: int | None = None       # its source
        self.first = False                # no byte of it taken yet
        self.staged: int | None = None    # the next packet's source
        self.done_prev = 0                # sources whose last byte left last clock
        self.prev_req = [0] * self.k
        self.birth: list[int | None] = [None] * self.k
        self.clock = 0

    def grant(self) -> int | None:
        busy = {self.cur, self.staged} | {i for i in range(self.k) if (self.done_prev >> i) & 1}
        cands = [i for i in range(self.k) if self.prev_req[i] and i not in busy]
        return min(cands, key=lambda i: (self.birth[i], i)) if cands else None

    def outputs(self, v: dict) -> dict[str, int]:
        last = len(self.out) == 1
        hs = bool(self.out) and v["m_axis_tready"]
        o = dict(m_axis_tvalid=int(bool(self.out)),
                 done_o=(1 << self.cur) if hs and last and self.cur is not None else 0)
        if self.out:
            o.update(m_axis_tdata=self.out[0], m_axis_tlast=int(last))
        return o

    @staticmethod
    def packet(addr: int, v: dict, s: int) -> list[int]:
        n = (v["n_i"] >> (3 * s)) & 7
        word = (v["data_i"] >> (32 * s)) & 0xFFFF_FFFF
        return [addr, n] + [(word >> (24 - 8 * j)) & 0xFF for j in range(n)]

    def edge(self, v: dict) -> None:
        self.clock += 1
        o = self.outputs(v)
        gnt = self.grant()
        hs = bool(self.out) and v["m_axis_tready"]
        last = len(self.out) == 1
        flush = bool(v.get("flush_i", 0))
        load = self.staged is not None and not flush and (not self.out or (hs and last))
        stage = self.staged is None or load
        if load:
            self.out, self.cur = self.packet(self.addr, v, self.staged), self.staged
            self.first = True
        elif hs:
            self.out = self.out[1:]
            self.first = False
            if not self.out:
                self.cur = None
        if stage:
            self.staged = gnt
        self.done_prev = o["done_o"]
        for i in range(self.k):
            r = (v["req_i"] >> i) & 1
            if r and not self.prev_req[i]:
                self.birth[i] = self.clock
            self.prev_req[i] = r
        if flush:
            # Every packet not started is dropped and the arbiter starts afresh; one whose
            # first byte waits becomes the power-up message, credited to its source.
            self.staged, self.done_prev = None, 0
            self.prev_req = [0] * self.k
            if self.out and self.first and not v["m_axis_tready"]:
                self.out = [self.addr, len(POWER_UP), *POWER_UP]
                self.cur = self.powerup_src
            else:
                self.cur = None


class TxTB(ClockedTB):
    INPUTS = dict(req_i=0, n_i=0, data_i=0, m_axis_tready=1, flush_i=0)
    PULSES = ("flush_i",)
    OUTPUTS = ("done_o", "m_axis_tdata", "m_axis_tvalid", "m_axis_tlast")

    def __init__(self, dut) -> None:
        super().__init__(dut, "tx")
        p = hdl_params()
        self.addr, self.k = int(p["MODULE_ADDR"]), int(p["K"])
        src = int(p.get("POWERUP_SRC", -1))
        self.powerup_src = src if 0 <= src < self.k else None
        self.model = TxModel(self.addr, self.k, self.powerup_src)
        self.queues: list[list[tuple[int, int]]] = [[] for _ in range(self.k)]  # (n, word)
        self.req = [0] * self.k
        self.low = [1] * self.k            # clocks the request has been down
        self.p_raise = 1.0
        self.clocks = 0
        self.waiting: list[tuple[int, int, list[int]]] = []  # (birth, src, packet) up now
        self.sent: list[tuple[int, int, list[int]]] = []     # in departure order
        self.out_bytes: list[int] = []
        self.out_packets: list[list[int]] = []
        self.prev_out: dict | None = None
        self.n_word = [(0, 0)] * self.k

    def add(self, s: int, n: int, word: int) -> None:
        self.queues[s].append((n, word))

    async def step(self, rst: int = 0, **inputs: int) -> dict[str, int]:
        await FallingEdge(self.clk)
        for s in range(self.k):
            if not self.req[s] and self.low[s] >= 1 and self.queues[s] and \
                    self.rng.random() < self.p_raise:
                self.req[s] = 1
                self.n_word[s] = self.queues[s].pop(0)
                n, w = self.n_word[s]
                self.waiting.append((self.clocks, s, [self.addr, n] +
                                     [(w >> (24 - 8 * j)) & 0xFF for j in range(n)]))
        n_i = sum((self.n_word[s][0] & 7) << (3 * s) for s in range(self.k))
        data_i = sum(self.n_word[s][1] << (32 * s) for s in range(self.k))
        req_i = sum(r << s for s, r in enumerate(self.req))
        driven = list(self.req)
        vals = self.drive(rst, **dict(dict(req_i=req_i, n_i=n_i, data_i=data_i), **inputs))
        await ReadOnly()
        self.clocks += 1
        if rst:
            self.model.reset()
            out: dict[str, int] = {}
        else:
            out = self.sample()
            exp = self.model.outputs(vals)
            got = {k: out[k] for k in exp}
            assert got == exp, f"clock {self.clocks} {vals}: DUT {got} != model {exp}"
            self.observe(vals, out)
            self.model.edge(vals)
        for s in range(self.k):
            self.low[s] = 0 if driven[s] else self.low[s] + 1
        if vals["flush_i"]:
            self.sources_reset()
        await RisingEdge(self.clk)
        return out

    def sources_reset(self) -> None:
        """The sources are reset with the flush (cmdRESET): every request drops, and the
        power-up source holds the power-up message."""
        self.req = [0] * self.k
        self.queues = [[] for _ in range(self.k)]
        self.waiting = []
        self.sent = []        # packet order is checked from the flush on
        if self.powerup_src is not None:
            s = self.powerup_src
            self.req[s] = 1
            self.n_word[s] = (len(POWER_UP), POWER_UP[0] << 24 | POWER_UP[1] << 16)
            self.waiting.append((self.clocks, s, [self.addr, len(POWER_UP), *POWER_UP]))

    def observe(self, v: dict, out: dict) -> None:
        p = self.prev_out
        if p is not None and p["m_axis_tvalid"] and not p["_ready"]:
            for k in ("m_axis_tvalid", "m_axis_tdata", "m_axis_tlast"):
                assert out[k] == p[k], f"clock {self.clocks}: {k} moved while stalled"
        if out["m_axis_tvalid"] and v["m_axis_tready"]:
            self.out_bytes.append(out["m_axis_tdata"])
            if out["m_axis_tlast"]:
                self.out_packets.append(self.out_bytes)
                self.out_bytes = []
        if out["done_o"]:
            assert out["done_o"] & (out["done_o"] - 1) == 0
            s = out["done_o"].bit_length() - 1
            assert self.req[s], f"done_o for source {s}, which does not request"
            self.req[s] = 0
            entry = next(w for w in self.waiting if w[1] == s)
            self.waiting.remove(entry)
            self.sent.append(entry)
            assert self.out_packets[-1] == entry[2], (
                f"source {s}: sent {self.out_packets[-1]}, its packet is {entry[2]}")
        self.prev_out = dict(out, _ready=v["m_axis_tready"])

    def check_order(self) -> None:
        order = [(b, s) for b, s, _ in self.sent]
        assert order == sorted(order), f"not oldest first: {order[:10]}"
        assert not self.out_bytes, "a packet left part-way"

    async def drain(self, limit: int = 500) -> None:
        for _ in range(limit):
            if not any(self.req) and not any(self.queues) and not self.model.out:
                break
            await self.step(m_axis_tready=1)
        await self.step(m_axis_tready=1)
        assert not any(self.req) and not any(self.queues), "packets stuck"


@SUITE.test()
async def test_whole_packets_and_latency(dut) -> None:
    """One source, each length 0..4: A, N, d0.., tlast exactly on byte N+2, the first byte
    3 clocks after the request rises; done_o with the last handshake."""
    tb = TxTB(dut)
    await tb.reset()
    for n in range(5):
        tb.add(tb.k - 1, n, 0xA1B2C3D4)
        outs = [await tb.step() for _ in range(4 + n + 2)]
        valid = [o["m_axis_tvalid"] for o in outs]
        assert valid[:3] == [0, 0, 0] and valid[3:3 + n + 2] == [1] * (n + 2), valid
        assert [o["m_axis_tlast"] for o in outs[3:3 + n + 2]] == [0] * (n + 1) + [1]
        assert outs[3 + n + 1]["done_o"] == 1 << (tb.k - 1)
        assert tb.out_packets[-1] == [tb.addr, n] + [0xA1, 0xB2, 0xC3, 0xD4][:n]
    tb.check_order()


@SUITE.test()
async def test_back_to_back_no_interleave(dut) -> None:
    """All sources at once: packets leave one after the other with no idle clock, by index
    (same birth), never interleaved."""
    tb = TxTB(dut)
    await tb.reset()
    for s in range(tb.k):
        tb.add(s, s % 5, 0x10203040 + s)
    outs = [await tb.step() for _ in range(3 + sum(s % 5 + 2 for s in range(tb.k)) + 2)]
    valid = [o["m_axis_tvalid"] for o in outs]
    first = valid.index(1)
    run = valid[first:first + sum(s % 5 + 2 for s in range(tb.k))]
    assert all(run), f"idle clock between packets: {valid}"
    assert [s for _, s, _ in tb.sent] == list(range(tb.k))
    tb.check_order()


@SUITE.test()
async def test_oldest_first(dut) -> None:
    """Sources raising their requests one clock apart, highest index first, go oldest first;
    a source raising again after its done goes after the others that waited."""
    tb = TxTB(dut)
    await tb.reset()
    for s in reversed(range(tb.k)):
        tb.add(s, 2, 0xEE00 + s)
        await tb.step(m_axis_tready=0)
    for _ in range(6):
        await tb.step(m_axis_tready=0)
    tb.add(tb.k - 1, 1, 0x77000000)          # raises again once its first packet is done
    await tb.drain()
    srcs = [s for _, s, _ in tb.sent]
    assert srcs == list(reversed(range(tb.k))) + [tb.k - 1], srcs
    tb.check_order()


@SUITE.test()
async def test_stalled_output_holds(dut) -> None:
    """With m_axis_tready low the offered byte stays (checked every clock); a packet
    staged meanwhile is not lost; ready toggling every clock."""
    tb = TxTB(dut)
    await tb.reset()
    for s in range(tb.k):
        tb.add(s, 4, 0xDEADBEEF ^ s)
    for i in range(60):
        await tb.step(m_axis_tready=i % 3 == 0)
    await tb.drain()
    assert len(tb.sent) == tb.k
    tb.check_order()


@SUITE.test()
async def test_random_vs_model(dut) -> None:
    """Random packets from every source, random raise times and back-pressure, rare resets
    (which abandon what is going out); model and order checked throughout."""
    tb = TxTB(dut)
    rng = tb.rng
    await tb.reset()
    for _ in range(3000):
        for s in range(tb.k):
            if len(tb.queues[s]) < 2 and rng.random() < 0.05:
                tb.add(s, rng.randrange(5), rng.randrange(1 << 32))
        tb.p_raise = rng.choice([1.0, 0.3])
        await tb.step(m_axis_tready=int(rng.random() < rng.choice([0.9, 0.5])))
    await tb.drain(2000)
    tb.check_order()
    assert len(tb.sent) > 200


@SUITE.test()
async def test_flush(dut) -> None:
    """flush_i (cmdRESET) with random traffic and back-pressure, against the model on every
    clock: a packet with a byte taken is finished and credits nobody, one whose first byte
    waits becomes the power-up message in place, nothing staged leaves, and the power-up
    message is the next packet out. Every case (idle, first byte waiting, mid-packet, last
    byte) is reached."""
    tb = TxTB(dut)
    rng = tb.rng
    await tb.reset()
    seen: set[str] = set()
    for _ in range(400):
        for s in range(tb.k):
            if rng.random() < 0.5:
                tb.add(s, rng.randrange(5), rng.randrange(1 << 32))
        for _ in range(rng.randrange(3, 15)):
            await tb.step(m_axis_tready=int(rng.random() < 0.6))
        ready = int(rng.random() < 0.5)
        out_before = list(tb.model.out)
        first = tb.model.first
        n_packets = len(tb.out_packets)
        await tb.step(m_axis_tready=ready, flush_i=1)
        case = ("idle" if not out_before else "waiting" if first and not ready
                else "last" if len(out_before) == 1 and ready else "mid")
        seen.add(case)
        await tb.drain()
        after = tb.out_packets[n_packets:]
        power_up = [tb.addr, len(POWER_UP), *POWER_UP]
        if case in ("mid", "last"):
            # The packet finishes as it was, and nothing else leaves before the power-up
            # message (or nothing at all without a power-up source).
            assert after and after[0][-len(out_before):] == out_before, (case, after, out_before, ready, first)
            after = after[1:]
        assert after == ([power_up] if tb.powerup_src is not None or case == "waiting" else []), \
            (case, after)
    assert seen == {"idle", "waiting", "mid", "last"}, seen


@pytest.mark.parametrize("case", SUITE.cases())
def test_bsd_tx(case) -> None:
    SUITE.run(case)
