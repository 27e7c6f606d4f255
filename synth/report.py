#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Fill the generated regions of docs/synthesis.md from synth/build/<design>/*.json.

    python synth/report.py [--doc docs/synthesis.md] [--build synth/build]

Reads the summaries synth/flow.py writes (seed<N>.json per placed seed, yosys.json for a
design that is not placed), checks them, and replaces the content between the
`<!-- generated:NAME begin -->` / `<!-- generated:NAME end -->` markers of the document;
the hand-written text around them is left as it is. Every figure in a region is read from the
JSON or computed from it here (differences, slopes, ratios); each region names the date and
command of the run(s) that measured it. A design without any summary shows as "not measured".
Fails (exit 1) if a marker is missing or a summary is malformed or incomplete.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tools"))

import flow  # noqa: E402
from docregions import RegionError, fill_file  # noqa: E402

DOC = flow.ROOT / "docs" / "synthesis.md"
REGIONS = ("run", "area", "per-pin", "consumers", "serial-link", "timing", "critical-paths", "families",
           "family-slopes", "family-paths", "warnings")
REQUIRED = ("schema", "design", "title", "parameters", "pins", "timers", "board_clock_hz", "date",
            "command", "seeds", "seed", "tools", "device", "cells", "placement", "fmax",
            "critical_paths", "warnings", "modules", "nextpnr_options", "target_mhz")
PLACEMENT_KEYS = ("lcs_used", "lcs_available")
PATH_KEYS = ("clock", "from", "to", "lut_levels", "carry_steps", "global_buffers", "other_logic_steps",
             "logic_ns", "routing_ns", "total_ns")
MODULE_KEYS = ("module", "name", "params", "instances", "cells", "children")
NOT_MEASURED = "not measured"

# Differences of the area table, as (from design, to design, what changes): the slopes per pin
# and per timer are computed from the two summaries' own pin and timer counts.
SLOPES = (("core5", "core16", "pins"), ("core16", "core64", "pins"),
          ("core16", "core16t", "timers"), ("core64", "core64t", "timers"))
DIFFERENCES = (("core5", "uart5", "the serial link: UART, FIFO, register slices, merge, heartbeat on"),
               ("core5", "icebreaker", "the board top over the bare core"))
WIDEST = "core64t"           # the design compared with the UP5K's size
CONSUMERS = "core16t"        # the design whose modules are counted apart
LINK, LINK_CORE = "uart5", "core5"   # the serial link's hierarchy, and the bare core it adds to
# The iCE40 designs: the original regions' tables (run .. critical-paths) are made of these.
ICE40 = flow.designs_of("ice40")
# Per family: the GP 1.0 core, the 16-pin cores of the slopes, and the board top.
FAMILY_DESIGNS = {"ice40": ("core5", "core16", "core16t", "icebreaker"),
                  "ecp5": ("ecp5_core5", "ecp5_core16", "ecp5_core16t", "ulx3s"),
                  "gowin": ("gowin_core5", "gowin_core16", "gowin_core16t", "tangnano9k")}


class ReportError(RuntimeError):
    """A summary is missing, malformed or incomplete, or the document lacks a marker."""


@dataclass
class Measured:
    design: flow.Design
    records: list[dict]           # one per seed (placed), or the single yosys-only summary
    files: list[Path]

    @property
    def base(self) -> dict:
        return self.records[0]

    @property
    def cells(self) -> dict[str, int]:
        return self.base["cells"]

    @property
    def placed(self) -> bool:
        return self.base["placement"] is not None

    @property
    def run(self) -> tuple[str, str]:
        return self.base["date"], self.base["command"]

    def fmax(self) -> dict[int, float]:
        """Seed -> the slowest clock's achieved Fmax (MHz)."""
        return {r["seed"]: min(c["achieved_mhz"] for c in r["fmax"].values()) for r in self.records}


# ------------------------------------------------------------------ loading

