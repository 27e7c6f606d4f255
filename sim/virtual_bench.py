#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The virtual module's speed (sim/virtual.cpp, `make virtual`) as a ratio to real time.

Each clock and baud rate's build (`make virtual-build`, the binary `make virtual` runs) runs
unpaced (`--bench SECONDS`) with a host on the bit-level serial line sending one command after
another, each when the previous reply is in. Per run: simulated seconds per wall second (what a
host sees on this machine as loaded now) and per CPU second (with a core to itself). Prints a
Markdown table and writes it, with the raw figures, to sim/build/virtual_bench.md and .json.

    .venv/bin/python sim/virtual_bench.py             # 2, 12, 48 MHz x 9600, 115200 baud
    .venv/bin/python sim/virtual_bench.py --clocks 12000000 --bauds 9600 --seconds 5
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "sim" / "build"
LINE = re.compile(r"simulated ([\d.]+) s in ([\d.]+) s wall, ([\d.]+) s cpu: ratio ([\d.]+) wall, ([\d.]+) cpu; "
                  r"(\d+) cycles per cpu second")
KEYS = ("simulated_s", "wall_s", "cpu_s", "ratio_wall", "ratio_cpu", "cycles_per_cpu_s")


def measure(clk: int, baud: int, hb_rate: int, seconds: float) -> dict:
    make_vars = [f"CLK_HZ={clk}", f"BAUD={baud}", f"HB_RATE={hb_rate}"]
    subprocess.run(["make", "-s", "virtual-build", *make_vars], cwd=ROOT, check=True)
    path = subprocess.run(["make", "-s", "--no-print-directory", "virtual-path", *make_vars], cwd=ROOT,
                          check=True, capture_output=True, text=True).stdout.strip()
    out = subprocess.run([str(ROOT / path), "--bench", str(seconds)], cwd=ROOT, check=True, capture_output=True,
                         text=True, stdin=subprocess.DEVNULL).stdout
    m = LINE.search(out) or sys.exit(f"sim/virtual_bench.py: error: no bench line from {path}:\n{out}")
    return {"clk_hz": clk, "baud": baud, **{k: float(v) for k, v in zip(KEYS, m.groups())}}


def keeps_up(runs: list[dict], key: str) -> str:
    ok = [c for c in sorted({r["clk_hz"] for r in runs}) if all(r[key] >= 1 for r in runs if r["clk_hz"] == c)]
    return f"{ok[-1] / 1e6:g} MHz" if ok else "none of those measured"


def main() -> int:
    ap = argparse.ArgumentParser(prog="sim/virtual_bench.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--clocks", type=int, nargs="+", default=[2_000_000, 12_000_000, 48_000_000], metavar="HZ")
    ap.add_argument("--bauds", type=int, nargs="+", default=[9600, 115200], metavar="BAUD")
    ap.add_argument("--hb-rate", type=int, default=10, help="HB_RATE of the builds (default 10: 256 ms)")
    ap.add_argument("--seconds", type=float, default=3.0, help="wall seconds per run (default 3)")
    args = ap.parse_args()
    if args.seconds <= 0:
        ap.error("--seconds must be positive")
    for clk in args.clocks:
        for baud in args.bauds:
            if baud < 1 or (clk + baud // 2) // baud < 8:
                ap.error(f"CLK_HZ {clk} / BAUD {baud} is below 8 clocks a bit (uart_rx needs 8)")
    date = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    load = " / ".join(f"{x:.1f}" for x in os.getloadavg())
    runs = [measure(c, b, args.hb_rate, args.seconds) for c in args.clocks for b in args.bauds]
    lines = [(f"Measured {date} by `{' '.join(['sim/virtual_bench.py', *sys.argv[1:]])}`, "
             f"{os.cpu_count()} cores, load average {load}."), "",
             "| CLK_HZ | BAUD | simulated s | wall s | ratio to real time | ratio per CPU second | M cycles per CPU second |",
             "|---|---|---:|---:|---:|---:|---:|"]
    lines += [f"| {r['clk_hz'] / 1e6:g} MHz | {r['baud']} | {r['simulated_s']:.2f} | {r['wall_s']:.2f} | "
              f"{r['ratio_wall']:.2f} | {r['ratio_cpu']:.2f} | {r['cycles_per_cpu_s'] / 1e6:.2f} |" for r in runs]
    lines += ["", (f"Keeps real time on this machine now up to {keeps_up(runs, 'ratio_wall')}; with a core to "
              f"itself up to {keeps_up(runs, 'ratio_cpu')}.")]
    text = "\n".join(lines) + "\n"
    print(text, end="")
    (OUT / "virtual_bench.md").write_text(text)
    (OUT / "virtual_bench.json").write_text(json.dumps({"date": date, "load": load, "runs": runs}, indent=1) + "\n")
    print("wrote sim/build/virtual_bench.md, sim/build/virtual_bench.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
