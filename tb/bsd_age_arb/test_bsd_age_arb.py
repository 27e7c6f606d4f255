# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_age_arb, and their pytest entry.

Checked against DESIGN.md ("bsd_age_arb: grants the oldest of several requesters, same-age
ties: lowest index"; decision 1) and the block's header comment: a request is born on the
clock it rises; the grant comes from registers only (the requests of the previous clock and
their ages), masked combinationally by exclude_i; it is one-hot or zero.

gnt_o depends on exclude_i in the same clock, so this TB samples gnt_o in ReadOnly right
after driving the inputs on the falling edge (the value the next rising edge sees), and
compares it with AgeModel on every clock.
"""

from __future__ import annotations

import pytest
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from clocked_tb import ClockedTB
from runner import hdl_params
from suite import Suite, on

# k7, k9, k10: bsd_tx's arbiter in the 5-, 7- and 8-pin tops (K = NUM_PINS + 2); k9 and k10
# run only test_every_pair_order, which sets and clears every bit of their age matrix.
SUITE = Suite(__file__, "bsd_age_arb", {"k1": {"K": 1}, "k3": {"K": 3}, "k7": {"K": 7},
                                        "k9": {"K": 9}, "k10": {"K": 10}}, quick=on("icarus"))
SMALL = ("k1", "k3", "k7")


class AgeModel:
    """Each requester's birth clock; the grant is the candidate (waiting since an earlier
    clock, not excluded) with the lowest (birth, index)."""

    def __init__(self, k: int) -> None:
        self.k = k
        self.reset()

    def reset(self) -> None:
        self.clock = 0
        self.prev_req = [0] * self.k         # req_i seen at the last edge
        self.birth: list[int | None] = [None] * self.k

    def grant(self, exclude: int) -> int:
        cands = [i for i in range(self.k) if self.prev_req[i] and not (exclude >> i) & 1]
        if not cands:
            return 0
        best = min(cands, key=lambda i: (self.birth[i], i))
        return 1 << best

    def edge(self, req: int) -> None:
        self.clock += 1
        for i in range(self.k):
            r = (req >> i) & 1
            if r and not self.prev_req[i]:
                self.birth[i] = self.clock
            elif not r:
                self.birth[i] = None
            self.prev_req[i] = r


class ArbTB(ClockedTB):
    INPUTS = dict(req_i=0, exclude_i=0)
    OUTPUTS = ("gnt_o",)

    def __init__(self, dut) -> None:
        super().__init__(dut, "age_arb")
        self.k = int(hdl_params().get("K", 4))
        self.model = AgeModel(self.k)
        self.clocks = 0

    async def step(self, rst: int = 0, **inputs: int) -> dict[str, int]:
        """Drive on the falling edge, sample gnt_o before the rising edge that uses it."""
        await FallingEdge(self.clk)
        vals = self.drive(rst, **inputs)
        await ReadOnly()
        if rst:
            out = {}
            self.model.reset()
        else:
            out = self.sample()
            gnt = out["gnt_o"]
            exp = self.model.grant(vals["exclude_i"])
            assert gnt & (gnt - 1) == 0, f"clock {self.clocks}: grant {gnt:b} not one-hot"
            assert gnt == exp, (f"clock {self.clocks}: req {vals['req_i']:b} excl "
                                f"{vals['exclude_i']:b} births {self.model.birth}: "
                                f"grant {gnt:b}, model {exp:b}")
            self.model.edge(vals["req_i"])
        self.clocks += 1
        await RisingEdge(self.clk)
        return out


def bit(i: int) -> int:
    return 1 << i


@SUITE.test(*SMALL)
async def test_reset_and_first_grant(dut) -> None:
    """After reset no grant; a request is granted one clock after it rises, not before."""
    tb = ArbTB(dut)
    await tb.reset()
    assert (await tb.step())["gnt_o"] == 0
    top = tb.k - 1
    assert (await tb.step(req_i=bit(top)))["gnt_o"] == 0, "granted on the clock it rose"
    assert (await tb.step())["gnt_o"] == bit(top)
    assert (await tb.step())["gnt_o"] == bit(top), "grant must stay while the request stays"
    # reset forgets the requests
    await tb.reset()
    assert (await tb.step())["gnt_o"] == 0


@SUITE.test("k3", "k7")
async def test_oldest_first(dut) -> None:
    """Requests rising on successive clocks, highest index first: the grant follows age,
    not index, as each older one drops."""
    tb = ArbTB(dut)
    await tb.reset()
    order = list(range(tb.k - 1, -1, -1))
    req = 0
    for i in order:
        req |= bit(i)
        await tb.step(req_i=req)
    for i in order:
        assert (await tb.step(req_i=req))["gnt_o"] == bit(i), f"oldest is {i}"
        req &= ~bit(i)
        # the dropped one is excluded for the clock its request falls (as bsd_tx does)
        out = await tb.step(req_i=req, exclude_i=bit(i))
        assert out["gnt_o"] & bit(i) == 0


@SUITE.test("k3", "k7")
async def test_ties_lowest_index(dut) -> None:
    """Requests born on the same clock rank by index; an older one still beats them."""
    tb = ArbTB(dut)
    await tb.reset()
    k = tb.k
    allm = (1 << k) - 1
    await tb.step(req_i=allm)
    for i in range(k):
        # i-1 drops this clock and is excluded for it (as bsd_tx does)
        out = await tb.step(req_i=allm & ~((1 << i) - 1), exclude_i=bit(i - 1) if i else 0)
        assert out["gnt_o"] == bit(i)
    # the top one waits; then all lower ones rise together: the top one is older
    await tb.step(req_i=0)
    await tb.step(req_i=bit(k - 1))
    await tb.step(req_i=allm)
    assert (await tb.step(req_i=allm))["gnt_o"] == bit(k - 1)
    # the clock it drops, the grant (from registers) is still its own
    assert (await tb.step(req_i=allm & ~bit(k - 1)))["gnt_o"] == bit(k - 1)
    assert (await tb.step(req_i=allm & ~bit(k - 1)))["gnt_o"] == 1


@SUITE.test("k3", "k7")
async def test_reborn_is_youngest(dut) -> None:
    """A request that drops and rises again is younger than every one still waiting."""
    tb = ArbTB(dut)
    await tb.reset()
    await tb.step(req_i=0b001)
    await tb.step(req_i=0b011)
    await tb.step(req_i=0b111)
    assert (await tb.step(req_i=0b111))["gnt_o"] == 0b001
    await tb.step(req_i=0b110)           # 0 drops for one clock
    out = await tb.step(req_i=0b111)     # and rises again
    assert out["gnt_o"] == 0b010
    assert (await tb.step(req_i=0b101))["gnt_o"] == 0b010  # 1 drops
    assert (await tb.step(req_i=0b101))["gnt_o"] == 0b100, "reborn 0 must be younger than 2"


@SUITE.test(*SMALL)
async def test_exclude(dut) -> None:
    """exclude_i masks a waiting requester in the same clock; the next oldest gets it;
    the excluded one keeps its age."""
    tb = ArbTB(dut)
    await tb.reset()
    allm = (1 << tb.k) - 1
    await tb.step(req_i=1)
    await tb.step(req_i=allm)
    assert (await tb.step(exclude_i=1))["gnt_o"] == (0b10 if tb.k > 1 else 0)
    assert (await tb.step(exclude_i=allm))["gnt_o"] == 0
    assert (await tb.step(exclude_i=0))["gnt_o"] == 1, "excluded one lost its age"


@SUITE.test(*SMALL)
async def test_random_vs_model(dut) -> None:
    """Random requests (held for random spans, as sources do), drops, rises and excludes,
    grant compared with AgeModel on every clock."""
    tb = ArbTB(dut)
    rng = tb.rng
    await tb.reset()
    k = tb.k
    req = 0
    granted = set()
    for n in range(4000):
        p_flip = rng.choice([0.05, 0.2, 0.5])
        for i in range(k):
            if rng.random() < p_flip / k * 2:
                req ^= bit(i)
        excl = 0
        for i in range(k):
            if rng.random() < 0.15:
                excl |= bit(i)
        out = await tb.step(rst=int(rng.random() < 0.002), req_i=req, exclude_i=excl)
        if out.get("gnt_o"):
            granted.add(out["gnt_o"])
    assert len(granted) == k, f"random stimulus granted only {granted}"


@SUITE.test("k7", "k9", "k10")
async def test_every_pair_order(dut) -> None:
    """Every ordered pair (i, j), i != j: i rises, j rises a clock later; i is granted while
    both wait, then j once i has dropped (excluded for the clock it falls). Each pair
    records "i older than j" in the age matrix and a later pair (j, i) clears it, so every
    off-diagonal bit of the matrix is set and cleared; the grant is compared with AgeModel
    on every clock."""
    tb = ArbTB(dut)
    await tb.reset()
    k = tb.k
    for i in range(k):
        for j in range(k):
            if i == j:
                continue
            both = bit(i) | bit(j)
            await tb.step(req_i=bit(i), exclude_i=0)
            assert (await tb.step(req_i=both, exclude_i=0))["gnt_o"] == bit(i), f"({i}, {j}): {i} alone"
            assert (await tb.step(req_i=both, exclude_i=0))["gnt_o"] == bit(i), f"({i}, {j}): {i} older"
            await tb.step(req_i=bit(j), exclude_i=bit(i))
            assert (await tb.step(req_i=bit(j), exclude_i=0))["gnt_o"] == bit(j), f"({i}, {j}): {j} after {i}"
            await tb.step(req_i=0, exclude_i=bit(j))
            assert (await tb.step(req_i=0, exclude_i=0))["gnt_o"] == 0


@pytest.mark.parametrize("case", SUITE.cases())
def test_bsd_age_arb(case) -> None:
    SUITE.run(case)