def _read(path: Path, d: flow.Design) -> dict:
    rerun = f"rerun `synth/synth.py --only {d.name}`"
    try:
        rec = json.loads(path.read_text())
    except ValueError as e:
        raise ReportError(f"{_rel(path)} is not valid JSON ({e}); {rerun}") from None
    if not isinstance(rec, dict):
        raise ReportError(f"{_rel(path)} is not a summary (a JSON object); {rerun}")
    missing = [k for k in REQUIRED if k not in rec]
    if missing:
        raise ReportError(f"{_rel(path)} lacks {', '.join(missing)}; {rerun}")
    if rec["schema"] != flow.SCHEMA:
        raise ReportError(f"{_rel(path)} has schema {rec['schema']}, this report reads {flow.SCHEMA}; {rerun}")
    if rec["design"] != d.name:
        raise ReportError(f"{_rel(path)} is a summary of {rec['design']!r}, not {d.name!r}; {rerun}")
    for k in ("lut4", "ff", "carry", "ram"):
        if not isinstance(rec["cells"].get(k), int):
            raise ReportError(f"{_rel(path)}: cells.{k} is not a count; {rerun}")
    if rec["placement"] is not None and (not rec["fmax"] or rec["critical_paths"] is None):
        raise ReportError(f"{_rel(path)}: placed, but without Fmax or critical paths; {rerun}")
    shapes = [("placement", PLACEMENT_KEYS, [rec["placement"]] if rec["placement"] else []),
              ("fmax", ("achieved_mhz",), list((rec["fmax"] or {}).values())),
              ("critical_paths", PATH_KEYS, rec["critical_paths"] or []),
              ("modules", MODULE_KEYS, rec["modules"] or [])]
    for field, keys, items in shapes:
        for item in items:
            lack = [k for k in keys if not isinstance(item, dict) or k not in item]
            if lack:
                raise ReportError(f"{_rel(path)}: an entry of {field} lacks {', '.join(lack)}; {rerun}")
    return rec


def _rel(path: Path) -> str:
    try:
        return str(path.relative_to(flow.ROOT))
    except ValueError:
        return str(path)


def load(build: Path = flow.BUILD) -> dict[str, Measured | None]:
    """Design name -> its summaries (None: not measured), checked for consistency."""
    out: dict[str, Measured | None] = {}
    for d in flow.DESIGNS:
        work = build / d.name
        seeds = sorted(work.glob("seed*.json"), key=lambda p: (len(p.stem), p.stem))
        only = work / "yosys.json"
        if not seeds and not only.exists():
            out[d.name] = None
            continue
        rerun = f"rerun `synth/synth.py --only {d.name}`"
        if seeds and only.exists():
            raise ReportError(f"{_rel(work)} has both seed*.json and yosys.json (from different runs); {rerun}")
        if only.exists():
            rec = _read(only, d)
            if rec["placement"] is not None:
                raise ReportError(f"{_rel(only)} is a placed summary under the name of an unplaced one; {rerun}")
            out[d.name] = Measured(d, [rec], [only])
            continue
        recs = [_read(p, d) for p in seeds]
        for p, r in zip(seeds, recs):
            if r["placement"] is None or p.stem != f"seed{r['seed']}":
                raise ReportError(f"{_rel(p)} is not the placement of seed {p.stem[4:]}; {rerun}")
            if (r["date"], r["command"], r["seeds"]) != (recs[0]["date"], recs[0]["command"], recs[0]["seeds"]):
                raise ReportError(f"{_rel(p)} and {_rel(seeds[0])} come from different runs; {rerun}")
        expected = recs[0]["seeds"]
        have = [r["seed"] for r in recs]
        absent = [s for s in expected if s not in have]
        if absent:
            names = ", ".join(_rel(work / f"seed{s}.json") for s in absent)
            raise ReportError(f"{names} absent: the run `{recs[0]['command']}` of {recs[0]['date']} "
                              f"placed seeds {_seeds(expected)}; {rerun}")
        if sorted(have) != sorted(expected):
            raise ReportError(f"{_rel(work)} has seeds {have}, its run placed {expected}; {rerun}")
        recs.sort(key=lambda r: r["seed"])
        out[d.name] = Measured(d, recs, [work / f"seed{r['seed']}.json" for r in recs])
    return out


# ------------------------------------------------------------------ formatting

def _seeds(seeds: list[int]) -> str:
    if seeds and seeds == list(range(seeds[0], seeds[-1] + 1)) and len(seeds) > 2:
        return f"{seeds[0]}–{seeds[-1]}"
    return ", ".join(str(s) for s in seeds)


def _date(iso: str) -> str:
    """`2026-12-01T23:55:15Z` -> `2026-12-01 23:55 UTC`."""
    m = re.fullmatch(r"(\d{4}-\d\d-\d\d)T(\d\d:\d\d)(:\d\d)?Z", iso)
    return f"{m.group(1)} {m.group(2)} UTC" if m else iso


