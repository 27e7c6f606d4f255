# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_pkt_tx, and their pytest entry.

Checked against PROTOCOL.md §2 and §5 and the block's header comment: each item of the
output queue becomes one whole packet `A, N, d0..` on m_axis, in item order, back to back:
a timer item `A, 4, 4, ID, hi, lo`, the reply item the reply slot's packet (N up to 8), the
heartbeat item `A, 2, 0, type`; tlast exactly on byte N + 1; tvalid, tdata and tlast held
while stalled; the source is told (timer_done_o with its index, reply_done_o, hb_done_o)
exactly on its packet's last handshake; an item is taken only when offered, never twice.
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from bsd_protocol import CMD_DEV_VAL, CMD_HB
from clocked_tb import ClockedTB
import runner
from runner import hdl_params

BUILDS = {"a2": {"MODULE_ADDR": 2}, "a254": {"MODULE_ADDR": 254}}
TIMER, REPLY, HB = 0, 1, 2


def item(kind: int, idx: int = 0, dev_id: int = 0, result: int = 0) -> int:
    return kind << 28 | idx << 22 | dev_id << 16 | result


class TxTB(ClockedTB):
    INPUTS = dict(flush_i=0, item_valid_i=0, item_data_i=0, rep_n_i=0, rep_data_i=0, rep_tail_i=0,
                  hb_type_i=0, m_axis_tready=1)
    OUTPUTS = ("item_ready_o", "free_o", "timer_done_o", "timer_idx_o", "reply_done_o", "hb_done_o",
               "m_axis_tdata", "m_axis_tvalid", "m_axis_tlast")

    def __init__(self, dut) -> None:
        super().__init__(dut, "pkt_tx")
        self.addr = int(hdl_params()["MODULE_ADDR"])

    async def edge(self, **inputs: int) -> dict:
        """Drive on the falling edge, sample what the next rising edge will see."""
        await FallingEdge(self.clk)
        self.drive(0, **inputs)
        await ReadOnly()
        out = self.sample()
        await RisingEdge(self.clk)
        return out


async def run_items(tb: TxTB, items: list[tuple], p_ready: float) -> None:
    """Offer the items in order (each with its source's state), random backpressure; check
    every packet and every done pulse."""
    rng = tb.rng
    expect: list[tuple[bytes, tuple]] = []
    for it in items:
        kind = it[0]
        if kind == TIMER:
            _, idx, dev_id, res = it
            pkt = bytes([tb.addr, 4, CMD_DEV_VAL, dev_id, res >> 8, res & 0xFF])
        elif kind == REPLY:
            _, data = it
            pkt = bytes([tb.addr, len(data)] + data)
        else:
            _, t = it
            pkt = bytes([tb.addr, 2, CMD_HB, t])
        expect.append((pkt, it))
    got: list[bytes] = []
    cur = bytearray()
    i = 0
    prev = None
    for _ in range(40 * len(items) + 50):
        kw: dict = dict(m_axis_tready=int(rng.random() < p_ready))
        # The reply slot and the heartbeat hold their packet until it has left: they show
        # the first reply / heartbeat not yet sent, and a second one is not queued before.
        rest = items[len(got):]
        rep = next((it for it in rest if it[0] == REPLY), None)
        hb = next((it for it in rest if it[0] == HB), None)
        if rep is not None:
            data = rep[1] + [0] * (8 - len(rep[1]))
            kw.update(rep_n_i=len(rep[1]), rep_data_i=int.from_bytes(bytes(data[:4]), "big"),
                      rep_tail_i=int.from_bytes(bytes(data[4:]), "big"))
        if hb is not None:
            kw["hb_type_i"] = hb[1]
        kw["item_valid_i"] = 0
        if i < len(items):
            it = items[i]
            in_flight = items[len(got):i]
            if it[0] == TIMER:
                kw.update(item_valid_i=1, item_data_i=item(TIMER, it[1], it[2], it[3]))
            elif all(x[0] != it[0] for x in in_flight):
                kw.update(item_valid_i=1, item_data_i=item(it[0], rng.randrange(64)))
        out = await tb.edge(**kw)
        if prev is not None and prev["m_axis_tvalid"] and not prev["m_axis_tready"]:
            assert out["m_axis_tvalid"] and (out["m_axis_tdata"], out["m_axis_tlast"]) == \
                (prev["m_axis_tdata"], prev["m_axis_tlast"]), "byte changed while stalled"
        done = (out["timer_done_o"], out["reply_done_o"], out["hb_done_o"])
        if out["m_axis_tvalid"] and kw["m_axis_tready"]:
            cur.append(out["m_axis_tdata"])
            want = expect[len(got)][0]
            assert out["m_axis_tlast"] == int(len(cur) == len(want)), f"tlast on byte {len(cur)} of {want.hex()}"
            if out["m_axis_tlast"]:
                kind = expect[len(got)][1][0]
                assert done == (int(kind == TIMER), int(kind == REPLY), int(kind == HB)), done
                if kind == TIMER:
                    assert out["timer_idx_o"] == expect[len(got)][1][1]
                got.append(bytes(cur))
                cur = bytearray()
            else:
                assert done == (0, 0, 0)
        else:
            assert done == (0, 0, 0)
        if kw["item_valid_i"] and out["item_ready_o"]:
            i += 1
        prev = dict(out, m_axis_tready=kw["m_axis_tready"])
    assert [g.hex() for g in got] == [e[0].hex() for e in expect]


@cocotb.test()
async def test_every_kind_in_order(dut) -> None:
    """Timer results, replies of every N (0..8) and heartbeats, in item order, always ready:
    packets back to back (the next item taken on the last handshake)."""
    tb = TxTB(dut)
    await tb.reset()
    rng = tb.rng
    items: list[tuple] = []
    for n in range(9):
        items.append((REPLY, [rng.randrange(256) for _ in range(n)]))
        items.append((TIMER, rng.randrange(64), rng.randrange(64), rng.randrange(65536)))
        items.append((HB, n & 1))
    await run_items(tb, items, 1.0)


@cocotb.test()
async def test_random_backpressure(dut) -> None:
    """200 random items under random backpressure: every packet whole and unchanged while
    stalled, done pulses exactly on last handshakes."""
    tb = TxTB(dut)
    await tb.reset()
    rng = tb.rng
    items: list[tuple] = []
    for _ in range(200):
        k = rng.randrange(3)
        items.append((TIMER, rng.randrange(64), rng.randrange(64), rng.randrange(65536)) if k == 0 else
                     (REPLY, [rng.randrange(256) for _ in range(rng.randrange(9))]) if k == 1 else
                     (HB, rng.randrange(2)))
    await run_items(tb, items, 0.6)


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="verilator"))
def test_bsd_pkt_tx(sim: str, build: str) -> None:
    runner.run(sim, "bsd_pkt_tx", __file__, BUILDS[build], build)
