# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_parser, and their pytest entry.

Builds: (MODULE_ADDR, RX_TIMEOUT_US) = (2, 20 us = 12.5 ticks: 13 -> 14 idle ticks),
(254, 16 us = exactly 10 ticks -> 11), (0x40, 0 = no timeout), (2, 25 600 = the default:
16 000 -> 16 001). The test drives tick_i itself.

Inputs are driven on the falling edge; s_axis_tready is read in ReadOnly() right
after that (the value the next rising edge uses), pkt_* in ReadOnly() after the
rising edge. A byte moves at a rising edge with tvalid and tready both 1.

Every step() compares tready and pkt_* with FramingModel (docs/PROTOCOL.md 2 and
DESIGN.md decisions 2 and 10), written from the contract:
- address A: the packet goes to the executor (KIND_CMD with N and d0..d2) when its
  last byte arrives; N = 0 to A: nothing; N > 8 to A: KIND_SERIAL right after the
  length byte, and the next byte is an address.
- 0xAD with N = 0: KIND_PROBE; 0xAD with N > 0 and any other address: the N data
  bytes are consumed silently (N > 8: the next byte is an address).
- hold_i = 1 (a reply is waiting) holds a packet that can need a reply (DESIGN.md
  decision 2): the last data byte of a packet to A waits (tready 0); a packet that ends
  with its length byte and has a reply (0xAD with N = 0, A with N > 8) takes its length
  byte and then waits (PEND, tready 0 for the next byte) until hold_i is 0, when it is
  handed over and the next byte may be taken on the same clock. tready never depends on
  the offered byte (or tvalid); every other byte streams.
- inter-byte timeout: counted in tick_i strobes on clocks with tready 1, tvalid 0
  and a packet partly received (length or data state), since the last accepted byte; the partial packet is
  dropped on the TIMEOUT_TICKS-th such strobe, TIMEOUT_TICKS = ceil(US / 1.6) + 1,
  the least count that never drops before RX_TIMEOUT_US of idle time whatever the
  tick phase: (TIMEOUT_TICKS - 1) * 1.6 us >= RX_TIMEOUT_US. RX_TIMEOUT_US = 0: never.
- a command's d0 also comes decoded (pkt_cmd_o, the block's header): one flag per command
  the executor knows (cmd_flags below), and d1's bits 5:0 as a one-hot over NUM_PINS pins
  (pkt_sel_o, 0 for a pin past the last), both checked with every command handed over.
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge, Timer

from bsd_model import CMD_FLAGS, cmd_flags, pin_sel
from bsd_protocol import (ADDR_RESYNC, DEFAULT_MODULE_ADDR, DEFAULT_RX_TIMEOUT_US, KIND_CMD, KIND_PROBE,
                          KIND_SERIAL, MAX_N)
from clocked_tb import ClockedTB
import runner
from runner import hdl_params
from seeding import make_rng

PERIOD_NS = 10

BUILDS = {
    f"addr{a}-to{t}us-pins{p}": {"MODULE_ADDR": a, "RX_TIMEOUT_US": t, "NUM_PINS": p}
    for a, t, p in [(2, 20, 5), (254, 16, 64), (0x40, 0, 1), (2, 25_600, 16)]
}
TIMED = [b for b, p in BUILDS.items() if p["RX_TIMEOUT_US"]]
UNTIMED = [b for b, p in BUILDS.items() if not p["RX_TIMEOUT_US"]]

MODULE_ADDR = int(hdl_params().get("MODULE_ADDR", DEFAULT_MODULE_ADDR))
RX_TIMEOUT_US = int(hdl_params().get("RX_TIMEOUT_US", DEFAULT_RX_TIMEOUT_US))
NUM_PINS = int(hdl_params().get("NUM_PINS", 5))


def timeout_ticks(us: int) -> int:
    """ceil(us / 1.6) + 1, in integers (1.6 us = 8/5 us)."""
    return (us * 5 + 7) // 8 + 1


T_TICKS = timeout_ticks(RX_TIMEOUT_US) if RX_TIMEOUT_US else None