def _num(x: float, digits: int = 1) -> str:
    return f"{x:.{digits}f}".replace("-", "−")


def _signed(x: int) -> str:
    return f"+{x}" if x > 0 else str(x).replace("-", "−")


def stamp(meas: dict[str, Measured | None], names: list[str]) -> str:
    """The date and command of the run(s) that measured `names`, and which are unmeasured."""
    runs: dict[tuple[str, str], list[str]] = {}
    missing = []
    for n in names:
        m = meas.get(n)
        if m is None:
            missing.append(n)
        else:
            runs.setdefault(m.run, []).append(n)
    parts = []
    if len(runs) == 1:
        ((date, cmd), _), = runs.items()
        parts.append(f"Measured {_date(date)} by `{cmd}`")
    elif runs:
        parts.append("Measured by " + "; ".join(
            f"`{cmd}` on {_date(date)} ({', '.join(ns)})" for (date, cmd), ns in sorted(runs.items())))
    if missing:
        parts.append(f"not measured: {', '.join(missing)}")
    return "_" + "; ".join(parts) + "._"


def _table(header: list[str], align: str, rows: list[list[str]]) -> list[str]:
    out = ["| " + " | ".join(header) + " |",
           "|" + "|".join("---:" if a == "r" else "---" for a in align) + "|"]
    out += ["| " + " | ".join(r) + " |" for r in rows]
    return out


def _lcs_available(meas: dict[str, Measured | None]) -> int | None:
    for m in meas.values():
        if m and m.placed and m.design.family == "ice40":
            return m.base["placement"]["lcs_available"]
    return None


def _range(values: list[float] | list[int], fmt=str) -> str:
    lo, hi = min(values), max(values)
    return fmt(lo) if lo == hi else f"{fmt(lo)}–{fmt(hi)}"


# ------------------------------------------------------------------ regions

def region_run(meas: dict[str, Measured | None]) -> str:
    names = [d.name for d in ICE40]
    got = [m for m in meas.values() if m]
    lines = [stamp(meas, names), "",
             "Filled in by `synth/report.py` from `synth/build/<design>/seed<N>.json` and `yosys.json`.", ""]
    if not got:
        return "\n".join(lines + ["Nothing measured yet: `make synth`."])
    tools: dict[str, set[str]] = {}
    for m in got:
        for r in m.records:
            for k, v in r["tools"].items():
                # "Yosys 0.70 (git sha1 28ba3cb92, Release, Clang ...)" -> without the build details
                short = re.match(r"(.*?\(git sha1 \w+)", v)
                tools.setdefault(k, set()).add(short.group(1) + ")" if short else v)
    rows = [[f"`{k}`", " / ".join(sorted(v))] for k, v in sorted(tools.items())]
    lines += _table(["tool", "version"], "ll", rows) + [""]
    placed = [m for m in got if m.placed]
    opts = sorted({" ".join(r["nextpnr_options"]) for m in placed for r in m.records})
    lines.append(f"yosys: `{' / '.join(sorted({m.base['yosys_script'] for m in got}))}`"
                 + (f"; nextpnr: `{' / '.join(opts)}`, one run per placement seed." if opts else "."))
    lines.append("")
    rows = []
    for d in ICE40:
        m = meas[d.name]
        if m is None:
            what = NOT_MEASURED
        elif m.placed:
            n = m.base["seeds"]
            what = f"placed (`{m.base['placed_top']}`), seed{'s' if len(n) > 1 else ''} {_seeds(n)}"
        else:
            what = "synthesized, not placed"
        params = ", ".join(f"{k}={v}" for k, v in d.params.items()) or "defaults"
        rows.append([f"`{d.name}`", d.title, f"`{d.counted_top}` ({params})", what])
    lines += _table(["design", "what", "cells counted of", "measured"], "llll", rows)
    return "\n".join(lines)


