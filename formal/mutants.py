#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Show that each proof bites: apply one mutant to the RTL, run the job's task, expect it
not to pass, restore the RTL. Edits rtl/ in place (restored even on error): run it only in
a work tree of your own, never beside other work. docs/formal.md records the results.

    formal/mutants.py            every mutant
    formal/mutants.py bsd_fifo   the mutants of the named jobs
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import run as formal_run

RTL = Path(__file__).resolve().parents[1] / "rtl"

# (job, task, file, original text, mutant text, what it breaks[, expected result]): the
# expected result is FAIL (a counterexample) unless given; a mutant is caught when the task
# does not pass, and the run fails when a mutant passes or gives other than its expected result.
MUTANTS = [
    ("bsd_axis_skid", "prove", "bsd_axis_skid.v",
     "out_data_q   <= skid_q;", "out_data_q   <= s_axis_tdata;",
     "draining the skid sends the input word instead of the skid word"),
    ("bsd_fifo", "prove", "bsd_fifo.v",
     "wire        one_free  = (wr_inc == {~rd_q[AW], rd_q[AW-1:0]});",
     "wire        one_free  = (wr_inc == rd_q);",
     "full flag never set: the RAM overflows"),
    ("bsd_timer_bank", "prove", "bsd_timer_bank.v",
     "assign busy_o      = run_q | host_q | rflx_q;", "assign busy_o      = run_q | host_q;",
     "a timer whose RFLX strobe is still to come is free again: busy until delivered broken"),
    ("bsd_timeout_wheel", "prove", "bsd_timeout_wheel.v",
     "stale_q  <= st_q || start_any || (!advance && stale_q);", "stale_q  <= st_q || (!advance && stale_q);",
     "a scan that read the start a restart is overwriting inserts the previous run's timeout"),
    ("bsd_timeout_wheel", "prove", "bsd_timeout_wheel.v",
     "assign expire_o = expire_q & ins_q;", "assign expire_o = expire_q;",
     "a restart after its slot was read expires at the previous run's timeout"),
    ("bsd_drain", "prove", "bsd_drain.v",
     "dio_first = dio_q && !(|(rem & before_q));", "dio_first = dio_q;",
     "the DIG_IO value always goes first, even above a lower timer ID"),
    ("bsd_pkt_tx", "prove", "bsd_pkt_tx.v",
     "last_q  <= pos_q == n_q;", "last_q  <= pos_q == n_q + 4'd1;",
     "tlast one byte late (on byte N + 2)"),
    ("bsd_trans_latch", "prove", "bsd_trans_latch.v",
     "            prev_q  <= level_i;\n        end else if (active)",
     "        end else if (active)",
     "arming keeps the old sample: a level present at arming fires"),
    ("bsd_tick_gen", "prove_clk2m", "bsd_tick_gen.v",
     "wire [W-1:0] sum  = acc_q + INC_W;", "wire [W-1:0] sum  = acc_q + INC_W + 1'b1;",
     "the accumulator steps by INC + 1: the rate is too high"),
    ("bsd_msg_merge", "prove", "bsd_msg_merge.v",
     "wire start    = req_i && !mid_q && !stall_q && !msg_q;",
     "wire start    = req_i && !mid_q && !msg_q;",
     "the message takes over from a stalled stream byte"),
    ("bsd_uart_tx", "prove", "bsd_uart_tx.v",
     "ready_q <= (left_q == 4'd1) && (cnt_q == CNT_ONE);",
     "ready_q <= (left_q == 4'd2) && (cnt_q == CNT_ONE);",
     "ready a bit early: the next byte cuts the stop bit short",
     "UNKNOWN"),  # the frame (30 clocks) is longer than the base case (6): induction fails only
    ("bsd_uart_tx", "bmc", "bsd_uart_tx.v",
     "ready_q <= (left_q == 4'd1) && (cnt_q == CNT_ONE);",
     "ready_q <= (left_q == 4'd2) && (cnt_q == CNT_ONE);",
     "ready a bit early, against the BMC of a whole frame"),
    ("bsd_uart_tx", "prove", "bsd_uart_tx.v",
     "            ready_q <= 1'b0;\n", "            ready_q <= 1'b1;\n",
     "ready stays up after a byte is taken: the next byte restarts the frame"),
    ("bsd_uart_rx", "prove", "bsd_uart_rx.v",
     "        rx_q        <= meta_q;\n", "        rx_q        <= rx_i;\n",
     "one synchronizer flop: the line reaches the state machine a clock early"),
    ("bsd_uart_rx", "bmc", "bsd_uart_rx.v",
     "                    if (rx_q) begin\n", "                    if (1'b1) begin\n",
     "stop bit not checked: a frame with a 0 stop bit gives a byte"),
    ("bsd_parser", "prove", "bsd_parser.v",
     "wire len_over = (|s_axis_tdata[7:4]) | (s_axis_tdata[3] & (|s_axis_tdata[2:0]));",
     "wire len_over = (|s_axis_tdata[7:4]);",
     "N = 9..15 taken as a command's length: N > 8 reaches the executor"),
    ("brainstem_dio", "bmc", "brainstem_dio.v",
     ".m_axis_tready (m_axis_tready),", ".m_axis_tready (1'b1),",
     "bsd_pkt_tx never sees the sink's stall: a stalled byte is replaced"),
    ("brainstem_dio", "reset_bmc", "bsd_pkt_tx.v",
     "wire       swap = flush_i && valid_q && first_q && !m_axis_tready;", "wire       swap = 1'b0;",
     "cmdRESET keeps a packet offered but not taken: the power-up message is not next"),
    ("brainstem_dio", "reset_bmc", "brainstem_dio.v",
     ".rst         (core_rst),\n        .cfg_we_i", ".rst         (rst),\n        .cfg_we_i",
     "cmdRESET leaves the pin configuration as it was"),
    ("bsd_sync", "prove", "bsd_sync.v",
     "sync_q <= meta_q;", "sync_q <= d_i;",
     "one flop: the pad level is seen one clock early"),
    ("bsd_cfg_regs", "prove", "bsd_cfg_regs.v",
     "if (FIXED_MASK[p]) begin : g_fixed", "if (1'b0) begin : g_fixed",
     "fixed pins get a writable register (reset 0x01, not FIXED_CFG)"),
    ("bsd_cfg_regs", "prove", "bsd_cfg_regs.v",
     "if (cfg_we_i && sel) cfg_q <= cfg_wdata_i;", "if (cfg_we_i) cfg_q <= cfg_wdata_i;",
     "a configuration write lands in every free pin, not only the addressed one"),
    ("bsd_heartbeat", "prove", "bsd_heartbeat.v",
     "if (!answered || req_q) link_up_q <= 1'b0;", "if (!answered) link_up_q <= 1'b0;",
     "a heartbeat due while the previous one is unsent keeps the link up",
     "UNKNOWN"),  # a heartbeat is 16 000 ticks from reset: only the induction step fails
    ("bsd_heartbeat", "bmc", "bsd_heartbeat.v",
     "if (!answered || req_q) link_up_q <= 1'b0;", "if (!answered) link_up_q <= 1'b0;",
     "the same, against the BMC from any state that meets the invariants"),
    ("bsd_heartbeat", "bmc", "bsd_heartbeat.v",
     "down_q     <= queued_q ? !down_q : 1'b0;", "down_q     <= !down_q;",
     "the type toggles from reset: after a reset the first heartbeat may be DOWN"),
    ("bsd_reply_slot", "prove", "bsd_reply_slot.v",
     "wire rep_wait_d = rep_req_o && !rep_done_i;", "wire rep_wait_d = rep_wait_q && !rep_done_i;",
     "the one-clock request (reply_q) is not kept: a reply not taken at once is lost"),
    ("bsd_exec", "prove", "bsd_exec.v",
     "wire [NUM_PINS-1:0] do_cfg   = sel & {NUM_PINS{c_cfg && pin_byte}} & ~FIXED_MASK;",
     "wire [NUM_PINS-1:0] do_cfg   = sel & {NUM_PINS{c_cfg && pin_byte}};",
     "a DIG_CFG write to a fixed pin is strobed (and re-arms it) instead of configErr"),
]


def main() -> int:
    only = sys.argv[1:]
    rows = []
    for job, task, fname, old, new, what, *exp in MUTANTS:
        expected = exp[0] if exp else "FAIL"
        if only and job not in only:
            continue
        path = RTL / fname
        text = path.read_text()
        if text.count(old) != 1:
            print(f"{job}: mutant text not found once in {fname}", file=sys.stderr)
            return 2
        try:
            path.write_text(text.replace(old, new))
            with tempfile.TemporaryDirectory() as tmp:
                result, depth, seconds, tail = formal_run.run_task(job, task, Path(tmp) / "w")
                failed = [l.split("summary:")[-1].strip() for l in tail.splitlines()
                          if "failed assertion" in l or "Unreached" in l]
        finally:
            path.write_text(text)
        caught = result != "PASS"
        rows.append((job, task, what, result, expected))
        note = "" if result == expected else f" (expected {expected})"
        print(f"{job:16} {task:12} {'caught' if caught else 'MISSED':7} {result:8}{note} {seconds:5.1f} s  {what}")
        for f in failed[:2]:
            print(f"    {f}")
    return 0 if all(r[3] != "PASS" and r[3] == r[4] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
