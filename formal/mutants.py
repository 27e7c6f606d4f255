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

# (job, task, file, original text, mutant text, what it breaks)
MUTANTS = [
    ("bsd_axis_skid", "prove", "bsd_axis_skid.v",
     "out_data_q   <= skid_q;", "out_data_q   <= s_axis_tdata;",
     "draining the skid sends the input word instead of the skid word"),
    ("bsd_fifo", "prove", "bsd_fifo.v",
     "wire        one_free  = (wr_inc == {~rd_q[AW], rd_q[AW-1:0]});",
     "wire        one_free  = (wr_inc == rd_q);",
     "full flag never set: the RAM overflows"),
    ("bsd_age_arb", "prove", "bsd_age_arb.v",
     "(req_q | (born & below(i)))", "(req_q | (born & ~below(i) & ~(1 << i)))",
     "same-clock newborns rank highest index first"),
    ("bsd_trans_latch", "prove", "bsd_trans_latch.v",
     "            prev_q  <= level_i;\n        end else if (active)",
     "        end else if (active)",
     "arming keeps the old sample: a level present at arming fires"),
    ("bsd_tick_gen", "prove_clk2m", "bsd_tick_gen.v",
     "wire [W-1:0] sum  = acc_q + INC_W;", "wire [W-1:0] sum  = acc_q + INC_W + 1'b1;",
     "the accumulator steps by INC + 1: the rate is too high"),
    ("bsd_event_timer", "prove", "bsd_event_timer.v",
     "!complete ? 16'd0 : count_zero ? 16'd1 : count_inc;", "!complete ? 16'd0 : count_inc;",
     "a completion with no tick reports 0 (a timeout's value)"),
    ("bsd_msg_merge", "prove", "bsd_msg_merge.v",
     "wire start    = req_i && !mid_q && !stall_q && !msg_q;",
     "wire start    = req_i && !mid_q && !msg_q;",
     "the message takes over from a stalled stream byte"),
    ("bsd_uart_tx", "prove", "bsd_uart_tx.v",
     "ready_q <= (left_q == 4'd1) && (cnt_q == CNT_ONE);",
     "ready_q <= (left_q == 4'd2) && (cnt_q == CNT_ONE);",
     "ready a bit early: the next byte cuts the stop bit short"),
    ("bsd_tx", "prove", "bsd_tx.v",
     "left_q  <= sel_n + 4'd2;", "left_q  <= sel_n + 4'd1;",
     "tlast one byte early (on byte N + 1)"),
]


def main() -> int:
    only = sys.argv[1:]
    rows = []
    for job, task, fname, old, new, what in MUTANTS:
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
        rows.append((job, task, what, result, failed[0] if failed else ""))
        print(f"{job:16} {task:12} {'caught' if caught else 'MISSED':7} {result:8} {seconds:5.1f} s  {what}")
        for f in failed[:2]:
            print(f"    {f}")
    return 0 if all(r[3] != "PASS" for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
