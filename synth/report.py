#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Fill the generated regions of docs/synthesis.md and draw docs/synthesis-scaling.svg from
synth/build/<design>/*.json.

    python synth/report.py [--doc docs/synthesis.md] [--build synth/build]

Reads the summaries synth/flow.py writes (seed<N>.json per placed seed, yosys.json for a
design that is not placed) and replaces the content between the
`<!-- generated:NAME begin -->` / `<!-- generated:NAME end -->` markers of the document; the
hand-written text around them is left as it is. Every figure in a region is read from the
JSON or computed from it here (differences, slopes, ratios); each region names the date and
command of the run(s) that measured it. A design without any summary shows as "not measured".
The plot puts this run's LUT4 against timer count beside the points of synth/scaling_baseline.json
(an earlier design, kept with its date and command). Fails (exit 1) if a marker is missing or a
summary is unreadable or from another version of the flow.
"""

from __future__ import annotations

import argparse
import json
import re
import statistics
import sys
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tools"))

import flow  # noqa: E402
from docregions import RegionError, fill_file  # noqa: E402

DOC = flow.ROOT / "docs" / "synthesis.md"
PLOT = flow.ROOT / "docs" / "synthesis-scaling.svg"
BASELINE = HERE / "scaling_baseline.json"
NOT_MEASURED = "not measured"

# Differences of the area table, as (from design, to design, what changes): the slopes per pin
# and per timer are computed from the two summaries' own pin and timer counts.
SLOPES = (("core5", "core16", "pins"), ("core16", "core64", "pins"),
          ("core16", "core16t", "timers"), ("core64", "core64t", "timers"))
DIFFERENCES = (("core5", "uart5", "the serial link: UART, FIFO, register slices, merge, heartbeat on"),
               ("core5", "icebreaker", "the board top over the bare core"),
               ("icebreaker", "icebreaker24", "19 more pins and 20 more timers on the board"))
CONSUMERS = "core16t"        # the design whose modules are counted apart
SCALING = {16: ("core16", "core16t"), 64: ("core64", "core64t16", "core64t")}   # the plot's points
TARGET_64X64 = 3300          # LUT4 of the core at 64 pins x 64 timers (the targets region and the plot)
ICE40 = flow.designs_of("ice40")
# Per family: the GP 1.0 core, the 16-pin cores of the slopes, and the board top.
FAMILY_DESIGNS = {"ice40": ("core5", "core16", "core16t", "icebreaker"),
                  "ecp5": ("ecp5_core5", "ecp5_core16", "ecp5_core16t", "ulx3s"),
                  "gowin": ("gowin_core5", "gowin_core16", "gowin_core16t", "tangnano9k")}


class ReportError(RuntimeError):
    """A summary is missing, unreadable or from another flow version, or the document lacks a marker."""


@dataclass
class Measured:
    design: flow.Design
    records: list[dict]           # one per placed seed, or the single unplaced summary

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


def _rel(path: Path) -> str:
    try:
        return str(path.relative_to(flow.ROOT))
    except ValueError:
        return str(path)


def load(build: Path = flow.BUILD) -> dict[str, Measured | None]:
    """Design name -> its summaries (None: not measured)."""
    out: dict[str, Measured | None] = {}
    for d in flow.DESIGNS:
        work = build / d.name
        files = sorted(work.glob("seed*.json"), key=lambda p: (len(p.stem), p.stem)) or \
            [p for p in [work / "yosys.json"] if p.exists()]
        rerun = f"rerun `synth/synth.py --only {d.name}`"
        recs = []
        for p in files:
            try:
                rec = json.loads(p.read_text())
            except ValueError as e:
                raise ReportError(f"{_rel(p)} is not valid JSON ({e}); {rerun}") from None
            if not isinstance(rec, dict) or rec.get("schema") != flow.SCHEMA or rec.get("design") != d.name:
                raise ReportError(f"{_rel(p)} is not a schema-{flow.SCHEMA} summary of {d.name}; {rerun}")
            if recs and (rec["date"], rec["command"]) != (recs[0]["date"], recs[0]["command"]):
                raise ReportError(f"{_rel(p)} and {_rel(files[0])} come from different runs; {rerun}")
            recs.append(rec)
        out[d.name] = Measured(d, recs) if recs else None
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


def _pct(used: int, avail: int) -> str:
    return f"{100 * used / avail:.1f} %" if avail else "—"


def _range(values: list, fmt=str) -> str:
    lo, hi = min(values), max(values)
    return fmt(lo) if lo == hi else f"{fmt(lo)}–{fmt(hi)}"


def stamp(meas: dict[str, Measured | None], names) -> str:
    """The date and command of the run(s) that measured `names`, and which are unmeasured."""
    runs: dict[tuple[str, str], list[str]] = {}
    for n in names:
        if meas.get(n):
            runs.setdefault(meas[n].run, []).append(n)
    parts = []
    if len(runs) == 1:
        ((date, cmd), _), = runs.items()
        parts.append(f"Measured {_date(date)} by `{cmd}`")
    elif runs:
        parts.append("Measured by " + "; ".join(
            f"`{cmd}` on {_date(date)} ({', '.join(ns)})" for (date, cmd), ns in sorted(runs.items())))
    missing = [n for n in names if not meas.get(n)]
    if missing:
        parts.append(f"not measured: {', '.join(missing)}")
    return "_" + "; ".join(parts) + "._"


def _table(header: list[str], align: str, rows: list[list[str]]) -> list[str]:
    return ["| " + " | ".join(header) + " |",
            "|" + "|".join("---:" if a == "r" else "---" for a in align) + "|",
            *("| " + " | ".join(r) + " |" for r in rows)]


def _slope(meas, a: str, b: str, what: str, key: str = "lut4") -> float | None:
    ma, mb = meas.get(a), meas.get(b)
    if ma is None or mb is None:
        return None
    return (mb.cells[key] - ma.cells[key]) / (mb.base[what] - ma.base[what])


def _slope_label(meas, a: str, b: str, what: str) -> str:
    ma, mb = meas.get(a), meas.get(b)
    if ma is None or mb is None:
        return f"`{a}` → `{b}`"
    if what == "pins":
        return f"a pin without a timer ({ma.base['pins']} → {mb.base['pins']} pins, {ma.base['timers']} timers)"
    return f"a timer added to a pin ({ma.base['pins']} pins: {ma.base['timers']} → {mb.base['timers']} timers)"


def _fit(m: Measured | None) -> str:
    """What a placement gives: LCs and Fmax per seed, or why there is none."""
    if m is None:
        return NOT_MEASURED
    if not m.placed:
        return f"not placed: {m.base['unplaced']}"
    pl = m.base["placement"]
    text = (f"{_range([r['placement']['lcs_used'] for r in m.records])} / {pl['lcs_available']} LCs "
            f"({_pct(pl['lcs_used'], pl['lcs_available'])}), Fmax {' / '.join(_num(v) for v in m.fmax().values())} MHz")
    return text + "".join(f"; {t}" for t in m.base["timed_out"])


# ------------------------------------------------------------------ regions

def region_run(meas) -> str:
    got = [m for m in meas.values() if m]
    lines = [stamp(meas, [d.name for d in ICE40]), ""]
    if not got:
        return "\n".join(lines + ["Nothing measured yet: `make synth`."])
    tools: dict[str, set[str]] = {}
    for m in got:
        for k, v in m.base["tools"].items():
            # "Yosys 0.70 (git sha1 28ba3cb92, Release, Clang ...)" -> without the build details
            short = re.match(r"(.*?\(git sha1 \w+)", v)
            tools.setdefault(k, set()).add(short.group(1) + ")" if short else v)
    lines += _table(["tool", "version"], "ll", [[f"`{k}`", " / ".join(sorted(v))] for k, v in sorted(tools.items())])
    opts = sorted({" ".join(r["nextpnr_options"]) for m in got for r in m.records if r["nextpnr_options"]})
    lines += ["", f"yosys: `{' / '.join(sorted({m.base['yosys_script'] for m in got}))}`"
              + (f"; nextpnr: `{' / '.join(opts)}`, one run per placement seed, at most "
                 f"{flow.PNR_TIMEOUT} s each." if opts else "."), ""]
    rows = []
    for d in ICE40:
        m = meas[d.name]
        what = (NOT_MEASURED if m is None else
                f"placed (`{m.base['placed_top']}`), seeds {_seeds(m.base['seeds'])}" if m.placed else
                f"not placed: {m.base['unplaced']}")
        params = ", ".join(f"{k}={v}" for k, v in d.params.items()) or "defaults"
        rows.append([f"`{d.name}`", d.title, f"`{d.counted_top}` ({params})", what])
    return "\n".join(lines + _table(["design", "what", "cells counted of", "measured"], "llll", rows))


def region_targets(meas) -> str:
    """The project's area and speed targets against this run's figures."""
    rows = []

    def row(figure: str, target: str, value: float | None, limit: float, text: str | None = None,
            at_least: bool = False) -> None:
        ok = None if value is None else (value >= limit if at_least else value <= limit)
        rows.append([figure, target, text or (NOT_MEASURED if value is None else _num(value, 0 if value == int(value) else 1)),
                     "—" if ok is None else "met" if ok else "**missed**"])

    cell = lambda n, k: meas[n].cells[k] if meas.get(n) else None  # noqa: E731
    row("GP 1.0 core (`core5`), LUT4", "≤ 700", cell("core5", "lut4"), 700)
    for key, name, limit in (("lut4", "LUT4", TARGET_64X64), ("ff", "FF", 2400), ("ram", "SB_RAM40_4K", 18)):
        row(f"64 pins × 64 timers (`core64t`), {name}", f"≤ {limit}", cell("core64t", key), limit)
    for a, b, what in SLOPES:
        row(_slope_label(meas, a, b, what) + ", LUT4", "≤ 14" if what == "pins" else "≤ 30",
            _slope(meas, a, b, what), 14 if what == "pins" else 30)
    for name, figure, fits in (("uart64t", "64 × 64 with the serial link in one UP5K (`uart64t`)", "≤ 75 % of its logic cells"),
                               ("icebreaker24", "24 pins × 24 timers on the iCEBreaker (`icebreaker24`)", "placed")):
        m = meas.get(name)
        if m is None or not m.placed:   # no fit, or out of time: a target missed, not a gap in the table
            rows += [[f"{figure}, placed", fits, _fit(m), "—" if m is None else "**missed**"],
                     [f"{figure}, worst Fmax (MHz)", "≥ 48" if name == "uart64t" else "≥ 12", "—", "—"]]
            continue
        pct = 100 * max(r["placement"]["lcs_used"] for r in m.records) / m.base["placement"]["lcs_available"]
        row(f"{figure}, logic cells", fits, pct if name == "uart64t" else 0, 75, f"{pct:.1f} %")
        row(f"{figure}, worst Fmax (MHz)", "≥ 48" if name == "uart64t" else "≥ 12", min(m.fmax().values()),
            48 if name == "uart64t" else 12, at_least=True)
    b = meas.get(flow.BOARD)
    fm = list(b.fmax().values()) if b and b.placed else None
    row(f"board top (`{flow.BOARD}`), median Fmax (MHz)", "≥ 60", statistics.median(fm) if fm else None, 60, at_least=True)
    row(f"board top (`{flow.BOARD}`), worst Fmax (MHz)", "≥ 55", min(fm) if fm else None, 55, at_least=True)
    names = ["core5", "core64t", *{n for s in SLOPES for n in s[:2]}, "uart64t", flow.BOARD, "icebreaker24"]
    return "\n".join([stamp(meas, sorted(set(names))), ""] + _table(["figure", "target", "this run", ""], "lrrl", rows))


def region_area(meas) -> str:
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
            fmax = " / ".join(_num(v) for v in fm.values()) + "".join(f"; {t}" for t in m.base["timed_out"])
            low = _num(min(fm.values()))
        else:
            lcs, fmax, low = "—", f"not placed: {m.base['unplaced']}", "—"
        rows.append([f"`{d.name}`", d.title, str(c["lut4"]), str(c["ff"]), str(c["carry"]), str(c["ram"]), lcs, fmax, low])
    lines = [stamp(meas, [d.name for d in ICE40]), ""]
    lines += _table(["design", "what", "LUT4", "FF", "carry", "RAM", "LCs placed", "Fmax per seed (MHz)", "min"],
                    "llrrrrrlr", rows)
    avail = next((m.base["placement"]["lcs_available"] for m in meas.values()
                  if m and m.placed and m.design.family == "ice40"), None)
    if avail is not None:
        lines += ["", f"LCs available on the device (nextpnr): {avail}."]
    return "\n".join(lines)


def region_per_pin(meas) -> str:
    used = sorted({n for a, b, _ in SLOPES + DIFFERENCES for n in (a, b)})
    rows = []
    for a, b, what in SLOPES:
        lut, ff = _slope(meas, a, b, what), _slope(meas, a, b, what, "ff")
        rows.append([_slope_label(meas, a, b, what), *(NOT_MEASURED if v is None else _num(v) for v in (lut, ff))])
    lines = [stamp(meas, used), ""] + _table(["step (rows of the area table)", "LUT4 per step", "FF per step"], "lrr", rows)
    rows = []
    for a, b, what in DIFFERENCES:
        ma, mb = meas.get(a), meas.get(b)
        rows.append([f"`{b}` − `{a}`: {what}", *([NOT_MEASURED] * 4 if ma is None or mb is None else
                     [_signed(mb.cells[k] - ma.cells[k]) for k in ("lut4", "ff", "carry", "ram")])])
    return "\n".join(lines + [""] + _table(["difference", "LUT4", "FF", "carry", "RAM"], "lrrrr", rows))


def _labels(mods: list[dict]) -> dict[str, str]:
    """Readable module names; modules that share a name get the parameters that tell them apart."""
    out = {}
    for m in mods:
        same = [o for o in mods if o["name"] == m["name"]]
        label = m["name"]
        if len(same) > 1:
            keys = sorted({k for o in same for k in o["params"] if len({str(x["params"].get(k)) for x in same}) > 1})
            extra = ", ".join(f"{k}={m['params'][k]}" for k in keys if k in m["params"])
            label += f" ({extra or ', '.join(f'`{n}`' for n in m.get('instance_names', [])) or same.index(m) + 1})"
        out[m["module"]] = label
    return out


def region_consumers(meas) -> str:
    lines = [stamp(meas, [CONSUMERS]), ""]
    m = meas.get(CONSUMERS)
    if m is None or not m.base["modules"]:
        return "\n".join(lines + [f"`{CONSUMERS}`: {NOT_MEASURED}."])
    mods = [x for x in m.base["modules"] if x["instances"]]
    labels = _labels(mods)
    total = sum(x["cells"]["lut4"] * x["instances"] for x in mods)
    lines += [f"`{CONSUMERS}` ({m.design.title}) with `-noflatten`: {total} LUT4s in all, against "
              f"{m.cells['lut4']} for the flattened core of the area table.", ""]
    rows = []
    for x in sorted(mods, key=lambda x: (-x["cells"]["lut4"] * x["instances"], labels[x["module"]])):
        c, n = x["cells"], x["instances"]
        if c["lut4"] or c["ff"] or c["carry"] or c["ram"]:
            name = labels[x["module"]] + (" (own logic)" if x["module"] == m.design.counted_top else "")
            rows.append([name, str(n), str(c["lut4"]), str(c["ff"]), str(c["carry"]), str(c["lut4"] * n),
                         f"{100 * c['lut4'] * n / total:.0f} %" if total else "—"])
    return "\n".join(lines + _table(["module", "instances", "LUT4 each", "FF each", "carry each", "LUT4 total",
                                     "share"], "lrrrrrr", rows))


def region_timing(meas) -> str:
    names = [d.name for d in ICE40 if d.placed_top]
    rows = []
    for name in names:
        m = meas[name]
        if m is None or not m.placed:
            rows.append([f"`{name}`", "—", _fit(m), *["—"] * 5])
            continue
        fm = m.fmax()
        hz, target = m.base["board_clock_hz"] / 1e6, m.base["target_mhz"]
        paths = [p for r in m.records for p in r["critical_paths"]]
        share = [p["routing_ns"] / p["total_ns"] * 100 for p in paths if p["total_ns"]]
        below = sum(v < target for v in fm.values())
        rows.append([f"`{name}`", _seeds(list(fm)), _range(list(fm.values()), _num), f"{_num(min(fm.values()) / hz)}×",
                     "yes" if not below else f"no ({below} of {len(fm)} seeds below)",
                     "yes" if min(fm.values()) >= hz else "no",
                     _range([p["lut_levels"] for p in paths]) if paths else "—",
                     _range([round(s) for s in share]) + " %" if share else "—"])
    lines = [stamp(meas, names), ""]
    lines += _table(["design", "seeds", "Fmax (MHz)", f"worst ÷ {_num(flow.BOARD_HZ / 1e6, 0)} MHz",
                     f"≥ {_num(flow.TARGET_MHZ, 0)} MHz on every seed", f"≥ {_num(flow.BOARD_HZ / 1e6, 0)} MHz on every seed",
                     "LUT levels of the critical paths", "routing share of their delay"], "lrlrllrr", rows)
    b = meas.get(flow.BOARD)
    if b and b.placed:
        fm, hz, target = b.fmax(), flow.BOARD_HZ / 1e6, flow.TARGET_MHZ
        worst = min(fm.values())
        lines += ["", f"Board top (`{flow.BOARD}`): worst Fmax {_num(worst)} MHz, median "
                  f"{_num(statistics.median(fm.values()))} MHz over seeds {_seeds(list(fm))}, {_num(worst / hz)}× its "
                  f"{_num(hz, 0)} MHz clock: it **{'meets' if worst >= target else 'misses'}** the {_num(target, 0)} MHz "
                  f"target and {'closes' if worst >= hz else 'does NOT close'} at {_num(hz, 0)} MHz on every seed."]
    return "\n".join(lines)


def _paths(meas, names: list[str]) -> str:
    rows = []
    for name in names:
        m = meas.get(name)
        if m is None or not m.placed:
            continue
        multi = len({p["clock"] for r in m.records for p in r["critical_paths"]}) > 1
        for r in m.records:
            for p in r["critical_paths"]:
                extra = "".join(f" (+ {p[k]} {label})" for k, label in
                                (("carry_steps", "carry"), ("global_buffers", "gbuf"), ("other_logic_steps", "other"))
                                if p[k])
                fmax = r["fmax"].get(p["clock"], {}).get("achieved_mhz")
                rows.append([f"`{name}`" + (f" `{p['clock']}`" if multi else ""), str(r["seed"]),
                             _num(fmax) if fmax is not None else "—", f"`{p['from']}`", f"`{p['to']}`",
                             f"{p['lut_levels']}{extra}", f"{_num(p['logic_ns'])} / {_num(p['routing_ns'])}"])
    lines = [stamp(meas, names), ""]
    if not rows:
        return "\n".join(lines + ["No placement measured."])
    return "\n".join(lines + _table(["design", "seed", "Fmax (MHz)", "from", "to", "LUT levels (+ other steps)",
                                     "logic / routing (ns)"], "lrrllrl", rows))


def region_critical_paths(meas) -> str:
    return _paths(meas, [d.name for d in ICE40 if d.placed_top])


def region_family_paths(meas) -> str:
    return _paths(meas, [n for fam in ("ecp5", "gowin") for n in (FAMILY_DESIGNS[fam][0], FAMILY_DESIGNS[fam][3])])


def region_families(meas) -> str:
    """Per family: the GP 1.0 core (in its harness) and the board top: area, utilization of
    the device, Fmax over the placement seeds, against the board clock and the 4x target."""
    names = [n for fam in FAMILY_DESIGNS.values() for n in (fam[0], fam[3])]
    rows = []
    for fam, (core, _, _, board) in FAMILY_DESIGNS.items():
        f = flow.FAMILIES[fam]
        for name in (core, board):
            m, label, title = meas.get(name), f"{f.title} ({f.board_title})", flow.design(name).title
            if m is None or not m.placed:
                c = m.cells if m else {}
                rows.append([label, f"`{name}`", title, *(str(c.get(k, "—")) for k in ("lut4", "ff", "carry", "ram")),
                             _fit(m), "—", "—", "—", "—"])
                continue
            c, pl, fm = m.cells, m.base["placement"], m.fmax()
            hz, target, worst = m.base["board_clock_hz"] / 1e6, m.base["target_mhz"], min(fm.values())
            util = (f"{_range([r['placement']['lcs_used'] for r in m.records])} / {pl['lcs_available']} "
                    f"{pl.get('logic_cell', 'LC')} ({_pct(pl['lcs_used'], pl['lcs_available'])})")
            if pl.get("ff_available"):
                util += f"; {pl['ff_used']} / {pl['ff_available']} FF ({_pct(pl['ff_used'], pl['ff_available'])})"
            util += f"; RAM {pl['ram_used']} / {pl['ram_available']}"
            below = sum(v < target for v in fm.values())
            rows.append([label, f"`{name}`", title, str(c["lut4"]), str(c["ff"]), str(c["carry"]), str(c["ram"]),
                         util, " / ".join(_num(v) for v in fm.values()), _num(worst), f"{_num(worst / hz)}× {_num(hz, 0)} MHz",
                         "yes" if not below else f"no ({below} of {len(fm)} seeds below {_num(target, 0)})"])
    lines = [stamp(meas, names), ""]
    lines += _table(["family (board)", "design", "what", "LUT4", "FF", "carry", "RAM", "placed: used / available",
                     "Fmax per seed (MHz)", "min", "min ÷ board clock", "≥ 4× board clock, every seed"],
                    "lllrrrrlrrrl", rows)
    rows = []
    for fam, designs in FAMILY_DESIGNS.items():
        f = flow.FAMILIES[fam]
        got = [meas[n] for n in designs if meas.get(n)]
        tools = sorted({f"{k} {v}" for m in got for r in m.records for k, v in r["tools"].items() if k != "yosys"})
        opts = sorted({" ".join(r["nextpnr_options"]) for m in got for r in m.records if r["nextpnr_options"]})
        rows.append([f"{f.title} ({f.board_title}, {_num(f.board_hz / 1e6, 0)} MHz)", f"`{f.yosys_synth}`",
                     f"`{f.nextpnr}`" + (f" `{' / '.join(opts)}`" if opts else ""),
                     ", ".join(tools) if tools else NOT_MEASURED])
    return "\n".join(lines + [""] + _table(["family", "yosys", "nextpnr and options", "tool versions (PyPI)"], "llll", rows))


def region_family_slopes(meas) -> str:
    """A pin without a timer (5 -> 16 pins, 4 timers) and a timer (16 pins, 4 -> 16 timers),
    per family, from the synthesized (flattened) cores."""
    rows = []
    for fam, (c5, c16, c16t, _) in FAMILY_DESIGNS.items():
        for a, b, what in ((c5, c16, "pins"), (c16, c16t, "timers")):
            vals = [_slope(meas, a, b, what, k) for k in ("lut4", "ff", "carry")]
            rows.append([flow.FAMILIES[fam].title, _slope_label(meas, a, b, what), *(NOT_MEASURED if v is None else _num(v) for v in vals)])
    names = [n for fam in FAMILY_DESIGNS.values() for n in fam[:3]]
    return "\n".join([stamp(meas, names), ""] + _table(["family", "step", "LUT4 per step", "FF per step",
                                                        "carry per step"], "llrrr", rows))


def region_warnings(meas) -> str:
    seen: dict[str, list[str]] = {}
    for d in flow.DESIGNS:
        for r in (meas[d.name].records if meas[d.name] else []):
            for w in r["warnings"]:
                if d.name not in seen.setdefault(w, []):
                    seen[w].append(d.name)
    lines = [stamp(meas, [d.name for d in flow.DESIGNS]), ""]
    if not seen:
        return "\n".join(lines + ["No warnings in the yosys and nextpnr logs."])
    rows = [["`" + w.replace("|", "\\|") + "`", ", ".join(f"`{n}`" for n in ds)] for w, ds in seen.items()]
    return "\n".join(lines + _table(["warning (numbers of MHz folded to N)", "designs"], "ll", rows))


BUILDERS = {"run": region_run, "targets": region_targets, "area": region_area, "per-pin": region_per_pin,
            "consumers": region_consumers, "timing": region_timing, "critical-paths": region_critical_paths,
            "families": region_families, "family-slopes": region_family_slopes,
            "family-paths": region_family_paths, "warnings": region_warnings}


# ------------------------------------------------------------------ the plot

def scaling_points(meas) -> dict[int, list[tuple[int, int]]]:
    """Pins -> [(timers, LUT4)] of this run's cores (the plot's points and the baseline's format)."""
    return {pins: [(meas[n].base["timers"], meas[n].cells["lut4"]) for n in names if meas.get(n)]
            for pins, names in SCALING.items()}


def plot(meas, path: Path = PLOT) -> bool:
    """LUT4 against timers, this run and the baseline; False if there is nothing to draw."""
    now = scaling_points(meas)
    if not any(now.values()):
        return False
    import matplotlib
    matplotlib.use("svg")
    import matplotlib.pyplot as plt
    plt.rcParams["svg.hashsalt"] = "brainstem_dio"     # the same figures give the same file
    base = json.loads(BASELINE.read_text()) if BASELINE.exists() else None
    fig, ax = plt.subplots(figsize=(7, 4.2))
    colors = {16: "tab:blue", 64: "tab:red"}
    date = _date(next(m.base["date"] for m in meas.values() if m))
    for pins, pts in now.items():
        if pts:
            ax.plot(*zip(*pts), "o-", color=colors[pins], label=f"{pins} pins, this run ({date})")
    if base:
        for pins, pts in base["points"].items():
            ax.plot(*zip(*pts), "s--", color=colors[int(pins)], alpha=0.45, mfc="none",
                    label=f"{pins} pins, {base['label']} ({base['date']})")
    lcs = next((m.base["placement"]["lcs_available"] for m in meas.values()
                if m and m.placed and m.design.family == "ice40"), None)
    if lcs:
        ax.axhline(lcs, color="gray", lw=0.8, ls=":")
        ax.text(1, lcs, f" iCE40UP5K: {lcs} logic cells", va="bottom", fontsize=8, color="gray")
    ax.plot([64], [TARGET_64X64], "x", color="black", label=f"target at 64 × 64: ≤ {TARGET_64X64} LUT4")
    ax.set(xlabel="timers", ylabel="LUT4 (yosys synth_ice40, core alone)",
           title="brainstem_dio: LUT4 against timer count", xlim=(0, 68))
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, metadata={"Date": None})
    plt.close(fig)
    head, _, rest = path.read_text().partition("\n")    # the XML declaration stays first
    path.write_text(f"{head}\n<!-- SPDX-License-Identifier: Apache-2.0 -->\n{rest}")
    return True


def write(doc: Path = DOC, build: Path = flow.BUILD) -> None:
    meas = load(build)
    try:
        bodies = {name: f(meas) for name, f in BUILDERS.items()}
    except (KeyError, TypeError, ValueError) as e:   # a summary without what the tables read
        raise ReportError(f"a summary under {_rel(build)} lacks what the tables read ({e!r}); "
                          f"rerun `make synth`") from None
    try:
        changed = fill_file(doc, bodies)
    except RegionError as e:
        raise ReportError(str(e).replace(str(flow.ROOT) + "/", "")) from None
    drawn = plot(meas) if doc == DOC else False
    missing = [n for n, m in meas.items() if m is None]
    print(f"{'wrote' if changed else 'unchanged:'} {_rel(doc)} ({len(bodies)} regions"
          + (f"; not measured: {', '.join(missing)}" if missing else "") + ")"
          + (f"; drew {_rel(PLOT)}" if drawn else ""))


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
