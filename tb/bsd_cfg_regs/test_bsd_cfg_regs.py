# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_cfg_regs, and their pytest entry.

Checked against PROTOCOL.md §3 (DIGCFG byte: a DIG_CFG set stores bits 4:0; FIXED pins),
§6 (power-up: DIGCFG 0x01, or FIXED_CFG's bits 4:0 on a fixed pin, with a fixed ENA armed;
output latch 0) and the block's header comment (fixed pins ignore configuration writes, their
output latch stays writable). The writes land at the edge that sees them; cfg_o and out_o
come from flops (or constants). From 17 pins on, ENA, TSTATE and TMODE (DIGCFG bits 1, 3, 4)
are a memory read with each packet: those fields of cfg_o then show the read pin's bits on
every line, from the clock after a read (rd_i, never on a write's clock, as bsd_exec) until the
next one, and 0 after reset; the block writes every pin's word after reset, a pin a clock, and
busy_o is set for those NUM_PINS clocks, in which no read or write may come (the core's parser
holds packets). The read also shows the pin's bits 4:1 (TRG too, which a flop a pin keeps as
well) on rd_cfg_o, which is 0 without the memory. CfgModel is compared with every output after
every clock.
"""

from __future__ import annotations

import cocotb
import pytest

from bsd_model import pin_sel, verilog_int
from bsd_protocol import (DIGCFG_ENA, DIGCFG_IODIR, DIGCFG_RESET, DIGCFG_STORED, DIGCFG_TMODE,
                          DIGCFG_TSTATE)
from clocked_tb import ClockedTB
import runner
from runner import hdl_params

READ_BITS = DIGCFG_TMODE | DIGCFG_TSTATE | DIGCFG_ENA   # with the memory, the fields a read shows
RD_CFG_BITS = DIGCFG_STORED & ~DIGCFG_IODIR            # bits 4:1, which rd_cfg_o shows
MEM_FROM = 17                             # the block's MEM_PINS

# pins7-fixed: pins 1, 3 and 6 fixed; pin 3 an input with ENA (0x13 | junk in bits 7:5,
# which must not show), pin 1 an output, pin 6 an input with TMODE/TSTATE/TRG.
FIXED_CFG7 = (0x1D << 48) | (0xE3 << 24) | (0xA0 << 8) | 0x5A  # pin 0's byte: unused
FIXED_CFG20 = (0x1F << 152) | (0x0C << 72) | (0xF3 << 16)
BUILDS = {
    "pins5": {"NUM_PINS": 5},
    "pins7-fixed": {"NUM_PINS": 7, "FIXED_MASK": "7'b1001010", "FIXED_CFG": f"56'h{FIXED_CFG7:x}"},
    "pins1-fixed": {"NUM_PINS": 1, "FIXED_MASK": "1'b1", "FIXED_CFG": "8'h03"},
    "pins16": {"NUM_PINS": 16},   # the widest flop form
    # The memory form: pins 2, 9 and 19 fixed (TMODE and ENA; an output with TSTATE and TRG;
    # an input with every bit).
    "pins20-fixed": {"NUM_PINS": 20, "FIXED_MASK": f"20'h{(1 << 19) | (1 << 9) | (1 << 2):x}",
                     "FIXED_CFG": f"160'h{FIXED_CFG20:x}"},
    # The widest cfg_o that Verilator gives toggle points (its default --coverage-max-width is
    # 256 bits: 64 pins' 320 get none), as the 24-pin board top has it: pins 8-23 are written
    # here every run, whatever the seed.
    "pins24": {"NUM_PINS": 24},
}


class CfgModel:
    def __init__(self, n: int, fixed_mask: int, fixed_cfg: int, mem: bool) -> None:
        self.n, self.fixed_mask, self.fixed_cfg, self.mem = n, fixed_mask, fixed_cfg, mem
        self.busy = 0
        self.reset()

    def fixed(self, p: int) -> bool:
        return bool((self.fixed_mask >> p) & 1)

    def reset(self) -> None:
        self.cfg = [((self.fixed_cfg >> (8 * p)) & DIGCFG_STORED) if self.fixed(p) else DIGCFG_RESET
                    for p in range(self.n)]
        self.out = [0] * self.n
        self.rd = 0   # with the memory: the last read pin's bits 4:1 (0 before the first read)
        self.busy = self.n if self.mem else 0   # clocks of the memory's sweep left

    def read(self, addr: int) -> None:
        self.rd = self.cfg[addr] & RD_CFG_BITS if addr < self.n else 0

    def step(self, v: dict) -> None:
        self.busy = max(self.busy - 1, 0)
        for p in range(self.n):
            if (v["sel_i"] >> p) & 1:
                if v["cfg_we_i"] and not self.fixed(p):
                    self.cfg[p] = v["cfg_wdata_i"] & DIGCFG_STORED
                if v["out_we_i"]:
                    self.out[p] = v["out_wdata_i"]

    def outputs(self) -> dict[str, int]:
        # oe_o: a pin drives its pad while DIGCFG IODIR (bit 0) is 0; watch_o: its
        # transition latch watches it while ENA and IODIR are both 1.
        watch = DIGCFG_ENA | DIGCFG_IODIR
        shown = [c & ~READ_BITS | self.rd & READ_BITS for c in self.cfg] if self.mem else self.cfg
        return dict(cfg_o=pack_cfg(shown), busy_o=int(self.busy > 0), rd_cfg_o=self.rd >> 1 if self.mem else 0,
                    out_o=sum(o << p for p, o in enumerate(self.out)),
                    oe_o=sum((~c & 1) << p for p, c in enumerate(self.cfg)),
                    watch_o=sum(int(c & watch == watch) << p for p, c in enumerate(self.cfg)))


def pack_cfg(cfg: list[int]) -> int:
    """Every pin's DIGCFG bits 4:0 as cfg_o carries them: field-major, bit k of pin p at
    k * n + p (the module's header)."""
    n = len(cfg)
    return sum(((c >> k) & 1) << (k * n + p) for p, c in enumerate(cfg) for k in range(5))


def unpack_cfg(word: int, n: int, p: int) -> int:
    """Pin p's DIGCFG bits 4:0 from a field-major cfg_o of n pins."""
    return sum(((word >> (k * n + p)) & 1) << k for k in range(5))


class CfgTB(ClockedTB):
    INPUTS = dict(cfg_we_i=0, out_we_i=0, sel_i=0, addr_i=0, rd_i=0, cfg_wdata_i=0, out_wdata_i=0)
    PULSES = ("cfg_we_i", "out_we_i", "rd_i")
    OUTPUTS = ("cfg_o", "out_o", "oe_o", "watch_o", "busy_o", "rd_cfg_o")

    def __init__(self, dut) -> None:
        super().__init__(dut, "cfg_regs")
        p = hdl_params()
        self.n = int(p["NUM_PINS"])
        self.mem = self.n >= MEM_FROM
        self.model = CfgModel(self.n, verilog_int(p.get("FIXED_MASK", 0)), verilog_int(p.get("FIXED_CFG", 0)),
                              self.mem)

    def drive(self, rst: int = 0, **inputs: int) -> dict[str, int]:
        # pin_idx_i=p stands for what bsd_exec and bsd_parser send: addr_i = p and its
        # one-hot sel_i = 1 << p, none beyond the last pin.
        if "pin_idx_i" in inputs:
            p = inputs.pop("pin_idx_i")
            inputs["addr_i"] = p
            inputs["sel_i"] = pin_sel(p, self.n)
        assert not (inputs.get("rd_i") and inputs.get("cfg_we_i")), "bsd_exec never reads on a write's clock"
        assert rst or not (self.model.busy and (inputs.get("rd_i") or inputs.get("cfg_we_i"))), \
            "the core's parser holds packets while busy_o"
        return super().drive(rst, **inputs)

    async def reset(self, cycles: int = 2) -> None:
        """Reset, then wait out the memory's sweep (busy_o, checked against the model)."""
        await super().reset(cycles)
        while self.model.busy:
            await self.step()

    def check(self, inputs, outputs, rst) -> None:
        if rst:
            self.model.reset()
        else:
            if inputs["rd_i"]:
                self.model.read(inputs["addr_i"])
            self.model.step(inputs)
        exp = self.model.outputs()
        assert dict(outputs) == exp, f"{inputs} rst={rst}: DUT {outputs} != model {exp}"

    async def cfg(self, p: int) -> int:
        """Pin p's DIGCFG bits 4:0 as cfg_o shows them the clock after a read of p."""
        out = await self.step(rd_i=1, pin_idx_i=p)
        return unpack_cfg(out["cfg_o"], self.model.n, p)


@cocotb.test()
async def test_reset_values(dut) -> None:
    """After reset: every free pin 0x01 (input, disarmed), every fixed pin FIXED_CFG's bits
    4:0 (ENA as given: armed), every output latch 0; also after writes to every pin and a
    second reset (with the memory, its words are then still written: the sweep clears them)."""
    tb = CfgTB(dut)
    await tb.reset()
    out = await tb.step()
    assert out["out_o"] == 0
    for p in range(tb.n):
        exp = tb.model.cfg[p]
        assert await tb.cfg(p) == exp
        if not tb.model.fixed(p):
            assert exp == DIGCFG_RESET
    for p in range(tb.n):
        await tb.step(cfg_we_i=1, out_we_i=1, pin_idx_i=p, cfg_wdata_i=RD_CFG_BITS, out_wdata_i=1)
    assert [await tb.cfg(p) for p in range(tb.n)] == [tb.model.cfg[p] if tb.model.fixed(p) else RD_CFG_BITS
                                                      for p in range(tb.n)]
    await tb.reset(1)
    out = await tb.step()
    assert out["out_o"] == 0 and out == tb.model.outputs()
    for p in range(tb.n):
        assert await tb.cfg(p) == tb.model.cfg[p]


@cocotb.test(skip=not runner.on("pins7-fixed", "pins1-fixed", "pins20-fixed"))
async def test_fixed_read_only(dut) -> None:
    """Configuration writes to a fixed pin change nothing (its latch stays writable);
    a fixed pin with ENA in FIXED_CFG reads armed from reset on."""
    tb = CfgTB(dut)
    await tb.reset()
    fixed = [p for p in range(tb.n) if tb.model.fixed(p)]
    assert any([await tb.cfg(p) & DIGCFG_ENA for p in fixed]), "build has no armed fixed pin"
    for p in fixed:
        before = await tb.cfg(p)
        for w in (0x00, 0x1F, before ^ 0x1F):
            await tb.step(cfg_we_i=1, pin_idx_i=p, cfg_wdata_i=w)
            assert await tb.cfg(p) == before, f"fixed pin {p} took {w:#x}"
        out = await tb.step(out_we_i=1, pin_idx_i=p, out_wdata_i=1)
        assert (out["out_o"] >> p) & 1


@cocotb.test()
async def test_writes_one_pin(dut) -> None:
    """A configuration write stores all of bits 4:0 of one pin only; an output write sets
    one latch only; both on one clock go to the same pin; an index >= NUM_PINS writes nothing."""
    tb = CfgTB(dut)
    await tb.reset()
    free = [p for p in range(tb.n) if not tb.model.fixed(p)]
    for p in free:
        for w in (0x1F, 0x00, 0x15, 0x0A, DIGCFG_IODIR):
            before = [await tb.cfg(q) for q in range(tb.n)]
            await tb.step(cfg_we_i=1, pin_idx_i=p, cfg_wdata_i=w)
            assert await tb.cfg(p) == w
            assert [await tb.cfg(q) for q in range(tb.n) if q != p] == [c for q, c in enumerate(before) if q != p]
    for p in range(tb.n):
        out = await tb.step(out_we_i=1, cfg_we_i=1, pin_idx_i=p, out_wdata_i=1, cfg_wdata_i=0)
        assert (out["out_o"] >> p) & 1
    assert out["out_o"] == (1 << tb.n) - 1
    before = [await tb.cfg(q) for q in range(tb.n)]
    for idx in (tb.n, 63):
        if idx < 64:
            out = await tb.step(out_we_i=1, cfg_we_i=1, pin_idx_i=idx, out_wdata_i=0,
                                cfg_wdata_i=0x1F)
            assert out["out_o"] == (1 << tb.n) - 1, f"index {idx} wrote a latch"
            assert [await tb.cfg(q) for q in range(tb.n)] == before, f"index {idx} wrote something"
    # a write enable of 0 writes nothing even with data on the ports
    await tb.step(pin_idx_i=0, out_wdata_i=0, cfg_wdata_i=0x1F)
    assert [await tb.cfg(q) for q in range(tb.n)] == before


@cocotb.test()
async def test_random_vs_model(dut) -> None:
    """Random writes and reads (any index 0..63, and now and then, without the memory, any
    set of pins at once), enables and resets, compared every clock (reads on clocks without
    a configuration write)."""
    tb = CfgTB(dut)
    rng = tb.rng
    await tb.reset()
    for _ in range(3000):
        idx = rng.randrange(tb.n + 2) if rng.random() < 0.9 else rng.randrange(64)
        # (with the memory, sel_i must be addr_i's line, as the parser gives them)
        where = dict(pin_idx_i=idx) if tb.mem or rng.random() < 0.9 else dict(sel_i=rng.getrandbits(tb.n))
        # (no read or configuration write while the memory is swept after a reset)
        free = not tb.model.busy
        cfg_we = int(free and rng.random() < 0.4)
        await tb.step(rst=int(rng.random() < 0.003), cfg_we_i=cfg_we,
                      rd_i=int(free and not cfg_we and rng.random() < 0.5),
                      out_we_i=int(rng.random() < 0.4), cfg_wdata_i=rng.randrange(32),
                      out_wdata_i=rng.randrange(2), **where)


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_cfg_regs(sim: str, build: str) -> None:
    runner.run(sim, "bsd_cfg_regs", __file__, BUILDS[build], build)
