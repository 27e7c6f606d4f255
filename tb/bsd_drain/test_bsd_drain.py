# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_drain, and their pytest entry.

Checked against PROTOCOL.md §4.2 and §5 and DESIGN.md decisions 1, 4 and 9: entries are
taken in queue order, and within one entry the items go timers by ascending timer (pin),
then the reply, then the heartbeat, with the DIG_IO RFLX value before the first timer whose
device ID is above its own. A reference stores T for its timer; a finish's result is
T - reference (1 when that is 0, 0 for a timeout: a timer's r and f bits together); it becomes an output-queue item
{timer, its ID, result} when the timer's HOST bit is set and an RFLX strobe when its RFLX
bit is (with the timer's rflx_done_o when its HOST bit is not: then the strobe frees it); the reply and the heartbeat become items, the
DIG_IO value a strobe. DrainModel is that text; the item and strobe sequences must equal it.
The entries come from a queue model with random gaps, several per clock's worth of events.
A timer's HOST and RFLX bits are its last start's: run_host_i/run_rflx_i below MEM_TIMERS
timers, the start ports from then on (a memory in the drain, read while a timer item is in
stage A; a start on such a clock waits, with hold_o set, and no start comes while hold_o is:
test_starts).
"""

from __future__ import annotations

import cocotb
import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from bsd_model import verilog_int
from clocked_tb import ClockedTB
import runner
from runner import hdl_params

# gp1: GP 1.0's timers (pins 1-4, IDs 11-14, consecutive); sparse: timers on pins 1, 2, 5
# and 7 of 8, IDs 4, 5, 8, 10 (the ID table), so DIG_IO IDs fall between timer IDs; mid: 12
# timers on 16 pins, with gaps, so the pick is one carry chain (9 to 16 timers: core16t's
# form); wide: 20 timers on 24 pins, with gaps, so the pick works over groups of timers (16
# and 4).
BUILDS = {
    "gp1": {"NUM_PINS": 5, "TIMER_MASK": "5'b11110", "TIMER_ID_BASE": 10, "NT": 4},
    "sparse": {"NUM_PINS": 8, "TIMER_MASK": "8'b10100110", "TIMER_ID_BASE": 3, "NT": 4},
    "mid": {"NUM_PINS": 16, "TIMER_MASK": "16'b1101111011101110", "TIMER_ID_BASE": 3, "NT": 12},
    "wide": {"NUM_PINS": 24, "TIMER_MASK": "24'b111011111101111101111110", "TIMER_ID_BASE": 3, "NT": 20},
    # full: 64 timers, the 64-timer core's drain (the runs' bits a memory, as from 17 timers:
    # wide's too); gp1mem: GP 1.0's timers with the memory form (MEM_TIMERS lowered), so that
    # its short entries put starts on clocks with and without a read.
    "full": {"NUM_PINS": 64, "TIMER_MASK": "64'b" + "1" * 64, "TIMER_ID_BASE": 0, "NT": 64},
    "gp1mem": {"NUM_PINS": 5, "TIMER_MASK": "5'b11110", "TIMER_ID_BASE": 10, "NT": 4, "MEM_TIMERS": 2},
}
TIMER, REPLY, HB = 0, 1, 2


class DrainTB(ClockedTB):
    INPUTS = dict(ev_valid_i=0, ev_data_i=0, ev_timers_i=0, run_host_i=0, run_rflx_i=0,
                  start_i=0, start_idx_i=0, start_host_i=0, start_rflx_i=0)
    OUTPUTS = ("ev_ready_o", "order_valid_o", "order_data_o", "rflx_done_o", "rflx_idx_o",
               "rflx_valid_o", "rflx_id_o", "rflx_data_o", "hold_o")

    def __init__(self, dut) -> None:
        super().__init__(dut, "drain")
        p = hdl_params()
        self.nt = int(p["NT"])
        mask, base = verilog_int(p["TIMER_MASK"]), int(p["TIMER_ID_BASE"])
        self.ids = [base + q for q in range(int(p["NUM_PINS"])) if mask >> q & 1]
        # From MEM_TIMERS timers on the runs' bits come from the start ports (a memory in
        # the drain), below from run_host_i/run_rflx_i (bsd_timer_bank's flops).
        self.mem = self.nt >= int(p.get("MEM_TIMERS", 17))

    def sample(self) -> dict[str, int]:
        """Data outputs are meaningful only with their valid (unreset flops read X on Icarus
        until then): an unresolved value reads as -1."""
        vals = {k: getattr(self.dut, k).value for k in self.OUTPUTS}
        out = {k: int(v) if v.is_resolvable else -1 for k, v in vals.items()}
        # A reply's or heartbeat's item carries a don't-care result (the reference RAM's
        # word, unwritten early on): its kind alone must resolve.
        kind = vals["order_data_o"][29:28]
        if out["order_data_o"] == -1 and kind.is_resolvable and int(kind) != TIMER:
            out["order_data_o"] = int(kind) << 28
        return out

    def entry(self, r: int, f: int, rep: int, dio: int, hb: int, dio_id: int, dio_val: int, t: int) -> int:
        n = self.nt
        return ((r << (n + 26)) | (f << 26) | (rep << 25) | (dio << 24) | (hb << 23)
                | (dio_id << 17) | (dio_val << 16) | t)

    async def edge(self, **inputs: int) -> dict:
        await FallingEdge(self.clk)
        self.drive(0, **inputs)
        await ReadOnly()
        out = self.sample()
        await RisingEdge(self.clk)
        return out


async def load_bits(tb: DrainTB, host: int, rflx: int) -> None:
    """The memory form: a start of every timer with its bits (the drain idle: each written on
    its clock), as the runs' bits before entries that assume them."""
    if not tb.mem:
        return
    for k in range(tb.nt):
        out = await tb.edge(start_i=1, start_idx_i=k, start_host_i=host >> k & 1, start_rflx_i=rflx >> k & 1)
        assert out["ev_ready_o"] and not out["hold_o"]
    out = await tb.edge(start_i=0)
    assert not out["hold_o"]


def item_of(d: int) -> tuple:
    """An output-queue item as the model writes it: (TIMER, timer, ID, result), or (kind,)."""
    kind = d >> 28
    return (TIMER, d >> 22 & 63, d >> 16 & 63, d & 0xFFFF) if kind == TIMER else (kind,)


def model_entry(tb: DrainTB, e: dict, ref: list, host: int, rflx: int, items: list, strobes: list) -> list[int]:
    """One entry's output-queue items and RFLX strobes, appended in order, with the runs'
    HOST and RFLX bits `host` and `rflx` (`ref`: each timer's reference, updated); returns
    the timers it finishes (a result or a timeout), in order."""
    order = [("t", k) for k in range(tb.nt) if (e["r"] | e["f"]) >> k & 1]
    if e["dio"]:
        pos = next((i for i, (_, k) in enumerate(order) if tb.ids[k] > e["dio_id"]), len(order))
        order.insert(pos, ("dio", 0))
    finished = []
    for what, k in order:
        if what == "dio":
            strobes.append((e["dio_id"], e["dio_val"]))
        elif e["r"] >> k & 1 and not e["f"] >> k & 1:
            ref[k] = e["t"]
        else:
            res = 0 if e["r"] >> k & 1 else max(1, (e["t"] - ref[k]) & 0xFFFF)
            if host >> k & 1:
                items.append((TIMER, k, tb.ids[k], res))
            if rflx >> k & 1:
                strobes.append((tb.ids[k], res))
            finished.append(k)
    if e["rep"]:
        items.append((REPLY,))
    if e["hb"]:
        items.append((HB,))
    return finished


def model(tb: DrainTB, entries: list[dict], host: int, rflx: int) -> tuple[list, list]:
    """The output-queue items and RFLX strobes the entries must give, in order."""
    ref: list[int | None] = [None] * tb.nt
    items: list = []
    strobes: list = []
    for e in entries:
        model_entry(tb, e, ref, host, rflx, items, strobes)
    return items, strobes


async def run(tb: DrainTB, n_entries: int, p_gap: float) -> None:
    rng, nt = tb.rng, tb.nt
    host, rflx = (rng.getrandbits(nt) | 1) & ~4, rng.getrandbits(nt) | 6  # timer 2: RFLX alone
    phase = [0] * nt   # 0: the next event is the reference, 1: the finish
    entries = []
    t = rng.randrange(65536)
    for _ in range(n_entries):
        t = (t + rng.choice([0, 1, 2, 40000])) & 0xFFFF
        r = f = 0
        for k in range(nt):
            if rng.random() < 0.5:
                if rng.random() < 0.25:
                    r |= 1 << k          # a timeout (with or without a reference before): r and f
                    f |= 1 << k
                    phase[k] = 0
                elif phase[k] == 0:
                    r |= 1 << k
                    phase[k] = 1
                else:
                    f |= 1 << k
                    phase[k] = 0
        dio = int(rng.random() < 0.3)
        entries.append(dict(r=r, f=f, rep=int(rng.random() < 0.3), dio=dio, hb=int(rng.random() < 0.2),
                            dio_id=rng.choice(tb.ids + [0, 63, tb.ids[0] + 1]) if dio else 0,
                            dio_val=rng.randrange(2), t=t, seed=rng.getrandbits(24)))
    entries = [e for e in entries if e["r"] | e["f"] | e["rep"] | e["dio"] | e["hb"]]
    want_items, want_strobes = model(tb, entries, host, rflx)
    await load_bits(tb, host, rflx)
    got_items, got_strobes, done = [], [], []
    i = 0
    offered = False  # entry i is on offer: it stays until taken (AXI-Stream, as the queue's head)
    for _ in range((nt + 8) * len(entries) + 40):  # an item a clock, gaps between entries
        kw = dict(run_host_i=host, run_rflx_i=rflx)
        if i < len(entries) and (offered or rng.random() >= p_gap):
            e = entries[i]
            # ev_timers_i says the entry has timer events (the queue's ev_any bit). An entry
            # without comes with r and f stale (random) half of the time, as from the skip
            # path, which the drain must ignore.
            timers = bool(e["r"] | e["f"])
            skip = not timers and e["seed"] & 1
            r, f = (e["seed"] >> 1 & (1 << nt) - 1, e["seed"] >> 9 & (1 << nt) - 1) if skip else (e["r"], e["f"])
            kw.update(ev_valid_i=1, ev_timers_i=int(timers),
                      ev_data_i=tb.entry(r, f, e["rep"], e["dio"], e["hb"], e["dio_id"], e["dio_val"], e["t"]))
        else:
            kw.update(ev_valid_i=0)
        out = await tb.edge(**kw)
        offered = bool(kw["ev_valid_i"])
        if kw["ev_valid_i"] and out["ev_ready_o"]:
            i += 1
            offered = False
        if out["order_valid_o"]:
            got_items.append(item_of(out["order_data_o"]))
        if out["rflx_valid_o"]:
            got_strobes.append((out["rflx_id_o"], out["rflx_data_o"]))
        if out["rflx_done_o"]:
            done.append(out["rflx_idx_o"])
    assert i == len(entries), f"the drain took {i} of {len(entries)} entries"
    assert got_items == want_items, f"items {got_items[:8]} != {want_items[:8]}"
    assert got_strobes == want_strobes, f"strobes {got_strobes[:8]} != {want_strobes[:8]}"
    want_done = [k for e in entries for k in range(nt)
                 if e["f"] >> k & 1 and rflx >> k & 1 and not host >> k & 1]
    assert sorted(done) == sorted(want_done) and len(done) == len(want_done)
    assert len(want_items) > 20 and len(want_strobes) > 20


@cocotb.test()
async def test_order_and_results(dut) -> None:
    """Back-to-back entries: items and strobes in entry order, timers ascending, the DIG_IO
    value placed by its ID, results T - reference (1 for 0, 0 for timeouts)."""
    tb = DrainTB(dut)
    await tb.reset()
    await run(tb, 150, 0.0)


@cocotb.test()
async def test_gaps(dut) -> None:
    """The same with gaps between entries (an empty queue now and then)."""
    tb = DrainTB(dut)
    await tb.reset()
    await run(tb, 150, 0.5)


@cocotb.test()
async def test_item_a_clock(dut) -> None:
    """An entry of every timer's finish, the DIG_IO value, the reply and the heartbeat takes
    exactly one clock per item, and the next entry follows after one idle clock; in the
    memory form after two when the entry has timer events (taken from the queue on the
    first: stage A read its r, f and T from the queue's head until then), and after three
    when its last item is a timer (the clock after it finds no timer left)."""
    tb = DrainTB(dut)
    await tb.reset()
    nt, full = tb.nt, (1 << tb.nt) - 1
    e1 = tb.entry(full, 0, 0, 0, 0, 0, 0, 100)
    e2 = tb.entry(0, full, 1, 1, 1, 0, 1, 200)
    e3 = tb.entry(0, 0, 1, 0, 0, 0, 0, 300)
    await load_bits(tb, full, 0)
    taken = []
    for c in range(3 * nt + 20):
        pend = [e for j, e in enumerate((e1, e2, e3)) if j >= len(taken)]
        kw = dict(run_host_i=full, run_rflx_i=0)
        # (e3 has no timer events: ev_timers_i low)
        kw.update(ev_valid_i=1, ev_timers_i=int(pend[0] != e3), ev_data_i=pend[0]) if pend \
            else kw.update(ev_valid_i=0)
        out = await tb.edge(**kw)
        if pend and out["ev_ready_o"]:
            taken.append(c)
    # e1: nt reference items; e2: DIG_IO (ID 0 first), nt finishes, reply, hb. A clock in
    # `taken` is the one that takes the entry from the queue: as it loads, or in the memory
    # form (e1, e2) on the first idle clock after its items, e2 loading on the clock after
    # e1's and e3 (no timer events) taken as it loads, on the clock after e2's.
    # e1 loads on clock 0 and its last item is a timer: taken as it loads, or in the memory
    # form on clock nt + 2 (items on 1..nt, then the clock that finds no timer left).
    gaps = (nt + 5, 1) if tb.mem else (nt + 1, nt + 4)
    assert (taken[0], taken[1] - taken[0], taken[2] - taken[1]) == (nt + 2 if tb.mem else 0, *gaps), taken


async def run_starts(tb: DrainTB, n_clocks: int, p_gap: float) -> None:
    """Timers started (start_i, as bsd_exec's stage 2: never while hold_o) at random, with
    random HOST and RFLX bits, each restarted only once its last result is delivered; their
    references and finishes come in entries made after the start, several timers an entry, so
    that starts meet the drain both idle (written on their clock) and in a run of timer items
    (pending: hold_o set from the next clock until the first clock without a timer in stage
    A, where the memory's port reads the runs' bits).
    Every finish must be delivered with the bits of its own last start; hold_o must be
    exactly that pending flag (always 0 below MEM_TIMERS, where run_host_i/run_rflx_i model
    bsd_timer_bank's flops, loaded on the clock after the start)."""
    rng, nt, ids = tb.rng, tb.nt, tb.ids
    bits = [(0, 0)] * nt          # each timer's last start's (HOST, RFLX)
    via_pend = [False] * nt       # that start's write was pending
    state = ["idle"] * nt         # idle, ref (reference due), fin (finish due), owed (result owed)
    started = [-1] * nt           # the clock of the last start
    ref: list[int | None] = [None] * nt
    run_host = run_rflx = 0       # bsd_timer_bank's flops (the small form's inputs)
    queue: list[int] = []         # entries made and not yet taken (words), with their timer flag
    flags: list[int] = []
    want_items, want_strobes, want_done = [], [], []
    got_items, got_strobes, got_done = [], [], []
    pend = 0                      # the drain's pending write, as hold_o must show it
    offered = False               # queue[0] is on offer
    n_pend = n_direct = n_pend_fin = 0
    t = rng.randrange(65536)
    c = tail = 0
    while tail < 8:  # (8 clocks after the last entry and result: the stages' last strobes)
        tail = 0 if c < n_clocks or queue or "owed" in state else tail + 1
        assert c < n_clocks + 40 * (nt + 8), f"not drained: {len(queue)} entries, owed {state.count('owed')}"
        await FallingEdge(tb.clk)
        gen = c < n_clocks
        hold = int(tb.dut.hold_o.value)
        # a clock without a timer in stage A (a flop of the drain's: no port of its shows it
        # on this clock), which writes a pending word
        nxt = 1 - int(tb.dut.a_t_q.value)
        assert hold == pend, f"clock {c}: hold_o {hold}, pending {pend}"
        kw = dict(start_i=0, run_host_i=run_host, run_rflx_i=run_rflx)
        t = (t + rng.choice([0, 0, 1, 3])) & 0xFFFF
        # the entry of the events of earlier clocks (timers started before this clock)
        if gen and rng.random() < 0.6:
            r = f = 0
            for k in range(nt):
                if started[k] >= c or rng.random() < 0.4:
                    continue
                if state[k] == "ref":
                    if rng.random() < 0.15:
                        r, f, state[k] = r | 1 << k, f | 1 << k, "owed"   # a timeout
                    else:
                        r, state[k] = r | 1 << k, "fin"
                elif state[k] == "fin":
                    if rng.random() < 0.1:
                        r, f, state[k] = r | 1 << k, f | 1 << k, "owed"
                    else:
                        f, state[k] = f | 1 << k, "owed"
            rep, dio, hb = int(rng.random() < 0.2), int(rng.random() < 0.2), int(rng.random() < 0.1)
            dio_id, dio_val = (rng.choice(ids + [0, 63]) if dio else 0), rng.randrange(2)
            if r | f | rep | dio | hb:
                queue.append(tb.entry(r, f, rep, dio, hb, dio_id, dio_val, t))
                flags.append(int(bool(r | f)))
                host = sum(h << k for k, (h, _) in enumerate(bits))
                rflx = sum(x << k for k, (_, x) in enumerate(bits))
                e = dict(r=r, f=f, rep=rep, dio=dio, hb=hb, dio_id=dio_id, dio_val=dio_val, t=t)
                for k in model_entry(tb, e, ref, host, rflx, want_items, want_strobes):
                    n_pend_fin += via_pend[k]
                    if rflx >> k & 1 and not host >> k & 1:
                        want_done.append(k)
        # a start (never while hold_o)
        idle = [k for k in range(nt) if state[k] == "idle"]
        # (more often while a timer is in stage A: few clocks, and only their starts wait)
        if gen and not hold and idle and rng.random() < (0.4 if nxt else 0.9):
            k = rng.choice(idle)
            h, x = rng.choice([(1, 0), (0, 1), (1, 1), (1, 1), (0, 0)])
            kw.update(start_i=1, start_idx_i=k, start_host_i=h, start_rflx_i=x)
            bits[k], via_pend[k], started[k] = (h, x), tb.mem and not nxt, c
            state[k] = "ref" if h | x else "idle"   # (no events without either bit)
            n_pend += tb.mem and not nxt
            n_direct += not (tb.mem and not nxt)
            run_host = run_host & ~(1 << k) | h << k
            run_rflx = run_rflx & ~(1 << k) | x << k
        # (an entry offered stays offered until taken, as from the queue's head: AXI-Stream)
        if queue and (offered or rng.random() >= p_gap):
            kw.update(ev_valid_i=1, ev_timers_i=flags[0], ev_data_i=queue[0])
        else:
            kw.update(ev_valid_i=0)
        tb.drive(0, **kw)
        await ReadOnly()
        out = tb.sample()
        if tb.mem:
            pend = int((kw["start_i"] and not nxt) or (pend and not nxt))
        offered = bool(kw["ev_valid_i"])
        if kw["ev_valid_i"] and out["ev_ready_o"]:
            queue.pop(0)
            flags.pop(0)
            offered = False
        if out["order_valid_o"]:
            item = item_of(out["order_data_o"])
            got_items.append(item)
            if item[0] == TIMER:
                assert state[item[1]] == "owed"
                state[item[1]] = "idle"             # delivered: may start again
        if out["rflx_valid_o"]:
            got_strobes.append((out["rflx_id_o"], out["rflx_data_o"]))
        if out["rflx_done_o"]:
            got_done.append(out["rflx_idx_o"])
            assert state[out["rflx_idx_o"]] == "owed"
            state[out["rflx_idx_o"]] = "idle"
        await RisingEdge(tb.clk)
        c += 1
    for what, got, want in (("items", got_items, want_items), ("strobes", got_strobes, want_strobes),
                            ("done", got_done, want_done)):
        i = next((i for i, (g, w) in enumerate(zip(got, want)) if g != w), min(len(got), len(want)))
        assert got == want, f"{what} from {i}: {got[i:i + 6]} != {want[i:i + 6]} ({len(got)}, {len(want)})"
    tb.log.info("starts: %d pending, %d direct; finishes of a pending start: %d; items %d, strobes %d",
                n_pend, n_direct, n_pend_fin, len(want_items), len(want_strobes))
    assert len(want_items) > 50 and len(want_strobes) > 50
    if tb.mem:
        assert n_pend > 20 and n_direct > 20 and n_pend_fin > 20


@cocotb.test()
async def test_starts(dut) -> None:
    """Starts among the entries: every finish delivered with its own last start's HOST and
    RFLX bits; from MEM_TIMERS timers on, a start during a run of picks waits (hold_o) and
    is written before its timer's finish is read."""
    tb = DrainTB(dut)
    await tb.reset()
    await run_starts(tb, 6000, 0.2)


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="verilator"))
def test_bsd_drain(sim: str, build: str) -> None:
    runner.run(sim, "bsd_drain", __file__, BUILDS[build], build)
