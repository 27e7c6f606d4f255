#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Each proof bites: each mutant's task, set up by make in a temporary FORMAL_WORK with the mutant
written into its src/ copy (rtl/ is never touched), must end as expected: FAIL unless given
(UNKNOWN: only the induction step fails). docs/formal.md records the results.

    formal/mutants.py [job ...]    every mutant, or those of the named jobs
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# (job, task, file, what it breaks, original text, mutant text[, expected result])
MUTANTS = [
    ("bsd_axis_skid", "prove", "bsd_axis_skid.v", "draining the skid sends the input word instead of the skid word",
     "out_data_q <= skid_valid_q ? skid_q : s_axis_tdata;", "out_data_q <= s_axis_tdata;"),
    ("bsd_fifo", "prove", "bsd_fifo.v", "full flag never set: the RAM overflows",
     "ram_full_q  <= !pop && step(wr_q) == rd_q;", "ram_full_q  <= 1'b0;"),
    ("bsd_fifo", "prove", "bsd_fifo.v", "a read while the output waits overwrites the read register: the head is lost",
     "        end else if (pop && out_valid_q && !m_axis_tready) begin", "        end else if (1'b0) begin"),
    ("bsd_timer_bank", "prove", "bsd_timer_bank.v",
     "a run with RFLX alone owes no result: free as it ends, before its strobe (busy until delivered broken)",
     "(start & {NUM_TIMERS{host_i || rflx_i}})", "(start & {NUM_TIMERS{host_i}})"),
    ("bsd_timeout_wheel", "prove", "bsd_timeout_wheel.v",
     "a scan that read the start a restart is overwriting inserts the previous run's timeout",
     "stale_q  <= st_q || start_any_i || (!advance && stale_q);", "stale_q  <= st_q || (!advance && stale_q);"),
    ("bsd_timeout_wheel", "prove", "bsd_timeout_wheel.v",
     "a restart after its slot was read expires at the previous run's timeout",
     "assign expire_o = expire_q & ins_q;", "assign expire_o = expire_q;"),
    ("bsd_timeout_wheel", "prove", "bsd_timeout_wheel.v", "an insert sets every bit of its slot (the bit mask ignored)",
     "if (w_mask[b]) w_word[b] = w_bit;", "w_word[b] = w_bit;"),
    ("bsd_timeout_wheel", "prove", "bsd_timeout_wheel.v", "an insert never marks its timer inserted: it never times out",
     "ins_q    <= ((insert ? ins_q | (ins_bit & run_i) : ins_q) & ~start_i);",
     "ins_q    <= ((clear ? ins_q | (ins_bit & run_i) : ins_q) & ~start_i);", "UNKNOWN"),
    ("bsd_timeout_wheel", "prove", "bsd_timeout_wheel.v",
     "a scan marks an idle timer inserted: expire_o names a timer that is not running",
     "ins_q | (ins_bit & run_i)", "ins_q | ins_bit"),
    ("bsd_drain", "prove", "bsd_drain.v", "the DIG_IO value always goes first, even above a lower timer ID",
     "rank_t    = |(r & ranks_of(dio_id_q)) | (RANK_IDX && any_t);", "rank_t    = (RANK_IDX && any_t);"),
    ("bsd_drain", "prove_memc", "bsd_drain.v",
     "consecutive IDs, memory form: no hold, the DIG_IO value goes after every timer",
     "assign hold = a_t_q && dio_q && {1'b0, ID0} + {1'b0, a_k_q} > {1'b0, dio_id_q};", "assign hold = 1'b0;"),
    ("bsd_drain", "prove_memc", "bsd_drain.v",
     "consecutive IDs, memory form: the value goes before a timer of its own ID",
     "{1'b0, ID0} + {1'b0, a_k_q} > {1'b0, dio_id_q};", "{1'b0, ID0} + {1'b0, a_k_q} >= {1'b0, dio_id_q};"),
    ("bsd_drain", "prove_memc", "bsd_drain.v", "consecutive IDs, memory form: a hold strobes no DIG_IO value",
     "            b_dio_q     <= 1'b1;\n", ""),
    ("bsd_drain", "prove_memc", "bsd_drain.v",
     "consecutive IDs, memory form: a hold also passes stage A's timer on (its packet twice)",
     "            b_ord_q     <= 1'b0;\n", ""),
    ("bsd_drain", "prove_memc", "bsd_drain.v",
     "consecutive IDs, memory form: a hold leaves the DIG_IO value waiting: it goes twice",
     "        if (hold) dio_q <= 1'b0;\n", ""),
    ("bsd_drain", "prove_t10", "bsd_drain.v",
     "every group of timers picks its lowest, not only the lowest group with a timer",
     "1'b1}) & {GS{!below}};", "1'b1});"),
    ("bsd_drain", "prove", "bsd_drain.v", "the empty flag ignores whether the new entry has items",
     "empty_q   <= !(ev_valid_i && ev_items);", "empty_q   <= !ev_valid_i;"),
    ("bsd_drain", "prove_mem", "bsd_drain.v", "a pending start's word is never written (only a start's own clock writes)",
     "end else if (hp_q || start_i) begin", "end else if (start_i) begin"),
    ("bsd_drain", "prove_mem", "bsd_drain.v", "no hold while a start's word is pending: a second start may overwrite it",
     "            assign hold_o     = hp_q;", "            assign hold_o     = 1'b0;"),
    ("bsd_drain", "prove_mem", "bsd_drain.v", "the pending word is written at the start port's index, not its own timer's",
     "wire [5:0] hr_a   = a_t_q ? a_k_q : hp_q ? hp_k_q : start_idx_i;",
     "wire [5:0] hr_a   = a_t_q ? a_k_q : start_idx_i;"),
    ("bsd_drain", "prove_mem", "bsd_drain.v", "the memory form loses a reply or heartbeat after a finish without HOST",
     "assign b_ord_w    = b_ord_q && (b_rep_q || b_hb_q || hr_rd_q[1]);", "assign b_ord_w    = b_ord_q && hr_rd_q[1];"),
    ("bsd_drain", "prove_mem", "bsd_drain.v", "a finish without HOST still queues its packet",
     "assign b_ord_w    = b_ord_q && (b_rep_q || b_hb_q || hr_rd_q[1]);", "assign b_ord_w    = b_ord_q;"),
    ("bsd_drain", "prove_mem", "bsd_drain.v", "a finish with HOST and RFLX releases its timer at the strobe",
     "assign b_free_w   = b_rdone_q && hr_rd_q[0] && !hr_rd_q[1];", "assign b_free_w   = b_rdone_q && hr_rd_q[0];"),
    ("bsd_drain", "prove_mem", "bsd_drain.v",
     "a start with a timer in stage A is written at once, at stage A's timer's address, and read no word",
     "                if (a_t_q) begin\n                    hr_rd_q", "                if (a_t_q && !start_i) begin\n                    hr_rd_q"),
    ("bsd_drain", "prove_mem", "bsd_drain.v",
     "an entry with timer events is taken from the queue as it loads: stage A reads the next one's r, f and T",
     "assign ev_ready_o = next && (held_q || !ev_t);", "assign ev_ready_o = next;"),
    ("bsd_drain", "prove_mem", "bsd_drain.v",
     "in the memory form no timer counts as left after the pick: an entry of two timers ends after one",
     "two_t     = MEM ? any_t :", "two_t     = MEM ? 1'b0 :"),
    ("bsd_drain", "prove_mem", "bsd_drain.v", "the clock that takes a held entry loads it again",
     "    wire          load = next && !held;", "    wire          load = next;"),
    ("bsd_pkt_tx", "prove", "bsd_pkt_tx.v", "tlast one byte late (on byte N + 2)",
     "!last_q && rem_q == 4'd0 :", "!last_q && rem_q == 4'd15 :"),
    ("bsd_pkt_tx", "prove", "bsd_pkt_tx.v", "free_o (the output queue's pop) on every handshake, not only the last",
     "assign free_o        = !valid_q || (hs && last_q);", "assign free_o        = !valid_q || hs;"),
    ("bsd_pkt_tx", "prove", "bsd_pkt_tx.v", "a reply's d4..d7 sent before its d0..d3",
     "wire [63:0] rep_bytes = {rep_data_i, rep_tail_i};", "wire [63:0] rep_bytes = {rep_tail_i, rep_data_i};", "UNKNOWN"),
    ("bsd_pkt_tx", "prove", "bsd_pkt_tx.v", "cmdRESET keeps a packet offered but not taken: no power-up message",
     "wire       swap = flush_i && valid_q && first_q && !m_axis_tready;", "wire       swap = 1'b0;"),
    ("bsd_pkt_tx", "prove", "bsd_pkt_tx.v", "cmdRESET swaps a packet whose address is taken on its clock",
     "wire       swap = flush_i && valid_q && first_q && !m_axis_tready;",
     "wire       swap = flush_i && valid_q && first_q;"),
    ("bsd_pkt_tx", "prove", "bsd_pkt_tx.v", "a swapped packet keeps the replaced packet's N",
     "rem_q      <= MSG_N[3:0];", "rem_q      <= rem_q;"),
    ("bsd_pkt_tx", "prove", "bsd_pkt_tx.v", "an item is taken on cmdRESET's clock (from a queue being reset)",
     "wire       free = !flush_i && free_o;", "wire       free = free_o;"),
    ("bsd_pkt_tx", "prove", "bsd_pkt_tx.v", "a packet under way at cmdRESET still reports its done",
     "(credit_q && !(flush_i && !swap))", "credit_q"),
    ("bsd_trans_latch", "prove", "bsd_trans_latch.v", "arming keeps the old sample: a level present at arming fires",
     "prev_q  <= prev_q ^ ((prev_q ^ level_i) & arm_i);", "prev_q  <= prev_q;"),
    ("bsd_trans_latch", "prove", "bsd_trans_latch.v", "a sample does not move the previous sample (only an arm does)",
     "            prev_q  <= level_i;\n", "            prev_q  <= prev_q ^ ((prev_q ^ level_i) & arm_i);\n"),
    ("bsd_tick_gen", "prove_clk2m", "bsd_tick_gen.v", "the accumulator steps by INC + 1: the rate is too high",
     "acc_q  <= acc_q + (wrap ? INC_W - MOD_W : INC_W);",
     "acc_q  <= acc_q + (wrap ? INC_W - MOD_W : INC_W) + 1'b1;"),
    ("bsd_msg_merge", "prove", "bsd_msg_merge.v", "the message takes over from a stalled stream byte",
     "wire start    = req_i && !mid_q && !stall_q && !msg_q;", "wire start    = req_i && !mid_q && !msg_q;"),
    ("bsd_uart_tx", "prove", "bsd_uart_tx.v", "ready a bit early: the next byte cuts the stop bit short",
     "ready_q <= (left_q == 4'd1) && penult;",
     "ready_q <= (left_q == 4'd2) && penult;", "UNKNOWN"),
    ("bsd_uart_tx", "bmc", "bsd_uart_tx.v", "ready a bit early, against the BMC of a whole frame",
     "ready_q <= (left_q == 4'd1) && penult;", "ready_q <= (left_q == 4'd2) && penult;"),
    ("bsd_uart_tx", "prove", "bsd_uart_tx.v", "ready stays up after a byte is taken: the next byte restarts the frame",
     "            ready_q <= 1'b0;\n", "            ready_q <= 1'b1;\n"),
    ("bsd_uart_rx", "prove", "bsd_uart_rx.v", "one synchronizer flop: the line reaches the state machine a clock early",
     "        rx_q        <= meta_q;\n", "        rx_q        <= rx_i;\n"),
    ("bsd_uart_rx", "bmc", "bsd_uart_rx.v", "stop bit not checked: a frame with a 0 stop bit gives a byte",
     "                    if (rx_q) begin\n", "                    if (1'b1) begin\n"),
    ("bsd_parser", "prove", "bsd_parser.v", "N = 9..15 taken as a command's length: N > 8 reaches the executor",
     "len_over = (|b[7:4]) | (b[3] & (|b[2:0]));", "len_over = (|b[7:4]);"),
    ("bsd_tick_gen", "prove_inc1", "bsd_tick_gen.v", "the LFSR divider wraps a clock early: a strobe every MOD - 1 clocks",
     "WRAP_POW = lfsr_pow(MOD0 - 1, LW, LFSR_P);", "WRAP_POW = lfsr_pow(MOD0 - 2, LW, LFSR_P);"),
    ("bsd_parser", "prove", "bsd_parser.v", "the idle LFSR's end one tick early: a partial packet dropped too soon",
     "IDLE_POW = lfsr_pow(TIMEOUT_TICKS - 1, LW, LFSR_P);",
     "IDLE_POW = lfsr_pow(TIMEOUT_TICKS - 2, LW, LFSR_P);", "UNKNOWN"),
    ("brainstem_dio", "bmc", "brainstem_dio.v", "bsd_pkt_tx never sees the sink's stall: a stalled byte is replaced",
     ".m_axis_tready (m_axis_tready),", ".m_axis_tready (1'b1),"),
    ("brainstem_dio", "reset_bmc", "bsd_pkt_tx.v",
     "cmdRESET keeps a packet offered but not taken: the power-up message is not next",
     "wire       swap = flush_i && valid_q && first_q && !m_axis_tready;", "wire       swap = 1'b0;"),
    ("brainstem_dio", "reset_bmc", "brainstem_dio.v", "cmdRESET leaves the pin configuration as it was",
     ".rst         (core_rst),\n        .cfg_we_i", ".rst         (rst),\n        .cfg_we_i"),
    ("bsd_sync", "prove", "bsd_sync.v", "one flop: the pad level is seen one clock early",
     "sync_q <= meta_q;", "sync_q <= d_i;"),
    ("bsd_cfg_regs", "prove", "bsd_cfg_regs.v", "fixed pins get a writable register (reset 0x01, not FIXED_CFG)",
     ("((g == 2 ? trg_w : cfg_q[g*NUM_PINS +: NUM_PINS]) & ~FIXED_MASK) |\n"
      "                                                       (FIXED_F[g*NUM_PINS +: NUM_PINS] & FIXED_MASK);"),
     "(g == 2 ? trg_w : cfg_q[g*NUM_PINS +: NUM_PINS]);"),
    ("bsd_cfg_regs", "prove", "bsd_cfg_regs.v",
     "a configuration write lands in every free pin, not only the addressed one",
     "if (sel_i[p]) begin", "if (1'b1) begin"),
    ("bsd_cfg_regs", "prove", "bsd_cfg_regs.v", "an output write lands in every pin, not only the addressed one",
     "out_q <= (out_q & ~sel_i) | (sel_i & {NUM_PINS{out_wdata_i}});", "out_q <= {NUM_PINS{out_wdata_i}};"),
    ("bsd_cfg_regs", "prove_mem", "bsd_cfg_regs.v",
     "with the memory, reset starts no sweep: a word written before it reads back after it",
     "clr_q     <= 1'b1;", "clr_q     <= clr_q;"),
    ("bsd_cfg_regs", "prove_mem", "bsd_cfg_regs.v", "with the memory, the sweep stops a pin short",
     "if (clr_pin_q == LAST_PIN) clr_q <= 1'b0;", "if (clr_pin_q == LAST_PIN - 6'd1) clr_q <= 1'b0;"),
    ("bsd_cfg_regs", "prove_mem", "bsd_cfg_regs.v", "with the memory, the sweep writes a fixed pin's word as a free one's",
     "mem[mem_addr] <= RESET_WORDS[4*clr_pin_q +: 4];", "mem[mem_addr] <= 4'd0;"),
    ("bsd_cfg_regs", "prove_mem", "bsd_cfg_regs.v", "with the memory, a configuration write lands in a fixed pin's word",
     "if (!(|(sel_i & FIXED_MASK))) mem[mem_addr]", "if (1'b1) mem[mem_addr]"),
    ("bsd_cfg_regs", "prove_mem", "bsd_cfg_regs.v", "with the memory, busy_o drops while the sweep runs",
     "assign busy_o  = clr_q;", "assign busy_o  = 1'b0;"),
    ("bsd_cfg_regs", "prove_mem", "bsd_cfg_regs.v", "with the memory, a read past the last pin shows a word",
     "rd_ok_q <= PIN_ADDR[addr_i];", "rd_ok_q <= 1'b1;"),
    ("bsd_cfg_regs", "prove_mem", "bsd_cfg_regs.v", "with the memory, the word keeps IODIR where ENA belongs",
     "mem[mem_addr] <= cfg_wdata_i[4:1];", "mem[mem_addr] <= {cfg_wdata_i[4:2], cfg_wdata_i[0]};"),
    ("bsd_cfg_regs", "prove_mem", "bsd_cfg_regs.v", "with the memory, a write's TRG lands in every pin's flop",
     "trg_q     <= (trg_q & ~sel_i) | (sel_i & {NUM_PINS{cfg_wdata_i[2]}});",
     "trg_q     <= {NUM_PINS{cfg_wdata_i[2]}};"),
    ("bsd_cfg_regs", "prove_mem", "bsd_cfg_regs.v", "with the memory, the word keeps no TRG: a read shows TRG 0",
     "mem[mem_addr] <= cfg_wdata_i[4:1];", "mem[mem_addr] <= {cfg_wdata_i[4:3], 1'b0, cfg_wdata_i[1]};"),
    ("bsd_cfg_regs", "prove_mem", "bsd_cfg_regs.v", "with the memory, rd_cfg_o's TRG is pin 0's flop, not the read pin's",
     "assign rd_cfg_o = rd_bits;", "assign rd_cfg_o = {rd_bits[3:2], cfg_o[2*NUM_PINS], rd_bits[0]};"),
    ("bsd_heartbeat", "prove", "bsd_heartbeat.v", "a heartbeat due while the previous one is unsent keeps the link up",
     "if (!answered || req_q) link_up_q <= 1'b0;", "if (!answered) link_up_q <= 1'b0;", "UNKNOWN"),
    ("bsd_heartbeat", "bmc", "bsd_heartbeat.v", "the same, against the BMC from any state that meets the invariants",
     "if (!answered || req_q) link_up_q <= 1'b0;", "if (!answered) link_up_q <= 1'b0;"),
    ("bsd_heartbeat", "bmc", "bsd_heartbeat.v",
     "the type toggles from reset: after a reset the first heartbeat may be DOWN",
     "down_q     <= queued_q ? !down_q : 1'b0;", "down_q     <= !down_q;"),
    ("bsd_reply_slot", "prove", "bsd_reply_slot.v",
     "the one-clock request (reply_q) is not kept: a reply not taken at once is lost",
     "wire rep_wait_d = rep_req_o && !rep_done_i;", "wire rep_wait_d = rep_wait_q && !rep_done_i;"),
    ("bsd_reply_slot", "prove", "bsd_reply_slot.v",
     "a reset with the transmitter's swap still marks the power-up message new: it is queued twice",
     "new_q       <= !swap_i;", "new_q       <= 1'b1;"),
    ("bsd_exec", "prove", "bsd_exec.v",
     "a DIG_CFG read of a pin beyond the last answers the pin's byte, not cmdIndexErr (stage 2's override)",
     "(idx_err_q ? MSG_CMD_INDEX_ERR : b1_q) |", "b1_q |"),
    ("bsd_exec", "prove", "bsd_exec.v",
     "a DIG_CFG write to a fixed pin is strobed (and re-arms it) instead of configErr",
     "cfg_w   = c_cfg && pin_ok && !sel_fixed;", "cfg_w   = c_cfg && pin_ok;"),
    ("bsd_exec", "prove_t2", "bsd_exec.v", "the timer numbers counted from 1: a start names the next timer",
     "num = 6'h3F;  // the pin before pin 0", "num = 6'h00;"),
    ("bsd_exec", "prove_t2", "bsd_exec.v",
     "a PTIME_RD of an input pin without a timer answers tmrConflict, not cmdIndexErr",
     "sel_timer  = &TIMER_MASK ? dev_ok : |(sel & TIMER_MASK);", "sel_timer  = &TIMER_MASK ? dev_ok : |sel;"),
    ("bsd_exec", "prove_all", "bsd_exec.v",
     "with a timer on every pin, no pin counts as a timer pin: every PTIME_RD answers cmdIndexErr",
     "sel_timer  = &TIMER_MASK ? dev_ok :", "sel_timer  = &TIMER_MASK ? 1'b0 :"),
    ("bsd_exec", "prove_mem", "bsd_exec.v", "with CFG_MEM, a DIG_CFG read answers ENA for TRG and TRG for ENA",
     "CFG_MEM ? cfg_rd_i :", "CFG_MEM ? {cfg_rd_i[3:2], cfg_rd_i[0], cfg_rd_i[1]} :"),
    ("bsd_exec", "prove_t9", "bsd_exec.v",
     "more than 8 timers: the start strobes' clear ignores the busy bit: a running timer restarts",
     "|(in & sel & TIMER_MASK) && !(|(busy & sel & TIMER_MASK));", "|(in & sel & TIMER_MASK);"),
    ("bsd_exec", "prove", "bsd_exec.v",
     "up to 8 timers: a start strobe's AND ignores the busy bit: a running timer restarts",
     "sel & TIMER_MASK & in & ~busy & {NUM_PINS{c_time}}", "sel & TIMER_MASK & in & {NUM_PINS{c_time}}"),
    ("bsd_exec", "prove_t9m", "bsd_exec.v",
     "more than 8 timers with CFG_MEM: a start strobe's AND ignores the busy bit: a running timer restarts",
     "sel & TIMER_MASK & in & ~busy & {NUM_PINS{c_time}}", "sel & TIMER_MASK & in & {NUM_PINS{c_time}}"),
    ("bsd_exec", "prove_t9m", "bsd_exec.v",
     "more than 8 timers with CFG_MEM: the strobes load the pin's line, and nothing clears them",
     "START_AND ? sel & TIMER_MASK & in", "FEW_TIMERS ? sel & TIMER_MASK & in"),
    ("bsd_parser", "prove", "bsd_parser.v",
     "d1's slot also loads on the handover's clock: stage 2 reads the next byte as the pin",
     "        if (pos_q[1]) begin\n", "        if (pos_q[1] || pkt_valid_q) begin\n", "UNKNOWN"),
    ("bsd_parser", "prove", "bsd_parser.v", "d1's one-hot from bits 4:0: a DEVCODE pin of 32 or more names a pin",
     "pkt_sel_q <= SEL_ONE << s_axis_tdata[5:0];", "pkt_sel_q <= SEL_ONE << s_axis_tdata[4:0];"),
]


