# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of bsd_exec, and their pytest entry.

Checked against PROTOCOL.md §2 (packets, messages, the precedence cmdInvalid, cmdTooShort,
the command's own error, cmdTooLong only after success), §3 (every form of cmdDIG_CFG,
cmdDIG_IO, cmdDIG_RST, cmdPTIME_RD, cmdHB; DEVCODE's HOST and RFLX bits; replies), DESIGN.md
decisions 6 and 8 and "Latencies" (the state-change strobes leave this block one clock
after pkt_valid_i, i.e. 2 clocks after the packet's last byte; the reply decision in that
same clock), and the block's header comment. The pin state (cfg_i, level_i, timer_busy_i)
counts as it is on the clock of pkt_valid_i.

ExecModel decodes each packet from those rules into the outputs expected right after the
clock that took it (every strobe 0 and no reply on all other clocks); the outputs that only
mean something with their strobe (pin_sel_o, write data, the timer's delivery bits, the
reply's bytes past reply_n_o, the DIG_IO RFLX id/value) are compared only then. Compared
after every clock.

cmdDEBUG (23): any N from 1 to 8 is echoed as the reply, `A, N, 23, d1 .. d(N-1)` (its
bytes past the fourth on reply_tail_o, taken from pkt_tail_i = d3..d7). The block's input
contract (its parser) hands over packets at least three clocks apart; the block checks that
in simulation, so every test spaces its packets so. The tests speak of d0; the block takes
it decoded as the parser hands it over (pkt_cmd_i, cmd_flags below).
"""

from __future__ import annotations

import cocotb
import pytest

from bsd_protocol import (CMD_DEBUG, CMD_DEV_VAL, CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST, CMD_HB,
                          CMD_MSG, CMD_PTIME_RD, CMD_RESET, DEVCODE_HOST, DEVCODE_PIN, DEVCODE_RFLX,
                          DIGCFG_FIXED, DIGCFG_IODIR, DIGCFG_STORED, HB_ANSWER_OFFSET, HB_DOWN,
                          HB_UP, KIND_CMD, KIND_PROBE, KIND_SERIAL, MAX_N, MSG_CMD_INDEX_ERR,
                          MSG_CMD_INVALID, MSG_CMD_TOO_LONG, MSG_CMD_TOO_SHORT, MSG_CONFIG_ERR,
                          MSG_SERIAL_ERROR, MSG_TMR_CONFLICT)
from bsd_model import cmd_flags, pin_sel, verilog_int
from clocked_tb import ClockedTB
import runner
from runner import hdl_params

BUILDS = {
    "gp1": {"NUM_PINS": 5, "TIMER_MASK": "5'b11110", "FIXED_MASK": "5'b00000", "PIN_ID_BASE": 5},
    "pins7-fixed": {"NUM_PINS": 7, "TIMER_MASK": "7'b1010011", "FIXED_MASK": "7'b0100101",
                    "PIN_ID_BASE": 40},
    # more than 8 timers: the start strobes share a clear instead of an AND each
    "pins12-t10": {"NUM_PINS": 12, "TIMER_MASK": "12'b111111011110", "FIXED_MASK": "12'b000000000001",
                   "PIN_ID_BASE": 5},
    # a timer on every pin: the executor's "a timer pin" is then "a pin at all"
    "pins3-all": {"NUM_PINS": 3, "TIMER_MASK": "3'b111", "FIXED_MASK": "3'b000", "PIN_ID_BASE": 5},
    "pins64": {"NUM_PINS": 64, "TIMER_MASK": "64'h8000000000000001",
               "FIXED_MASK": "64'h4000000000000000", "PIN_ID_BASE": 0},
    # the core's from 17 pins on: a DIG_CFG read takes bits 4:1 from bsd_cfg_regs's memory
    # read (cfg_rd_i), and the pin's one-hot is decoded from d1; the testbench then puts the
    # inverse of every pin's bits 4:1 on cfg_i and the next pin's line on pkt_sel_i
    "pins20-mem": {"NUM_PINS": 20, "TIMER_MASK": "20'hfffff", "FIXED_MASK": "20'h00010",
                   "PIN_ID_BASE": 0, "CFG_MEM": 1},
}

ALWAYS = ("s2_valid_o", "cfg_we_o", "out_we_o", "rearm_o", "timer_start_o", "timer_go_o", "hb_answer_o",
          "reply_o", "dio_rflx_o", "soft_reset_o")


def pin_cfg(word: int, n: int, p: int) -> int:
    """Pin p's DIGCFG bits 4:0 from a field-major cfg_i of n pins (bsd_cfg_regs: bit k of
    pin p at k * n + p)."""
    return sum(((word >> (k * n + p)) & 1) << k for k in range(5))


class ExecModel:
    def __init__(self, p: dict) -> None:
        self.n = int(p["NUM_PINS"])
        self.timer_mask = verilog_int(p["TIMER_MASK"])
        self.fixed_mask = verilog_int(p["FIXED_MASK"])
        self.pin_id_base = int(p["PIN_ID_BASE"])
        self.exp = self.idle()

    @staticmethod
    def idle() -> dict:
        return {k: 0 for k in ALWAYS}

    def decode(self, v: dict) -> dict:
        e = self.idle()
        if not v["pkt_valid_i"]:
            return e
        e["s2_valid_o"] = 1
        kind, n, d0, d1, d2 = (v[k] for k in ("pkt_kind_i", "pkt_n_i", "pkt_d0_i", "pkt_d1_i",
                                              "pkt_d2_i"))
        cfg = [pin_cfg(v["cfg_i"], self.n, p) for p in range(self.n)]
        is_input = lambda p: bool(cfg[p] & DIGCFG_IODIR)  # noqa: E731
        bit = lambda m, p: bool((m >> p) & 1)  # noqa: E731

        def reply(*data: int) -> None:
            e.update(reply_o=1, reply_n_o=len(data), _reply_bytes=list(data))

        def msg(code: int) -> None:
            reply(CMD_MSG, code)

        def too_long(longest: int) -> None:
            if n > longest:
                msg(MSG_CMD_TOO_LONG)

        if kind == KIND_PROBE:
            reply()
        elif kind == KIND_SERIAL:
            msg(MSG_SERIAL_ERROR)
        elif d0 == CMD_HB:
            if n >= 2 and d1 in (HB_UP + HB_ANSWER_OFFSET, HB_DOWN + HB_ANSWER_OFFSET):
                e.update(hb_answer_o=1, hb_answer_down_o=int(d1 == HB_DOWN + HB_ANSWER_OFFSET))
        elif d0 not in (CMD_DEBUG, CMD_RESET, CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST, CMD_PTIME_RD):
            msg(MSG_CMD_INVALID)
        elif d0 == CMD_RESET:  # any N; the reset's power-up message is its answer
            e["soft_reset_o"] = 1
        elif d0 == CMD_DEBUG:  # the echo, any N from 1 to 8, never cmdTooShort or cmdTooLong
            tail = [(v["pkt_tail_i"] >> (32 - 8 * j)) & 0xFF for j in range(5)]
            reply(*([d0, d1, d2] + tail)[:n])
        elif n == 1:
            msg(MSG_CMD_TOO_SHORT)
        elif d0 == CMD_DIG_CFG:
            if d1 >= self.n:
                msg(MSG_CMD_INDEX_ERR)
            elif n == 2:
                reply(CMD_DIG_CFG, d1, (DIGCFG_FIXED if bit(self.fixed_mask, d1) else 0) | cfg[d1])
            elif bit(self.fixed_mask, d1):
                msg(MSG_CONFIG_ERR)
            else:
                e.update(cfg_we_o=1, pin_sel_o=1 << d1, cfg_wdata_o=d2 & DIGCFG_STORED,
                         rearm_o=1 << d1)
                too_long(3)
        elif d0 == CMD_DIG_IO and n >= 3:
            if d1 >= self.n or is_input(d1):
                msg(MSG_CMD_INDEX_ERR)
            else:
                e.update(out_we_o=1, pin_sel_o=1 << d1, out_wdata_o=int(d2 != 0))
                too_long(3)
        elif d0 == CMD_DIG_IO:
            pin = d1 & DEVCODE_PIN
            if pin >= self.n or not is_input(pin):
                msg(MSG_CMD_INDEX_ERR)
            else:
                level = (v["level_i"] >> pin) & 1
                if d1 & DEVCODE_HOST:
                    reply(CMD_DEV_VAL, self.pin_id_base + pin, level)
                if d1 & DEVCODE_RFLX:
                    e.update(dio_rflx_o=1, dio_id_o=self.pin_id_base + pin, dio_val_o=level)
        elif d0 == CMD_DIG_RST:
            if d1 >= self.n:
                msg(MSG_CMD_INDEX_ERR)
            else:
                e["rearm_o"] = 1 << d1
                too_long(2)
        else:  # PTIME_RD
            pin = d1 & DEVCODE_PIN
            if pin >= self.n or not bit(self.timer_mask, pin) or not is_input(pin):
                msg(MSG_CMD_INDEX_ERR)
            elif bit(v["timer_busy_i"], pin):
                msg(MSG_TMR_CONFLICT)
            else:
                # the timer's number: the timers on the pins below
                tnum = bin(self.timer_mask & ((1 << pin) - 1)).count("1")
                e.update(timer_start_o=1 << pin, timer_go_o=1, timer_idx_o=tnum,
                         timer_host_o=int(bool(d1 & DEVCODE_HOST)),
                         timer_rflx_o=int(bool(d1 & DEVCODE_RFLX)))
                too_long(2)
        return e


class ExecTB(ClockedTB):
    INPUTS = dict(pkt_valid_i=0, pkt_kind_i=KIND_CMD, pkt_n_i=0, pkt_cmd_i=cmd_flags(0), pkt_d1_i=0,
                  pkt_sel_i=1, pkt_d2_i=0, pkt_tail_i=0, cfg_i=0, cfg_rd_i=0, level_i=0, timer_busy_i=0)
    PULSES = ("pkt_valid_i",)
    OUTPUTS = ALWAYS + ("pin_sel_o", "cfg_wdata_o", "out_wdata_o", "timer_idx_o", "timer_host_o",
                        "timer_rflx_o", "hb_answer_down_o", "reply_n_o", "reply_data_o",
                        "reply_tail_o", "dio_id_o", "dio_val_o")

    def drive(self, rst: int = 0, **inputs: int) -> dict[str, int]:
        """As ClockedTB's, with d0 and d1 put on the ports as bsd_parser hands them over:
        d0 decoded (pkt_cmd_i), d1 with its pin one-hot beside it (pkt_sel_i, held with
        d1); the values returned (the model's) name d0 itself, pkt_d0_i."""
        d0 = inputs.pop("pkt_d0_i", self.cur.pop("pkt_d0_i", 0))
        sel = pin_sel(inputs.get("pkt_d1_i", self.cur["pkt_d1_i"]), self.n)
        vals = super().drive(rst, pkt_cmd_i=cmd_flags(d0), pkt_sel_i=sel, **inputs)
        vals["pkt_d0_i"] = d0
        if self.cfg_mem:
            # cfg_rd_i: d1's pin's bits 4:1, as the memory shows them the clock after the
            # packet's (held until its outputs are sampled); cfg_i's bits 4:1 inverted, so
            # that a reply read from them fails (the values returned keep the model's).
            d1, cfg = vals["pkt_d1_i"], vals["cfg_i"]
            rd = pin_cfg(cfg, self.n, d1) >> 1 if d1 < self.n else 0
            self.dut.cfg_rd_i.value = rd
            self.dut.cfg_i.value = cfg ^ (((1 << 4 * self.n) - 1) << self.n)
            # the block decodes d1 itself: the parser's one-hot, a pin off, must not matter
            self.dut.pkt_sel_i.value = (sel << 1 | sel >> (self.n - 1)) & ((1 << self.n) - 1)
        return vals

    def __init__(self, dut) -> None:
        super().__init__(dut, "exec")
        self.model = ExecModel(hdl_params())
        self.n = self.model.n
        self.cfg_mem = bool(int(hdl_params().get("CFG_MEM", 0)))
        self.clocks = 0
        self.replies = 0

    def check(self, inputs, outputs, rst) -> None:
        self.clocks += 1
        exp = self.model.idle() if rst else self.model.decode(dict(inputs))
        self.model.exp = exp
        got = {k: outputs[k] for k in exp if not k.startswith("_")}
        if exp.get("reply_o"):
            nb = exp["reply_n_o"]
            data = outputs["reply_data_o"] << 32 | outputs["reply_tail_o"]
            got["_reply_bytes"] = [(data >> (56 - 8 * j)) & 0xFF for j in range(nb)]
            self.replies += 1
        assert got == {k: v for k, v in exp.items()}, (
            f"clock {self.clocks} {dict(inputs)}: DUT {got} != model {exp}")

    def state(self, cfg: list[int] | None = None, level: int = 0, busy: int = 0) -> dict:
        cfg = cfg if cfg is not None else [DIGCFG_IODIR] * self.n
        return dict(cfg_i=sum(((c >> k) & 1) << (k * self.n + p)
                              for p, c in enumerate(cfg) for k in range(5)), level_i=level,
                    timer_busy_i=busy)

    async def cmd(self, *data: int, n: int | None = None, kind: int = KIND_CMD,
                  **state: int) -> dict:
        """Hand over one packet (N = len(data) unless given); return stage 2's outputs."""
        d = list(data) + [0] * (3 - len(data))
        out = await self.step(pkt_valid_i=1, pkt_kind_i=kind,
                              pkt_n_i=len(data) if n is None else n,
                              pkt_d0_i=d[0], pkt_d1_i=d[1], pkt_d2_i=d[2], **state)
        idle = await self.step()
        assert all(idle[k] == 0 for k in ALWAYS if k != "s2_valid_o"), "strobes held over"
        await self.step()  # packets come at least three clocks apart
        return out

    def reply(self, out: dict) -> list[int] | None:
        if not out["reply_o"]:
            return None
        return [(out["reply_data_o"] >> (24 - 8 * j)) & 0xFF for j in range(out["reply_n_o"])]

    def pins(self) -> dict[str, list[int]]:
        m = self.model
        all_p = range(self.n)
        return dict(
            timer=[p for p in all_p if (m.timer_mask >> p) & 1],
            notimer=[p for p in all_p if not (m.timer_mask >> p) & 1],
            fixed=[p for p in all_p if (m.fixed_mask >> p) & 1],
            free=[p for p in all_p if not (m.fixed_mask >> p) & 1])


def message(code: int) -> list[int]:
    return [CMD_MSG, code]


@cocotb.test(skip=not runner.on("gp1", "pins7-fixed", "pins64"))
async def test_dig_cfg(dut) -> None:
    """Set: a cfg write of bits 4:0 to that pin and its re-arm, no reply; query: `26, pin,
    DIGCFG` with FIXED set on fixed pins; a fixed pin's set is configErr and changes nothing;
    pin >= NUM_PINS is cmdIndexErr for both forms."""
    tb = ExecTB(dut)
    await tb.reset()
    pins = tb.pins()
    cfg = [(0x15 + p) & 0x1F for p in range(tb.n)]
    for p in range(tb.n):
        fixed = p in pins["fixed"]
        out = await tb.cmd(CMD_DIG_CFG, p, 0xEA, **tb.state(cfg))
        if fixed:
            assert tb.reply(out) == message(MSG_CONFIG_ERR) and out["cfg_we_o"] == 0
            assert out["rearm_o"] == 0
        else:
            assert (out["cfg_we_o"], out["pin_sel_o"], out["cfg_wdata_o"]) == (1, 1 << p, 0x0A)
            assert out["rearm_o"] == 1 << p and out["reply_o"] == 0
        out = await tb.cmd(CMD_DIG_CFG, p, **tb.state(cfg))
        assert tb.reply(out) == [CMD_DIG_CFG, p, (DIGCFG_FIXED if fixed else 0) | cfg[p]]
    for bad in (tb.n, 0x40, 0x80 | 0, 255):
        for form in ((CMD_DIG_CFG, bad), (CMD_DIG_CFG, bad, 1)):
            out = await tb.cmd(*form)
            assert tb.reply(out) == message(MSG_CMD_INDEX_ERR), f"{form}"


@cocotb.test(skip=not runner.on("gp1", "pins7-fixed", "pins64"))
async def test_dig_io(dut) -> None:
    """Write: output latch <- value != 0 on an output pin, cmdIndexErr on an input pin or a
    bad pin; read (DEVCODE): HOST replies `4, PIN_ID_BASE+pin, level`, RFLX strobes the same
    value for the RFLX slot, both or neither; reading an output pin is cmdIndexErr."""
    tb = ExecTB(dut)
    await tb.reset()
    base = tb.model.pin_id_base
    outputs = [0] * tb.n
    inputs = [DIGCFG_IODIR] * tb.n
    for p in range(tb.n):
        for val, want in ((0, 0), (1, 1), (0x80, 1)):
            out = await tb.cmd(CMD_DIG_IO, p, val, **tb.state(outputs))
            assert (out["out_we_o"], out["pin_sel_o"], out["out_wdata_o"]) == (1, 1 << p, want)
            assert out["reply_o"] == 0
        out = await tb.cmd(CMD_DIG_IO, p, 1, **tb.state(inputs))
        assert tb.reply(out) == message(MSG_CMD_INDEX_ERR) and out["out_we_o"] == 0
        for level in (0, 1):
            st = tb.state(inputs, level=level << p)
            out = await tb.cmd(CMD_DIG_IO, DEVCODE_HOST | p, **st)
            assert tb.reply(out) == [CMD_DEV_VAL, base + p, level] and out["dio_rflx_o"] == 0
            out = await tb.cmd(CMD_DIG_IO, DEVCODE_RFLX | p, **st)
            assert out["reply_o"] == 0
            assert (out["dio_rflx_o"], out["dio_id_o"], out["dio_val_o"]) == (1, base + p, level)
            out = await tb.cmd(CMD_DIG_IO, DEVCODE_HOST | DEVCODE_RFLX | p, **st)
            assert tb.reply(out) == [CMD_DEV_VAL, base + p, level] and out["dio_rflx_o"] == 1
            out = await tb.cmd(CMD_DIG_IO, p, **st)
            assert out["reply_o"] == 0 and out["dio_rflx_o"] == 0, "neither bit: discarded"
        out = await tb.cmd(CMD_DIG_IO, DEVCODE_HOST | DEVCODE_RFLX | p, **tb.state(outputs))
        assert tb.reply(out) == message(MSG_CMD_INDEX_ERR) and out["dio_rflx_o"] == 0
    for bad in (tb.n, 63):
        if bad < tb.n:
            continue  # 64 pins: 63 is a pin, and no DEVCODE names one beyond it
        if bad < 64:
            out = await tb.cmd(CMD_DIG_IO, DEVCODE_HOST | bad, **tb.state(inputs))
            assert tb.reply(out) == message(MSG_CMD_INDEX_ERR)
        out = await tb.cmd(CMD_DIG_IO, bad, 1, **tb.state(outputs))
        assert tb.reply(out) == message(MSG_CMD_INDEX_ERR)


@cocotb.test(skip=not runner.on("gp1", "pins7-fixed", "pins64"))
async def test_dig_rst_and_ptime(dut) -> None:
    """DIG_RST re-arms its pin, silently even on an output pin (decision 6); PTIME_RD starts
    the pin's timer with the DEVCODE's HOST/RFLX bits, cmdIndexErr without a timer, on an
    output pin or out of range, tmrConflict while busy (no start)."""
    tb = ExecTB(dut)
    await tb.reset()
    pins = tb.pins()
    inputs, outputs = [DIGCFG_IODIR] * tb.n, [0] * tb.n
    for p in range(tb.n):
        for cfg in (inputs, outputs):
            out = await tb.cmd(CMD_DIG_RST, p, **tb.state(cfg))
            assert out["rearm_o"] == 1 << p and out["reply_o"] == 0
    out = await tb.cmd(CMD_DIG_RST, tb.n)
    assert tb.reply(out) == message(MSG_CMD_INDEX_ERR) and out["rearm_o"] == 0
    for p in pins["timer"]:
        for bits in (0, DEVCODE_HOST, DEVCODE_RFLX, DEVCODE_HOST | DEVCODE_RFLX):
            out = await tb.cmd(CMD_PTIME_RD, bits | p, **tb.state(inputs))
            assert out["timer_start_o"] == 1 << p and out["reply_o"] == 0
            assert (out["timer_host_o"], out["timer_rflx_o"]) == (
                int(bool(bits & DEVCODE_HOST)), int(bool(bits & DEVCODE_RFLX)))
        out = await tb.cmd(CMD_PTIME_RD, DEVCODE_HOST | p, **tb.state(inputs, busy=1 << p))
        assert tb.reply(out) == message(MSG_TMR_CONFLICT) and out["timer_start_o"] == 0
        # another pin's busy timer does not matter
        out = await tb.cmd(CMD_PTIME_RD, DEVCODE_HOST | p,
                           **tb.state(inputs, busy=((1 << tb.n) - 1) & ~(1 << p)))
        assert out["timer_start_o"] == 1 << p
        out = await tb.cmd(CMD_PTIME_RD, DEVCODE_HOST | p, **tb.state(outputs))
        assert tb.reply(out) == message(MSG_CMD_INDEX_ERR) and out["timer_start_o"] == 0
    for p in pins["notimer"] + ([tb.n] if tb.n < 64 else []):
        out = await tb.cmd(CMD_PTIME_RD, DEVCODE_HOST | p, **tb.state(inputs, busy=0))
        assert tb.reply(out) == message(MSG_CMD_INDEX_ERR) and out["timer_start_o"] == 0


@cocotb.test(skip=not runner.on("gp1", "pins7-fixed"))
async def test_precedence(dut) -> None:
    """cmdInvalid (any N >= 1) before cmdTooShort before the command's own error; cmdTooLong
    only after a success (with its action); an error with extra bytes is only the error."""
    tb = ExecTB(dut)
    await tb.reset()
    pins = tb.pins()
    inputs = [DIGCFG_IODIR] * tb.n
    t = pins["timer"][0]
    for code in (1, CMD_DEV_VAL, CMD_MSG, 0x63, 0xFF, 30, 25):
        for n in (1, 2, 8):
            out = await tb.cmd(code, tb.n, n=n)
            assert tb.reply(out) == message(MSG_CMD_INVALID), f"code {code} N={n}"
    for code in (CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST, CMD_PTIME_RD):
        out = await tb.cmd(code, tb.n, n=1)
        assert tb.reply(out) == message(MSG_CMD_TOO_SHORT), f"code {code}"
        assert all(out[k] == 0 for k in ALWAYS if k not in ("s2_valid_o", "reply_o"))
    for n in range(4, MAX_N + 1):   # longest forms 3, 3, 2, 2
        out = await tb.cmd(CMD_DIG_CFG, 0 if 0 in pins["free"] else pins["free"][0], 3, n=n,
                           **tb.state(inputs))
        assert out["cfg_we_o"] == 1 and tb.reply(out) == message(MSG_CMD_TOO_LONG)
        out = await tb.cmd(CMD_DIG_IO, 0, 1, n=n, **tb.state([0] * tb.n))
        assert out["out_we_o"] == 1 and tb.reply(out) == message(MSG_CMD_TOO_LONG)
        out = await tb.cmd(CMD_DIG_CFG, tb.n, 3, n=n)
        assert tb.reply(out) == message(MSG_CMD_INDEX_ERR)
        out = await tb.cmd(CMD_DIG_IO, 0, 1, n=n, **tb.state(inputs))
        assert tb.reply(out) == message(MSG_CMD_INDEX_ERR)
        if pins["fixed"]:
            out = await tb.cmd(CMD_DIG_CFG, pins["fixed"][0], 3, n=n)
            assert tb.reply(out) == message(MSG_CONFIG_ERR)
    for n in range(3, MAX_N + 1):
        out = await tb.cmd(CMD_DIG_RST, 0, 0, n=n)
        assert out["rearm_o"] == 1 and tb.reply(out) == message(MSG_CMD_TOO_LONG)
        out = await tb.cmd(CMD_PTIME_RD, DEVCODE_HOST | t, 0, n=n, **tb.state(inputs))
        assert out["timer_start_o"] == 1 << t and tb.reply(out) == message(MSG_CMD_TOO_LONG)
        out = await tb.cmd(CMD_PTIME_RD, DEVCODE_HOST | t, 0, n=n, **tb.state(inputs, busy=1 << t))
        assert tb.reply(out) == message(MSG_TMR_CONFLICT)
        out = await tb.cmd(CMD_DIG_RST, tb.n, 0, n=n)
        assert tb.reply(out) == message(MSG_CMD_INDEX_ERR)
    # DIG_IO with N = 2 is a read: never cmdTooLong
    out = await tb.cmd(CMD_DIG_IO, DEVCODE_HOST, **tb.state(inputs))
    assert tb.reply(out)[0] == CMD_DEV_VAL


@cocotb.test(skip=not runner.on("gp1"))
async def test_probe_serial_hb(dut) -> None:
    """The resync probe replies `A, 0`; serialError for N > 8; cmdHB is always silent and
    answers only with N >= 2 and type 2 (UP) or 3 (DOWN), whatever follows."""
    tb = ExecTB(dut)
    await tb.reset()
    out = await tb.cmd(n=0, kind=KIND_PROBE)
    assert (out["reply_o"], out["reply_n_o"]) == (1, 0)
    out = await tb.cmd(n=9, kind=KIND_SERIAL)
    assert tb.reply(out) == message(MSG_SERIAL_ERROR)
    for n in range(1, MAX_N + 1):
        for typ in range(6):
            out = await tb.cmd(CMD_HB, typ, n=n)
            assert out["reply_o"] == 0
            answers = n >= 2 and typ in (HB_UP + HB_ANSWER_OFFSET, HB_DOWN + HB_ANSWER_OFFSET)
            assert out["hb_answer_o"] == int(answers), f"N={n} type {typ}"
            if answers:
                assert out["hb_answer_down_o"] == int(typ == HB_DOWN + HB_ANSWER_OFFSET)


@cocotb.test(skip=not runner.on("gp1"))
async def test_strobe_clock(dut) -> None:
    """The strobes and the reply show on exactly one clock, the one after pkt_valid_i; the
    pin state counts as it was on the pkt_valid_i clock (a change a clock later is not seen)."""
    tb = ExecTB(dut)
    await tb.reset()
    inputs = [DIGCFG_IODIR] * tb.n
    await tb.step(**tb.state(inputs, level=0b1))
    out = await tb.step(pkt_valid_i=1, pkt_n_i=2, pkt_d0_i=CMD_DIG_IO, pkt_d1_i=DEVCODE_HOST,
                        **tb.state(inputs, level=0b1))
    assert tb.reply(out) == [CMD_DEV_VAL, tb.model.pin_id_base, 1]
    out = await tb.step(**tb.state([0] * tb.n, level=0))  # state changes after the packet
    assert out["reply_o"] == 0 and out["s2_valid_o"] == 0
    await tb.step(**tb.state([0] * tb.n, level=0))  # packets come at least three clocks apart
    out = await tb.step(pkt_valid_i=1, pkt_n_i=2, pkt_d0_i=CMD_PTIME_RD, pkt_d1_i=1,
                        **tb.state(inputs))
    assert out["timer_start_o"] == 0b10
    out = await tb.step(**tb.state(inputs, busy=0b10))
    assert out["timer_start_o"] == 0 and out["reply_o"] == 0
    await tb.step(**tb.state(inputs, busy=0b10))
    # reset drops a packet in stage 2
    await tb.step(pkt_valid_i=1, pkt_n_i=2, pkt_d0_i=CMD_DIG_RST, pkt_d1_i=0)
    await tb.step(rst=1, pkt_valid_i=1, pkt_n_i=2, pkt_d0_i=CMD_DIG_RST, pkt_d1_i=0)
    out = await tb.step()
    assert out["rearm_o"] == 0 and out["s2_valid_o"] == 0


@cocotb.test(skip=not runner.on("gp1"))
async def test_debug_echo(dut) -> None:
    """cmdDEBUG is echoed whole for every N from 1 to 8: `23, d1 .. d(N-1)` as the reply."""
    tb = ExecTB(dut)
    await tb.reset()
    data = [0x17, 0xA1, 0xB2, 0xC3, 0xD4, 0xE5, 0xF6, 0x07]
    tail = int.from_bytes(bytes(data[3:]), "big")
    for n in range(1, MAX_N + 1):
        out = await tb.step(pkt_valid_i=1, pkt_n_i=n, pkt_d0_i=CMD_DEBUG, pkt_d1_i=data[1],
                            pkt_d2_i=data[2], pkt_tail_i=tail)
        assert out["reply_o"] and out["reply_n_o"] == n, out
        await tb.steps(2)


@cocotb.test()
async def test_random_vs_model(dut) -> None:
    """Random packets (every kind, code, N, pin and DEVCODE byte) over random pin state,
    three clocks apart (the closest the parser hands them over) or more, rare resets; the
    model checked on every clock."""
    tb = ExecTB(dut)
    rng = tb.rng
    await tb.reset()
    codes = [CMD_HB, CMD_DEBUG, CMD_RESET, CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST, CMD_PTIME_RD]
    strobes = 0
    for _ in range(2500):
        kind = rng.choice([KIND_CMD] * 8 + [KIND_PROBE, KIND_SERIAL])
        d0 = rng.choice(codes * 4 + [rng.randrange(256)])
        pin = rng.randrange(tb.n + 2) if rng.random() < 0.9 else rng.randrange(256)
        d1 = rng.choice([pin, pin | (rng.randrange(4) << 6) if pin < 64 else pin,
                         rng.randrange(6)])
        st = dict(cfg_i=rng.getrandbits(5 * tb.n), level_i=rng.getrandbits(tb.n),
                  timer_busy_i=rng.getrandbits(tb.n) if rng.random() < 0.5 else 0)
        n = rng.randrange(1, MAX_N + 1) if kind == KIND_CMD else (0 if kind == KIND_PROBE else 9)
        out = await tb.step(rst=int(rng.random() < 0.003), pkt_valid_i=1, pkt_kind_i=kind,
                            pkt_n_i=rng.choice([n, min(n, 3), min(n, 2)]), pkt_d0_i=d0,
                            pkt_d1_i=d1, pkt_d2_i=rng.choice([0, 1, rng.randrange(256)]),
                            pkt_tail_i=rng.getrandbits(40), **st)
        strobes += out["cfg_we_o"] + out["out_we_o"] + (out["timer_start_o"] != 0)
        for _ in range(rng.choice([2, 2, 3, 4])):  # as close as the parser hands them over
            await tb.step(**st)
    # A guard that the draw reaches the strobes and replies at all (the model checks each one):
    # pins7-fixed gave 99 strobes at seed 169304783, so the bound sits well below the counts.
    assert strobes > 50 and tb.replies > 800, (strobes, tb.replies)


@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, quick="icarus"))
def test_bsd_exec(sim: str, build: str) -> None:
    runner.run(sim, "bsd_exec", __file__, BUILDS[build], build)
