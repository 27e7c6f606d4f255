#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The virtual module's speed (sim/virtual.cpp, `make virtual`) as a ratio to real time.

For each clock and baud rate it builds the virtual module (`make virtual-build`, the same
binary `make virtual` runs) and runs it unpaced (`--bench SECONDS`): a host on the bit-level
serial line sends one command after another, each when the previous reply is in (DIG_CFG
set and query, DIG_IO reads, DIG_RST, PTIME_RD on a toggling pad), and answers the heartbeat.
It prints, per run, simulated seconds per wall second (what a host sees on this machine as it
is loaded now) and per CPU second (what the simulation would give with a core to itself), and
then the highest clock that keeps real time. `--write FILE` also fills FILE's marked region
`<!-- generated:virtual-speed begin -->` .. `end` with the Markdown table, under the run's date
and command (`make bench` does this for docs/benchmarks.md; tools/docregions.py).

    .venv/bin/python sim/virtual_bench.py                 # 2, 12, 48 MHz x 9600, 115200 baud
    .venv/bin/python sim/virtual_bench.py --markdown      # the same as a Markdown table
    .venv/bin/python sim/virtual_bench.py --write docs/benchmarks.md   # and into its region
    .venv/bin/python sim/virtual_bench.py --clocks 2000000 4000000 --bauds 9600 --seconds 5
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
from docregions import RegionError, fill, fill_file  # noqa: E402

REGION = "virtual-speed"
BOARD_HZ = 12_000_000      # the iCEBreaker's clock: the virtual module should keep real time there
LINE = re.compile(r"simulated ([\d.]+) s in ([\d.]+) s wall, ([\d.]+) s cpu: ratio ([\d.]+) wall, ([\d.]+) cpu; "
                  r"(\d+) cycles per cpu second")


@dataclass
class Run:
    clk_hz: int
    baud: int
    simulated: float
    wall: float
    cpu: float
    ratio_wall: float
    ratio_cpu: float
    cycles_per_cpu_s: int


def build(clk_hz: int, baud: int, hb_rate: int) -> Path:
    make_vars = [f"CLK_HZ={clk_hz}", f"BAUD={baud}", f"HB_RATE={hb_rate}"]
    subprocess.run(["make", "-s", "virtual-build", *make_vars], cwd=ROOT, check=True)
    path = subprocess.run(["make", "-s", "--no-print-directory", "virtual-path", *make_vars], cwd=ROOT,
                          check=True, capture_output=True, text=True).stdout.strip()
    return ROOT / path


def measure(binary: Path, clk_hz: int, baud: int, seconds: float) -> Run:
    out = subprocess.run([str(binary), "--bench", str(seconds)], cwd=ROOT, check=True, capture_output=True,
                         text=True, stdin=subprocess.DEVNULL).stdout
    m = LINE.search(out)
    if not m:
        sys.exit(f"virtual_bench: cannot read the bench line of {binary}:\n{out}")
    sim, wall, cpu, rw, rc, cps = m.groups()
    return Run(clk_hz, baud, float(sim), float(wall), float(cpu), float(rw), float(rc), int(cps))


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    return f"{cpu}, {os.cpu_count()} cores, Linux {platform.release()}, load average {load}"


def highest(runs: list[Run], key: str) -> int | None:
    """The highest clock whose every baud rate keeps real time (ratio >= 1) by `key`."""
    ok = [clk for clk in sorted({r.clk_hz for r in runs})
          if all(getattr(r, key) >= 1.0 for r in runs if r.clk_hz == clk)]
    return ok[-1] if ok else None


def mhz(hz: float | None) -> str:
    return "none" if hz is None else f"{hz / 1e6:g} MHz"