def region_area(meas: dict[str, Measured | None]) -> str:
    avail = _lcs_available(meas)
    rows = []
    for d in ICE40:
        m = meas[d.name]
        if m is None:
            rows.append([f"`{d.name}`", d.title, *["—"] * 5, f"{NOT_MEASURED} (`synth/synth.py --only {d.name}`)", "—"])
            continue
        c = m.cells
        if m.placed:
            fm = m.fmax()
            lcs = _range([r["placement"]["lcs_used"] for r in m.records])
            fmax, low = " / ".join(_num(v) for v in fm.values()), _num(min(fm.values()))
        else:
            lcs, low = "—", "—"
            if d.place_if_full:
                fmax = "not placed by default (`--full` places it)"
            elif avail is not None and c["lut4"] > avail:
                fmax = f"not placed ({d.unplaced_why}: {c['lut4']} LUT4s, {avail} LCs)"
            else:
                fmax = f"not placed ({d.unplaced_why or 'yosys only'})"
        rows.append([f"`{d.name}`", d.title, str(c["lut4"]), str(c["ff"]), str(c["carry"]), str(c["ram"]),
                     lcs, fmax, low])
    lines = [stamp(meas, [d.name for d in ICE40]), ""]
    lines += _table(["design", "what", "LUT4", "FF", "carry", "RAM", "LCs placed", "Fmax per seed (MHz)", "min"],
                    "llrrrrrlr", rows)
    if avail is not None:
        lines += ["", f"LCs available on the device (nextpnr): {avail}."]
    return "\n".join(lines)


def region_per_pin(meas: dict[str, Measured | None]) -> str:
    used = sorted({n for a, b, _ in SLOPES for n in (a, b)} | {n for a, b, _ in DIFFERENCES for n in (a, b)}
                  | {WIDEST}, key=[d.name for d in ICE40].index)
    lines = [stamp(meas, used), ""]
    rows = []
    for a, b, what in SLOPES:
        ma, mb = meas[a], meas[b]
        if ma is None or mb is None:
            label = f"`{a}` → `{b}`"
            rows.append([label, NOT_MEASURED, NOT_MEASURED])
            continue
        n = mb.base[what] - ma.base[what]
        if what == "pins":
            label = (f"a pin without a timer ({ma.base['pins']} → {mb.base['pins']} pins, "
                     f"{ma.base['timers']} timers)")
        else:
            label = (f"a timer added to a pin ({ma.base['pins']} pins: "
                     f"{ma.base['timers']} → {mb.base['timers']} timers)")
        rows.append([label, _num((mb.cells["lut4"] - ma.cells["lut4"]) / n),
                     _num((mb.cells["ff"] - ma.cells["ff"]) / n)])
    lines += _table(["step (rows of the area table)", "LUT4 per step", "FF per step"], "lrr", rows)
    lines.append("")
    rows = []
    for a, b, what in DIFFERENCES:
        ma, mb = meas[a], meas[b]
        label = f"`{b}` − `{a}`: {what}"
        if ma is None or mb is None:
            rows.append([label, *[NOT_MEASURED] * 4])
        else:
            rows.append([label, *[_signed(mb.cells[k] - ma.cells[k]) for k in ("lut4", "ff", "carry", "ram")]])
    lines += _table(["difference", "LUT4", "FF", "carry", "RAM"], "lrrrr", rows)
    lines.append("")
    avail, w = _lcs_available(meas), meas[WIDEST]
    if w is None or avail is None:
        lines.append(f"`{WIDEST}` against the device: {NOT_MEASURED}.")
    else:
        lines.append(f"`{WIDEST}` ({w.design.title}): {w.cells['lut4']} LUT4s = "
                     f"{_num(w.cells['lut4'] / avail)} × the {avail} LCs of the device, "
                     f"before its {w.cells['ff']} FFs are counted.")
    return "\n".join(lines)


def _labels(mods: list[dict]) -> dict[str, str]:
    """Readable module names; modules that share a name get the parameters that tell them apart."""
    out = {}
    for m in mods:
        same = [o for o in mods if o["name"] == m["name"]]
        label = m["name"]
        if len(same) > 1:
            keys = sorted({k for o in same for k in o["params"]
                           if len({str(x["params"].get(k)) for x in same}) > 1})
            extra = ", ".join(f"{k}={m['params'][k]}" for k in keys if k in m["params"])
            if not extra:
                extra = ", ".join(f"`{n}`" for n in m.get("instance_names", [])) or f"variant {same.index(m) + 1}"
            label += f" ({extra})"
        out[m["module"]] = label
    return out