class FramingModel:
    def __init__(self, addr: int, t_ticks: int | None) -> None:
        self.addr, self.t_ticks = addr, t_ticks
        self.drops = 0  # partial packets dropped by the timeout (kept across reset)
        self.reset()

    def reset(self) -> None:
        self.state = "ADDR"
        self.idle = 0

    def stop(self) -> bool:
        """The next byte waits while hold_i is 1."""
        if self.state == "PEND":
            return True
        return (self.state == "DATA" and self.pkt_addr == self.addr
                and len(self.data) + 1 == self.n)

    def tready(self, hold: int, tvalid: int = 0, tdata: int = 0) -> int:
        return int(not (hold and self.stop()))

    def step(self, tvalid: int, tdata: int, hold: int, tick: int):
        """One clock; returns the packet handed over at this edge or None."""
        ready = self.tready(hold)
        out = None
        if self.state == "PEND" and not hold:
            out, self.state = self.pending, "ADDR"
        if not (tvalid and ready):
            if ready and not tvalid and self.state in ("LEN", "DATA") and self.t_ticks and tick:
                self.idle += 1
                if self.idle == self.t_ticks:
                    self.state, self.drops = "ADDR", self.drops + 1
            return out
        self.idle = 0
        own = self.state != "ADDR" and self.pkt_addr == self.addr
        if self.state == "ADDR":
            self.pkt_addr, self.state = tdata, "LEN"
        elif self.state == "LEN":
            self.n, self.data = tdata, []
            if tdata > MAX_N:
                self.state = "ADDR"
                if own:
                    self.state, self.pending = "PEND", (KIND_SERIAL, None, [])
            elif tdata == 0:
                self.state = "ADDR"
                if self.pkt_addr == ADDR_RESYNC:
                    self.state, self.pending = "PEND", (KIND_PROBE, 0, [])
            else:
                self.state = "DATA"
        else:
            self.data.append(tdata)
            if len(self.data) == self.n:
                self.state = "ADDR"
                return (KIND_CMD, self.n, self.data[:3]) if own else None
        return out