def run(job: str, task: str, fname: str, old: str, new: str) -> tuple[str, list[str]]:
    """sby's result (PASS, FAIL, UNKNOWN, ERROR) of the task with the mutant, and what failed."""
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp) / f"{job}_{task}"
        make = ["make", "-s", "--no-print-directory", "-C", str(ROOT), f"FORMAL_WORK={tmp}"]
        subprocess.run([*make, f"{work}/config.sby"], check=True)
        src = work / "src" / fname
        text = src.read_text()
        if text.count(old) != 1:
            raise SystemExit(f"{job} {task}: the mutant's text is not in {fname} exactly once")
        src.write_text(text.replace(old, new))
        subprocess.run([*make, f"{work}/PASS"], check=False, capture_output=True)
        log = (work / "logfile.txt").read_text().splitlines()
        failed = [ln.split("summary:")[-1].strip() for ln in log if "failed assertion" in ln or "Unreached" in ln]
        return (work / "status").read_text().split()[0], failed[:2]


def main(only: list[str]) -> int:
    todo = [m for m in MUTANTS if not only or m[0] in only]
    if not todo or not set(only) <= {m[0] for m in MUTANTS}:
        print(f"mutants.py: no mutants of {' '.join(only)}; jobs: {' '.join(sorted({m[0] for m in MUTANTS}))}",
              file=sys.stderr)
        return 2
    bad = 0
    for job, task, fname, what, old, new, *exp in todo:
        expected = exp[0] if exp else "FAIL"
        result, failed = run(job, task, fname, old, new)
        bad += result != expected
        print(f"{job:17} {task:11} {result:7} {'' if result == expected else f'(expected {expected}) '}{what}")
        for line in failed:
            print(f"    {line}")
    print(f"{len(todo) - bad} of {len(todo)} mutants caught as expected")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