def region_consumers(meas: dict[str, Measured | None]) -> str:
    lines = [stamp(meas, [CONSUMERS]), ""]
    m = meas[CONSUMERS]
    if m is None or not m.base["modules"]:
        return "\n".join(lines + [f"`{CONSUMERS}`: {NOT_MEASURED}."])
    mods = [x for x in m.base["modules"] if x["instances"]]
    labels = _labels(mods)
    total = sum(x["cells"]["lut4"] * x["instances"] for x in mods)
    lines.append(f"`{CONSUMERS}` ({m.design.title}) with `-noflatten`: {total} LUT4s in all, against "
                 f"{m.cells['lut4']} for the flattened core of the area table.")
    lines.append("")
    rows = []
    for x in sorted(mods, key=lambda x: (-x["cells"]["lut4"] * x["instances"], labels[x["module"]])):
        c, n = x["cells"], x["instances"]
        if not (c["lut4"] or c["ff"] or c["carry"] or c["ram"]):
            continue
        name = labels[x["module"]] + (" (own logic)" if x["module"] == m.design.counted_top else "")
        share = f"{100 * c['lut4'] * n / total:.0f} %" if total else "—"
        rows.append([name, str(n), str(c["lut4"]), str(c["ff"]), str(c["carry"]), str(c["lut4"] * n), share])
    lines += _table(["module", "instances", "LUT4 each", "FF each", "carry each", "LUT4 total", "share"],
                    "lrrrrrr", rows)
    return "\n".join(lines)


def _under(mods: dict[str, dict], root: str, target: str) -> int:
    """Instances of `target` in the subtree of one `root` instance."""
    if root == target:
        return 1
    return sum(n * _under(mods, child, target) for child, n in mods[root]["children"].items() if child != root)


def region_serial_link(meas: dict[str, Measured | None]) -> str:
    lines = [stamp(meas, [LINK, LINK_CORE]), ""]
    m = meas[LINK]
    if m is None or not m.base["modules"]:
        return "\n".join(lines + [f"`{LINK}`: {NOT_MEASURED}."])
    mods = {x["module"]: x for x in m.base["modules"]}
    cores = [x for x in mods.values() if x["name"] == flow.CORE_TOP]
    if len(cores) != 1:
        raise ReportError(f"{_rel(m.files[0])}: expected one `{flow.CORE_TOP}` module in the hierarchy, "
                          f"found {len(cores)}")
    core = cores[0]
    labels = _labels(list(mods.values()))
    rows, total = [], {"lut4": 0, "ff": 0}
    for x in sorted(mods.values(), key=lambda x: labels[x["module"]]):
        n = x["instances"] - core["instances"] * _under(mods, core["module"], x["module"])
        c = x["cells"]
        if n <= 0 or not (c["lut4"] or c["ff"] or c["ram"]):
            continue
        name = labels[x["module"]] + (" (own logic)" if x["module"] == m.design.counted_top else "")
        rows.append([name, str(n), str(c["lut4"]), str(c["ff"]), str(c["carry"]), str(c["ram"])])
        total["lut4"] += n * c["lut4"]
        total["ff"] += n * c["ff"]
    # Modules inside the core that cost differently from the bare core's (e.g. the heartbeat,
    # on in the wrapper): matched by name and parameters against LINK_CORE's hierarchy.
    inside, extra = [], {"lut4": 0, "ff": 0}
    bare = meas[LINK_CORE]
    if bare is not None and bare.base["modules"]:
        bare_mods = bare.base["modules"]
        for x in sorted(mods.values(), key=lambda x: labels[x["module"]]):
            k = _under(mods, core["module"], x["module"]) * core["instances"]
            if not k:
                continue
            # The same parameters give the same (hashed) module name; else a unique name.
            same = [b for b in bare_mods if b["module"] == x["module"]]
            if not same:
                same = [b for b in bare_mods if b["name"] == x["name"]]
            if len(same) != 1:
                continue
            b = same[0]
            if b["cells"] != x["cells"] or b["instances"] != k:
                for key in ("lut4", "ff"):
                    extra[key] += k * x["cells"][key] - b["instances"] * b["cells"][key]
                inside.append([labels[x["module"]] + " (inside the core)", str(k),
                               f"{x['cells']['lut4']} (bare core: {b['cells']['lut4']})",
                               f"{x['cells']['ff']} (bare core: {b['cells']['ff']})",
                               str(x["cells"]["carry"]), str(x["cells"]["ram"])])
    lines += _table(["module", "instances", "LUT4 each", "FF each", "carry each", "RAM each"], "lrrrrr",
                    rows + inside)
    lines.append("")
    text = (f"Unflattened, the modules outside `{flow.CORE_TOP}` add {total['lut4']} LUT4s and {total['ff']} FFs")
    if inside:
        text += (f"; with what the core's modules add over `{LINK_CORE}`'s, {total['lut4'] + extra['lut4']} "
                 f"LUT4s and {total['ff'] + extra['ff']} FFs")
    if bare is not None:
        text += (f". Flattened (`{LINK}` − `{LINK_CORE}` in the area table): "
                 f"{_signed(m.cells['lut4'] - bare.cells['lut4'])} LUT4s, {_signed(m.cells['ff'] - bare.cells['ff'])} FFs")
    lines.append(text + ".")
    return "\n".join(lines)