class ParserTB(ClockedTB):
    """step() reads tready in the middle of its clock as well, so it is its own; the
    short keyword names below stand for the ports."""

    PORTS = {"tvalid": "s_axis_tvalid", "tdata": "s_axis_tdata", "hold": "hold_i", "tick": "tick_i"}
    INPUTS = {port: 0 for port in PORTS.values()}
    PERIOD_NS = PERIOD_NS

    def __init__(self, dut):
        super().__init__(dut, "parser")
        self.model = FramingModel(MODULE_ADDR, T_TICKS)
        self.edge = 0
        self.pkts: list[tuple] = []

    def _apply(self, rst: int, kw: dict) -> dict:
        vals = self.drive(rst, **{self.PORTS[k]: v for k, v in kw.items()})
        return {k: vals[port] for k, port in self.PORTS.items()}

    def _read_pkt(self):
        d = self.dut
        if not int(d.pkt_valid_o.value):
            return None
        if int(d.pkt_kind_o.value) == KIND_CMD:
            d0 = int(d.pkt_d0_o.value)
            assert int(d.pkt_cmd_o.value) == cmd_flags(d0), f"pkt_cmd_o {int(d.pkt_cmd_o.value):#x} for d0 {d0}"
            d1 = int(d.pkt_d1_o.value)
            assert int(d.pkt_sel_o.value) == pin_sel(d1, NUM_PINS), f"pkt_sel_o {int(d.pkt_sel_o.value):#x} for d1 {d1}"
        return (int(d.pkt_kind_o.value), int(d.pkt_n_o.value),
                [int(d.pkt_d0_o.value), int(d.pkt_d1_o.value), int(d.pkt_d2_o.value)])

    @staticmethod
    def _same(got, exp) -> bool:
        if got is None or exp is None:
            return got is None and exp is None
        kind, n, data = exp
        if got[0] != kind:
            return False
        if kind == KIND_SERIAL:
            return True  # N is not meaningful
        return got[1] == n and got[2][: len(data)] == data

    async def step(self, rst: int = 0, **kw) -> tuple[int, object]:
        """One clock: returns (tready used at this edge, packet handed over at it)."""
        await FallingEdge(self.dut.clk)
        v = self._apply(rst, kw)
        await ReadOnly()
        ready = int(self.dut.s_axis_tready.value)
        exp_ready = 0 if rst else self.model.tready(v["hold"], v["tvalid"], v["tdata"])
        assert ready == exp_ready, (
            f"edge {self.edge + 1}: tready {ready}, expected {exp_ready} "
            f"(state {self.model.state}, hold {v['hold']}, rst {rst})"
        )
        await RisingEdge(self.dut.clk)
        await ReadOnly()
        self.edge += 1
        got = self._read_pkt()
        if rst:
            self.model.reset()
            exp = None
        else:
            exp = self.model.step(v["tvalid"], v["tdata"], v["hold"], v["tick"])
        assert self._same(got, exp), f"edge {self.edge}: pkt {got}, expected {exp} ({v})"
        if got is not None:
            self.pkts.append(got)
        return ready, got

    async def skip(self, n: int, **kw) -> None:
        """n clocks with constant inputs, fast (one Timer); tvalid may be 1 only where
        the byte is held (tready 0), so no byte moves."""
        assert n >= 2
        await FallingEdge(self.dut.clk)
        v = self._apply(0, kw)
        await ReadOnly()
        ready = self.model.tready(v["hold"], v["tvalid"], v["tdata"])
        assert not (v["tvalid"] and ready), "skip() cannot move bytes"
        assert int(self.dut.s_axis_tready.value) == ready
        await Timer((n - 1) * PERIOD_NS + PERIOD_NS // 4, unit="ns")
        await RisingEdge(self.dut.clk)
        await ReadOnly()
        self.edge += n
        for _ in range(n):
            assert self.model.step(v["tvalid"], v["tdata"], v["hold"], v["tick"]) is None
        assert not int(self.dut.pkt_valid_o.value)
        assert int(self.dut.s_axis_tready.value) == self.model.tready(v["hold"], v["tvalid"], v["tdata"])

    async def reset(self) -> None:
        for _ in range(2):
            ready, _ = await self.step(rst=1, tvalid=0)
            assert ready == 0, "tready must be 0 during reset"

    async def send(self, data, **kw) -> list:
        """Bytes back to back (tvalid stays 1 while bytes remain)."""
        out = []
        for b in data:
            for _ in range(100):
                ready, pkt = await self.step(tvalid=1, tdata=b, **kw)
                if pkt is not None:
                    out.append(pkt)
                if ready:
                    break
            else:
                raise AssertionError(f"byte {b:#x} not accepted")
        ready, pkt = await self.step(tvalid=0, **kw)  # the last byte's packet shows here
        if pkt is not None:
            out.append(pkt)
        return out


OTHER_ADDRS = [a for a in (0, 1, 3, 4, 0x7F, 0x80, 0xAC, 0xAE, 0xFE, 0xFF)
               if a != MODULE_ADDR]  # fmt: skip


@cocotb.test()
async def test_own_packets(dut):
    """Own-address packets of N = 1..8: KIND_CMD with N and the first three data bytes
    (d0 a command the executor knows, or any byte; pkt_cmd_o checked with each)."""
    tb = ParserTB(dut)
    rng = make_rng(dut, "own packets")
    await tb.reset()
    for n in list(range(1, 9)) * 3:
        data = [rng.randrange(256) for _ in range(n)]
        data[0] = rng.choice([*CMD_FLAGS, data[0]])
        pkts = await tb.send([MODULE_ADDR, n, *data])
        assert len(pkts) == 1, pkts
        kind, got_n, d = pkts[0]
        assert (kind, got_n) == (KIND_CMD, n)
        assert d[: min(n, 3)] == data[:3]


@cocotb.test()
async def test_other_addresses_silent(dut):
    """Other addresses (and 0xAD with N > 0) are consumed silently, byte for byte:
    a packet to A right behind them is framed correctly."""
    tb = ParserTB(dut)
    rng = make_rng(dut, "other addresses")
    await tb.reset()
    for addr in OTHER_ADDRS + [ADDR_RESYNC]:
        for n in range(0 if addr != ADDR_RESYNC else 1, 9):
            # data full of own-address, 0xAD and small length values
            data = [rng.choice([MODULE_ADDR, ADDR_RESYNC, 0, 1, 2, 8, 9]) for _ in range(n)]
            pkts = await tb.send([addr, n, *data, MODULE_ADDR, 2, 0x1B, 0x80])
            assert len(pkts) == 1, (addr, n, data, pkts)
            assert pkts[0][:2] == (KIND_CMD, 2) and pkts[0][2][:2] == [0x1B, 0x80], pkts


@cocotb.test()
async def test_probe_and_empty(dut):
    tb = ParserTB(dut)
    await tb.reset()
    pkts = await tb.send([ADDR_RESYNC, 0])
    assert [p[:2] for p in pkts] == [(KIND_PROBE, 0)], pkts
    assert await tb.send([MODULE_ADDR, 0]) == [], "N = 0 to own address must do nothing"
    # 0xAD with N > 0: ignored (data consumed), then a probe works again
    assert await tb.send([ADDR_RESYNC, 2, ADDR_RESYNC, 0]) == []
    pkts = await tb.send([ADDR_RESYNC, 0, MODULE_ADDR, 0, ADDR_RESYNC, 0])
    assert [p[:2] for p in pkts] == [(KIND_PROBE, 0), (KIND_PROBE, 0)], pkts


@cocotb.test()
async def test_length_over_8(dut):
    """N > 8: KIND_SERIAL only for the own address; the next byte is an address."""
    tb = ParserTB(dut)
    await tb.reset()
    for n in (9, 15, 16, 0x80, 0xFF):
        pkts = await tb.send([MODULE_ADDR, n])
        assert [p[0] for p in pkts] == [KIND_SERIAL], (n, pkts)
        # next byte is an address: a probe right after
        pkts = await tb.send([ADDR_RESYNC, 0])
        assert [p[0] for p in pkts] == [KIND_PROBE]
        for addr in (OTHER_ADDRS[0], ADDR_RESYNC):
            assert await tb.send([addr, n]) == [], f"N={n} to {addr:#x} must be silent"
            pkts = await tb.send([MODULE_ADDR, 1, 0x63])
            assert len(pkts) == 1 and pkts[0][:2] == (KIND_CMD, 1), pkts
            assert pkts[0][2][0] == 0x63, pkts


@cocotb.test()
async def test_back_to_back_full_rate(dut):
    """hold_i = 0 and tvalid always 1: one byte per clock, tready never drops."""
    tb = ParserTB(dut)
    rng = make_rng(dut, "back to back")
    await tb.reset()
    stream = []
    for _ in range(150):
        addr = rng.choice([MODULE_ADDR, MODULE_ADDR, ADDR_RESYNC, rng.randrange(256)])
        n = rng.choice([0, 1, 2, 3, 4, 8, 9, rng.randrange(256)])
        stream += [addr, n] + ([rng.randrange(256) for _ in range(n)] if n <= 8 else [])
    clocks = 0
    for b in stream:
        ready, _ = await tb.step(tvalid=1, tdata=b, hold=0, tick=rng.randrange(2))
        assert ready == 1, f"tready 0 at byte {clocks} with hold_i = 0"
        clocks += 1
    await tb.step(tvalid=0)
    assert clocks == len(stream)
    assert len(tb.pkts) > 25


@cocotb.test()
async def test_hold_stalls_only_reply_capable_packets(dut):
    """With hold_i = 1, tready is 0 exactly for the last data byte of a packet to A and
    for the byte after a length byte that ended a packet with a reply (0xAD with N = 0,
    A with N > 8: that packet waits to be handed over); everything else (addresses,
    length and data bytes, other modules' packets, 0xAD with N > 0) streams. When hold_i
    drops, the waiting packet is handed over and the held byte is taken."""
    tb = ParserTB(dut)
    await tb.reset()

    async def offer(b, expect_ready):
        ready, _ = await tb.step(tvalid=1, tdata=b, hold=1)
        assert ready == expect_ready, f"byte {b:#x}: tready {ready} with hold, want {expect_ready}"
        if not ready:  # held: stays held, then goes when hold drops
            for _ in range(5):
                ready, _ = await tb.step(tvalid=1, tdata=b, hold=1)
                assert ready == 0
            ready, _ = await tb.step(tvalid=1, tdata=b, hold=0)
            assert ready == 1

    other = OTHER_ADDRS[0]
    # own address, N = 3: address, length and data stream; the last data byte is held
    for b, r in [(MODULE_ADDR, 1), (3, 1), (0x1A, 1), (0x02, 1), (0x05, 0)]:
        await offer(b, r)
    await tb.step(tvalid=0, hold=1)
    assert tb.pkts[-1] == (KIND_CMD, 3, [0x1A, 0x02, 0x05])
    # own address, N = 1
    for b, r in [(MODULE_ADDR, 1), (1, 1), (0x63, 0)]:
        await offer(b, r)
    # probe: its length byte is taken, then the packet waits and the next byte with it;
    # 0xAD with N > 0 never replies: streams
    for b, r in [(ADDR_RESYNC, 1), (0, 1), (ADDR_RESYNC, 0), (2, 1), (MODULE_ADDR, 1), (7, 1)]:
        await offer(b, r)
    assert tb.pkts[-1][0] == KIND_PROBE, tb.pkts
    # other address: nothing held, not even its last byte
    for b, r in [(other, 1), (2, 1), (MODULE_ADDR, 1), (0, 1)]:
        await offer(b, r)
    # own address with N = 0 (no reply): streams; N > 8 (serialError): waits, handed over
    # on the first clock without hold_i
    for b, r in [(MODULE_ADDR, 1), (0, 1), (MODULE_ADDR, 1), (9, 1)]:
        await offer(b, r)
    for _ in range(3):
        _, pkt = await tb.step(tvalid=0, hold=1)
        assert pkt is None and int(dut.s_axis_tready.value) == 0
    _, pkt = await tb.step(tvalid=0, hold=0)
    assert pkt is not None and pkt[0] == KIND_SERIAL
    kinds = [p[0] for p in tb.pkts]
    assert kinds == [KIND_CMD, KIND_CMD, KIND_PROBE, KIND_SERIAL], tb.pkts


# Ticks every 8 clocks (a 1.6 us tick at a 0.2 us clock) only where that stays short.
TIMEOUT_EVERY = [1, 8] if T_TICKS and T_TICKS < 200 else [1]


@cocotb.test(skip=not runner.on(*TIMED))
@cocotb.parametrize(every=TIMEOUT_EVERY, late=[0, 1])
async def test_inter_byte_timeout(dut, every, late):
    """A partial packet survives T_TICKS - 1 idle ticks and is dropped by the
    T_TICKS-th. With a tick every 8 clocks (8 clocks = 1.6 us) at a random phase, the
    drop lands between RX_TIMEOUT_US and RX_TIMEOUT_US + 3.2 us of idle time."""
    tb = ParserTB(dut)
    rng = make_rng(dut, f"timeout every={every} late={late}")
    await tb.reset()
    dut._log.info("RX_TIMEOUT_US=%d: %d idle ticks drop a packet", RX_TIMEOUT_US, T_TICKS)
    for partial in ([MODULE_ADDR], [MODULE_ADDR, 2], [MODULE_ADDR, 3, 0x1A, 0x01],
                    [OTHER_ADDRS[0], 4, 9], [ADDR_RESYNC], [ADDR_RESYNC, 3]):  # fmt: skip
        phase = rng.randrange(every)
        # The last byte is accepted at edge e0; send() adds clock e0+1, tvalid 0, no tick.
        await tb.send(partial, hold=0, tick=0)
        j, ticks = 1, 0  # idle clocks since e0 so far (e0+1 .. e0+j), ticks among them
        target = T_TICKS - 1 + late  # idle ticks to let pass before the next byte
        if every == 1 and target > 40:
            await tb.skip(target - 20, tvalid=0, tick=1)
            j += target - 20
            ticks += target - 20
        # late = 0: every idle clock up to (not including) the T_TICKS-th tick's clock;
        # late = 1: up to and including it.
        while not (late and ticks == target):
            t = int((j + 1 + phase) % every == 0)  # tick on clock e0+j+1?
            if ticks + t > target:
                break
            await tb.step(tvalid=0, tick=t)
            j, ticks = j + 1, ticks + t
        assert ticks == target
        if every == 8 and late:
            # dropped at edge e0+j: j idle clocks of 0.2 us; US <= j/5 <= US + 3.2
            assert 5 * RX_TIMEOUT_US <= j <= 5 * RX_TIMEOUT_US + 16, (j, RX_TIMEOUT_US)
        # Now A, 1, 0x55: a new packet if dropped, else it continues the partial one.
        tb.pkts.clear()
        pkts = await tb.send([MODULE_ADDR, 1, 0x55], tick=0)
        new_pkt = [p for p in pkts if p[:2] == (KIND_CMD, 1) and p[2][0] == 0x55]
        if late:
            assert new_pkt, f"partial {partial} not dropped after {ticks} idle ticks: {pkts}"
        else:
            assert not new_pkt, f"partial {partial} dropped after {ticks} idle ticks: {pkts}"
        assert tb.model.drops == late
        tb.model.drops = 0
        await tb.reset()  # clean framing for the next partial


@cocotb.test(skip=not runner.on(*TIMED))
async def test_timeout_not_while_stalled(dut):
    """Ticks while tready is 0 (hold; tvalid high or low) never count; idle ticks
    before and after a stall add up."""
    tb = ParserTB(dut)
    await tb.reset()
    many = 3 * T_TICKS + 10
    # The last byte of a packet to A offered and held with tvalid = 1 for `many` ticks:
    # not dropped.
    await tb.send([MODULE_ADDR, 2, 0x1B], hold=0, tick=0)
    ready, _ = await tb.step(tvalid=1, tdata=0x80, hold=1, tick=1)
    assert ready == 0
    await tb.skip(many, tvalid=1, tdata=0x80, hold=1, tick=1)
    ready, _ = await tb.step(tvalid=1, tdata=0x80, hold=0, tick=1)
    assert ready == 1
    await tb.step(tvalid=0, hold=0, tick=0)
    assert tb.pkts[-1][:2] == (KIND_CMD, 2) and tb.pkts[-1][2][:2] == [0x1B, 0x80], tb.pkts
    # The same wait for the last byte with tvalid = 0 (tready 0): no counting either.
    await tb.send([MODULE_ADDR, 1], hold=0)
    await tb.skip(T_TICKS - 1, tvalid=0, hold=0, tick=1)  # T-1 idle ticks counted
    await tb.skip(many, tvalid=0, hold=1, tick=1)  # stalled by hold: none counted
    assert tb.model.drops == 0
    tb.pkts.clear()
    await tb.send([0x44], hold=0, tick=0)  # still framed: N = 1, data 0x44
    assert tb.pkts and tb.pkts[-1][:2] == (KIND_CMD, 1) and tb.pkts[-1][2][0] == 0x44
    # Again, and one more idle tick after the stall drops it.
    await tb.send([MODULE_ADDR, 1], hold=0)
    await tb.skip(T_TICKS - 1, tvalid=0, hold=0, tick=1)
    await tb.skip(many, tvalid=0, hold=1, tick=1)
    await tb.step(tvalid=0, hold=0, tick=1)
    assert tb.model.drops == 1
    tb.pkts.clear()
    await tb.send([1, 0x44, ADDR_RESYNC, 0], tick=0)  # 1 is an address now: N=0x44 > 8
    assert [p[0] for p in tb.pkts] == [KIND_PROBE], tb.pkts


@cocotb.test(skip=not runner.on(*UNTIMED))
async def test_no_timeout_when_zero(dut):
    """RX_TIMEOUT_US = 0: a partial packet waits forever."""
    tb = ParserTB(dut)
    await tb.reset()
    await tb.send([MODULE_ADDR, 2, 0x1A])
    await tb.skip(100_000, tvalid=0, tick=1)
    pkts = await tb.send([0x03])
    assert [p[:2] for p in pkts] == [(KIND_CMD, 2)] and pkts[0][2][:2] == [0x1A, 3], pkts


@cocotb.test()
async def test_reset_mid_packet(dut):
    tb = ParserTB(dut)
    await tb.reset()
    await tb.send([MODULE_ADDR, 3, 0x1A])
    await tb.reset()
    pkts = await tb.send([ADDR_RESYNC, 0])
    assert [p[0] for p in pkts] == [KIND_PROBE], pkts


@cocotb.test()
async def test_random_stream_vs_model(dut):
    """Random byte streams (well-formed and garbage), random tvalid gaps, hold_i and
    tick_i; tready and every packet compared with FramingModel on every clock.
    tvalid/tdata follow AXI: once offered, a byte stays until taken."""
    tb = ParserTB(dut)
    rng = make_rng(dut, "parser random")
    await tb.reset()

    def gen_stream():
        out = []
        for _ in range(rng.randrange(1, 6)):
            addr = rng.choice([MODULE_ADDR] * 6 + [ADDR_RESYNC] * 3 + OTHER_ADDRS)
            n = rng.choice([0, 1, 2, 3, 4, 5, 8, 9, 200])
            body = [rng.choice([MODULE_ADDR, ADDR_RESYNC, 0, rng.randrange(256)])
                    for _ in range(min(n, MAX_N))]  # fmt: skip
            if rng.random() < 0.15:  # truncated packet
                body = body[: rng.randrange(len(body) + 1)]
            out += [addr, n] + body
        return out

    for _ in range(120):
        stream = gen_stream()
        hold_p = rng.choice([0.0, 0.3, 0.8])
        tick_p = rng.choice([0.05, 0.5])
        gap_p = rng.choice([0.0, 0.3, 0.8])
        i = 0
        offering = False
        while i < len(stream):
            if not offering and T_TICKS and T_TICKS < 50 and rng.random() < 0.03:
                # a long pause, often past the inter-byte timeout
                for _ in range(rng.randrange(1, int(2 * T_TICKS / tick_p))):
                    await tb.step(tvalid=0, hold=int(rng.random() < hold_p),
                                  tick=int(rng.random() < tick_p))  # fmt: skip
            if not offering and rng.random() < gap_p:
                await tb.step(tvalid=0, hold=int(rng.random() < hold_p),
                              tick=int(rng.random() < tick_p))  # fmt: skip
                continue
            offering = True
            ready, _ = await tb.step(tvalid=1, tdata=stream[i], hold=int(rng.random() < hold_p),
                                     tick=int(rng.random() < tick_p))  # fmt: skip
            if ready:
                i += 1
                offering = False
        if rng.random() < 0.02:
            await tb.reset()
    await tb.step(tvalid=0)
    kinds = [p[0] for p in tb.pkts]
    dut._log.info(
        "random: %d clocks, %d packets (%d CMD, %d PROBE, %d SERIAL), %d timeouts",
        tb.edge, len(kinds), kinds.count(KIND_CMD), kinds.count(KIND_PROBE),
        kinds.count(KIND_SERIAL), tb.model.drops,
    )  # fmt: skip
    assert kinds.count(KIND_CMD) > 20 and kinds.count(KIND_PROBE) > 5
    if T_TICKS and T_TICKS < 50:
        assert tb.model.drops > 5, "random stimulus hardly reached the inter-byte timeout"


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_parser(sim: str, build: str) -> None:
    runner.run(sim, "bsd_parser", __file__, BUILDS[build], build)