def report(runs: list[Run], markdown: bool, where: str) -> str:
    head = ["CLK_HZ", "BAUD", "simulated s", "wall s", "ratio to real time", "ratio per CPU second",
            "M cycles per CPU second"]
    rows = [[f"{r.clk_hz / 1e6:g} MHz", str(r.baud), f"{r.simulated:.2f}", f"{r.wall:.2f}",
             f"{r.ratio_wall:.2f}", f"{r.ratio_cpu:.2f}", f"{r.cycles_per_cpu_s / 1e6:.2f}"] for r in runs]
    wall_best = highest(runs, "ratio_wall")
    cpu_best = highest(runs, "ratio_cpu")
    # With a core to itself the simulation keeps real time up to its slowest cycle rate.
    estimate = min(r.cycles_per_cpu_s for r in runs)
    summary = [
        f"Highest clock that keeps real time on this machine now: {mhz(wall_best)}"
        f" (with a core to itself: {mhz(cpu_best)} of those measured; about"
        f" {estimate / 1e6:.1f} MHz from the slowest cycle rate).",
    ]
    board = [r.ratio_cpu for r in runs if r.clk_hz == BOARD_HZ]
    if board:
        summary.append(f"At {BOARD_HZ / 1e6:g} MHz (the iCEBreaker's clock), per CPU second: "
                       f"{min(board):.2f} of real time at the slowest baud rate: "
                       f"**{'keeps' if min(board) >= 1 else 'does not keep'}** real time on one core (target ≥ 1).")
    if markdown:
        lines = [f"Machine: {where}.", "", "| " + " | ".join(head) + " |",
                 "|" + "|".join(["---"] * 2 + ["---:"] * (len(head) - 2)) + "|"]
        lines += ["| " + " | ".join(row) + " |" for row in rows]
        return "\n".join(lines + [""] + [line + "\n" for line in summary[:-1]] + summary[-1:])
    widths = [max(len(h), *(len(row[i]) for row in rows)) for i, h in enumerate(head)]
    lines = [f"machine: {where}", "  ".join(h.rjust(w) for h, w in zip(head, widths))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(row, widths)) for row in rows]
    return "\n".join(lines + summary)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(prog="sim/virtual_bench.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--clocks", type=int, nargs="+", default=[2_000_000, 12_000_000, 48_000_000],
                    metavar="HZ", help="CLK_HZ values (default: 2, 12 and 48 MHz)")
    ap.add_argument("--bauds", type=int, nargs="+", default=[9600, 115200], metavar="BAUD",
                    help="BAUD values (default: 9600 and 115200)")
    ap.add_argument("--hb-rate", type=int, default=10, help="HB_RATE of the builds (default 10: 256 ms)")
    ap.add_argument("--seconds", type=float, default=3.0, help="wall seconds per run (default 3)")
    ap.add_argument("--markdown", action="store_true", help="print a Markdown table")
    ap.add_argument("--write", type=Path, metavar="FILE",
                    help=f"also fill the region `generated:{REGION}` of FILE with the Markdown table")
    args = ap.parse_args(argv)
    if args.seconds <= 0:
        ap.error("--seconds must be positive")
    for clk in args.clocks:
        for baud in args.bauds:
            if (clk + baud // 2) // baud < 8:
                ap.error(f"CLK_HZ {clk} / BAUD {baud} is below 8 clocks a bit (uart_rx needs 8)")
    if args.write is not None:  # a missing marker fails now, not after the runs
        try:
            fill(args.write.read_text(encoding="utf-8"), {REGION: ""}, where=str(args.write))
        except (OSError, RegionError) as e:
            print(f"sim/virtual_bench.py: error: {e}", file=sys.stderr)
            return 1
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    where = machine()
    runs = []
    for clk in args.clocks:
        for baud in args.bauds:
            binary = build(clk, baud, args.hb_rate)
            runs.append(measure(binary, clk, baud, args.seconds))
            print(f"virtual_bench: {clk / 1e6:g} MHz, {baud} baud: ratio {runs[-1].ratio_wall:.2f}", file=sys.stderr)
    print(report(runs, args.markdown, where))
    if args.write is not None:
        body = f"_Measured {date} by `{shlex.join(['sim/virtual_bench.py', *argv])}`._\n\n" + report(runs, True, where)
        changed = fill_file(args.write, {REGION: body})
        print(f"{'wrote' if changed else 'unchanged:'} {args.write} ({REGION})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