def region_timing(meas: dict[str, Measured | None]) -> str:
    names = [d.name for d in ICE40 if d.placed_top]
    lines = [stamp(meas, names), ""]
    rows = []
    board = None
    for d in ICE40:
        if not d.placed_top:
            continue
        m = meas[d.name]
        if m is None or not m.placed:
            rows.append([f"`{d.name}`", "—", NOT_MEASURED if m is None else "not placed", *["—"] * 5])
            continue
        fm = m.fmax()
        hz = m.base["board_clock_hz"] / 1e6
        target = m.base["target_mhz"]
        paths = [p for r in m.records for p in r["critical_paths"]]
        share = [p["routing_ns"] / p["total_ns"] * 100 for p in paths if p["total_ns"]]
        rows.append([f"`{d.name}`", _seeds(list(fm)), _range(list(fm.values()), _num),
                     f"{_num(min(fm.values()) / hz)}×",
                     "yes" if min(fm.values()) >= target else f"no ({sum(v < target for v in fm.values())} of {len(fm)} seeds below)",
                     "yes" if min(fm.values()) >= hz else "no",
                     _range([p["lut_levels"] for p in paths]) if paths else "—",
                     _range([round(s) for s in share]) + " %" if share else "—"])
        if d.name == flow.BOARD:
            board = (m, fm, hz, target)
    hz_txt = _num(board[2], 0) if board else "board clock"
    lines += _table(["design", "seeds", "Fmax (MHz)", f"worst ÷ {hz_txt} MHz",
                     f"≥ {_num(board[3], 0) if board else 'target'} MHz on every seed",
                     f"≥ {hz_txt} MHz on every seed", "LUT levels of the critical paths",
                     "routing share of their delay"], "lrlrllrr", rows)
    lines.append("")
    if board:
        m, fm, hz, target = board
        worst = min(fm.values())
        lines.append(f"Board top (`{flow.BOARD}`): worst Fmax {_num(worst)} MHz over seeds {_seeds(list(fm))}, "
                     f"{_num(worst / hz)}× its {_num(hz, 0)} MHz clock: it **{'meets' if worst >= target else 'misses'}** "
                     f"the {_num(target, 0)} MHz target"
                     + ("" if worst >= target else f" ({sum(v < target for v in fm.values())} of {len(fm)} seeds below)")
                     + (f" and closes at {_num(hz, 0)} MHz on every seed." if worst >= hz
                        else f"; it does NOT close at {_num(hz, 0)} MHz on every seed."))
    else:
        lines.append(f"Board top (`{flow.BOARD}`): {NOT_MEASURED}.")
    return "\n".join(lines)


def region_critical_paths(meas: dict[str, Measured | None]) -> str:
    names = [d.name for d in ICE40 if d.placed_top]
    lines = [stamp(meas, names), ""]
    rows = []
    for d in ICE40:
        m = meas[d.name]
        if m is None or not m.placed:
            continue
        multi = len({p["clock"] for r in m.records for p in r["critical_paths"]}) > 1
        for r in m.records:
            for p in r["critical_paths"]:
                extra = "".join(f" (+ {p[k]} {label})" for k, label in
                                (("carry_steps", "carry"), ("global_buffers", "gbuf"), ("other_logic_steps", "other"))
                                if p[k])
                fmax = r["fmax"].get(p["clock"], {}).get("achieved_mhz")
                rows.append([f"`{d.name}`" + (f" `{p['clock']}`" if multi else ""), str(r["seed"]),
                             _num(fmax) if fmax is not None else "—", f"`{p['from']}`", f"`{p['to']}`",
                             f"{p['lut_levels']}{extra}", f"{_num(p['logic_ns'])} / {_num(p['routing_ns'])}"])
    if not rows:
        return "\n".join(lines + ["No placement measured."])
    lines += _table(["design", "seed", "Fmax (MHz)", "from", "to", "LUT levels (+ other steps)",
                     "logic / routing (ns)"], "lrrllrl", rows)
    return "\n".join(lines)


def _pct(used: int, avail: int) -> str:
    return f"{100 * used / avail:.1f} %" if avail else "—"


def region_families(meas: dict[str, Measured | None]) -> str:
    """Per family: the GP 1.0 core (in its harness) and the board top: area, utilization of
    the device, Fmax over the placement seeds, against the board clock and the 4x target."""
    names = [n for fam in FAMILY_DESIGNS.values() for n in (fam[0], fam[3])]
    lines = [stamp(meas, names), ""]
    rows = []
    for fam, (core, _, _, board) in FAMILY_DESIGNS.items():
        f = flow.FAMILIES[fam]
        for name in (core, board):
            d = flow.design(name)
            m = meas.get(name)
            label = f"{f.title} ({f.board_title})"
            if m is None:
                rows.append([label, f"`{name}`", d.title, *["—"] * 4, NOT_MEASURED, "—", "—", "—", "—"])
                continue
            c = m.cells
            if not m.placed:
                rows.append([label, f"`{name}`", d.title, str(c["lut4"]), str(c["ff"]), str(c["carry"]),
                             str(c["ram"]), "not placed", "—", "—", "—", "—"])
                continue
            pl = m.base["placement"]
            fm = m.fmax()
            hz = m.base["board_clock_hz"] / 1e6
            target = m.base["target_mhz"]
            util = (f"{_range([r['placement']['lcs_used'] for r in m.records])} / {pl['lcs_available']} "
                    f"{pl.get('logic_cell', 'LC')} ({_pct(pl['lcs_used'], pl['lcs_available'])})")
            if pl.get("ff_available"):
                util += f"; {pl['ff_used']} / {pl['ff_available']} FF ({_pct(pl['ff_used'], pl['ff_available'])})"
            util += f"; RAM {pl['ram_used']} / {pl['ram_available']}"
            worst = min(fm.values())
            rows.append([label, f"`{name}`", d.title, str(c["lut4"]), str(c["ff"]), str(c["carry"]), str(c["ram"]),
                         util, " / ".join(_num(v) for v in fm.values()), _num(worst),
                         f"{_num(worst / hz)}× {_num(hz, 0)} MHz",
                         "yes" if worst >= target else f"no ({sum(v < target for v in fm.values())} of {len(fm)} seeds below {_num(target, 0)})"])
    lines += _table(["family (board)", "design", "what", "LUT4", "FF", "carry", "RAM",
                     "placed: used / available", "Fmax per seed (MHz)", "min", "min ÷ board clock",
                     "≥ 4× board clock, every seed"], "lllrrrrlrrrl", rows)
    lines.append("")
    rows = []
    for fam in FAMILY_DESIGNS:
        f = flow.FAMILIES[fam]
        got = [meas[n] for n in FAMILY_DESIGNS[fam] if meas.get(n)]
        tools = sorted({f"{k} {v}" for m in got for r in m.records for k, v in r["tools"].items()
                        if k not in ("yosys",)})
        opts = sorted({" ".join(r["nextpnr_options"]) for m in got for r in m.records if r["nextpnr_options"]})
        rows.append([f"{f.title} ({f.board_title}, {_num(f.board_hz / 1e6, 0)} MHz)", f"`{f.yosys_synth}`",
                     f"`{f.nextpnr}`" + (f" `{' / '.join(opts)}`" if opts else ""),
                     ", ".join(tools) if tools else NOT_MEASURED])
    lines += _table(["family", "yosys", "nextpnr and options", "tool versions (PyPI)"], "llll", rows)
    return "\n".join(lines)


def region_family_slopes(meas: dict[str, Measured | None]) -> str:
    """A pin without a timer (5 -> 16 pins, 4 timers) and a timer (16 pins, 4 -> 16 timers),
    per family, from the synthesized (flattened) cores."""
    names = [n for fam in FAMILY_DESIGNS.values() for n in fam[:3]]
    lines = [stamp(meas, names), ""]
    rows = []
    for fam, (c5, c16, c16t, _) in FAMILY_DESIGNS.items():
        f = flow.FAMILIES[fam]
        for a, b, what in ((c5, c16, "pins"), (c16, c16t, "timers")):
            ma, mb = meas.get(a), meas.get(b)
            if ma is None or mb is None:
                rows.append([f.title, f"`{a}` → `{b}`", NOT_MEASURED, NOT_MEASURED, NOT_MEASURED])
                continue
            n = mb.base[what] - ma.base[what]
            label = (f"a pin without a timer ({ma.base['pins']} → {mb.base['pins']} pins)" if what == "pins"
                     else f"a timer added to a pin ({ma.base['pins']} pins: {ma.base['timers']} → {mb.base['timers']})")
            rows.append([f.title, label, _num((mb.cells["lut4"] - ma.cells["lut4"]) / n),
                         _num((mb.cells["ff"] - ma.cells["ff"]) / n),
                         _num((mb.cells["carry"] - ma.cells["carry"]) / n)])
    lines += _table(["family", "step", "LUT4 per step", "FF per step", "carry per step"], "llrrr", rows)
    return "\n".join(lines)


def region_family_paths(meas: dict[str, Measured | None]) -> str:
    """The critical path of every placement of the ECP5 and Gowin designs."""
    names = [n for fam in ("ecp5", "gowin") for n in (FAMILY_DESIGNS[fam][0], FAMILY_DESIGNS[fam][3])]
    lines = [stamp(meas, names), ""]
    rows = []
    for name in names:
        m = meas.get(name)
        if m is None or not m.placed:
            continue
        for r in m.records:
            for p in r["critical_paths"]:
                extra = "".join(f" (+ {p[k]} {label})" for k, label in
                                (("carry_steps", "carry"), ("global_buffers", "gbuf"), ("other_logic_steps", "other"))
                                if p[k])
                fmax = r["fmax"].get(p["clock"], {}).get("achieved_mhz")
                rows.append([f"`{name}`", str(r["seed"]), _num(fmax) if fmax is not None else "—",
                             f"`{p['from']}`", f"`{p['to']}`", f"{p['lut_levels']}{extra}",
                             f"{_num(p['logic_ns'])} / {_num(p['routing_ns'])}"])
    if not rows:
        return "\n".join(lines + ["No placement measured."])
    lines += _table(["design", "seed", "Fmax (MHz)", "from", "to", "LUT levels (+ other steps)",
                     "logic / routing (ns)"], "lrrllrl", rows)
    return "\n".join(lines)


def region_warnings(meas: dict[str, Measured | None]) -> str:
    names = [d.name for d in flow.DESIGNS]
    lines = [stamp(meas, names), ""]
    seen: dict[str, list[str]] = {}
    for d in flow.DESIGNS:
        m = meas[d.name]
        if m is None:
            continue
        for r in m.records:
            for w in r["warnings"]:
                ds = seen.setdefault(w, [])
                if d.name not in ds:
                    ds.append(d.name)
    if not seen:
        return "\n".join(lines + ["No warnings in the yosys and nextpnr logs."])
    rows = [["`" + w.replace("|", "\\|") + "`", ", ".join(f"`{n}`" for n in ds)] for w, ds in seen.items()]
    lines += _table(["warning (numbers of MHz folded to N)", "designs"], "ll", rows)
    return "\n".join(lines)


BUILDERS = {"run": region_run, "area": region_area, "per-pin": region_per_pin,
            "consumers": region_consumers, "serial-link": region_serial_link, "timing": region_timing,
            "critical-paths": region_critical_paths, "families": region_families,
            "family-slopes": region_family_slopes, "family-paths": region_family_paths,
            "warnings": region_warnings}
assert tuple(BUILDERS) == REGIONS


def write(doc: Path = DOC, build: Path = flow.BUILD) -> None:
    meas = load(build)
    try:
        bodies = {name: BUILDERS[name](meas) for name in REGIONS}
    except (KeyError, TypeError, ValueError) as e:   # a summary that passed the checks above but not the tables
        raise ReportError(f"a summary under {_rel(build)} lacks what the tables read ({e!r}); "
                          f"rerun `make synth`") from None
    try:
        changed = fill_file(doc, bodies)
    except RegionError as e:
        raise ReportError(str(e).replace(str(flow.ROOT) + "/", "")) from None
    missing = [n for n, m in meas.items() if m is None]
    print(f"{'wrote' if changed else 'unchanged:'} {_rel(doc)} ({len(REGIONS)} regions"
          + (f"; not measured: {', '.join(missing)}" if missing else "") + ")")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="synth/report.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--doc", type=Path, default=DOC, help="the document to fill (default docs/synthesis.md)")
    ap.add_argument("--build", type=Path, default=flow.BUILD, help="where the summaries are (default synth/build)")
    args = ap.parse_args(argv)
    try:
        write(args.doc, args.build)
    except ReportError as e:
        print(f"synth/report.py: error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
