# SPDX-License-Identifier: Apache-2.0
"""Code coverage of rtl/ over the Verilator regression (`make coverage`; docs/coverage.md):
runs the Verilator cases with BSD_COVERAGE=1 and BSD_FCOV_DIR (then tools/fcov_report.py
--check), merges the data files and gives per rtl/ module line, branch and toggle % against the
targets; a module below a target passes only when tools/coverage_waivers.toml names every point
it leaves uncovered, and a waiver that names no uncovered point is an error.

    .venv/bin/python tools/coverage.py [--no-run]   # --no-run: report on the data files already there

Exit 0: targets met or every exception named; 1: not, or the regression failed; 2: bad
arguments, waivers or data.
"""

from __future__ import annotations

import argparse
import fnmatch
import os
import re
import shutil
import subprocess
import sys
import tomllib
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "sim_build" / "coverage"
WAIVERS = ROOT / "tools" / "coverage_waivers.toml"
KINDS = ("line", "branch", "toggle")
TARGETS = {"line": 98.0, "toggle": 95.0, "branch": 0.0}   # % each module needs
# The Verilator cases, less the two files that run plain Verilator binaries (no coverage).
PYTEST_SELECT = ["-k", "verilator", "--ignore", "tb/param_checks",
                 "--ignore", "tb/bsd_tick_gen/test_bsd_tick_gen_drift.py", "tb"]


class UsageError(Exception):
    """Bad arguments, a bad waiver file or unusable data: exit 2 with the message."""


@dataclass(frozen=True, order=True)
class Point:
    module: str
    file: str       # relative to the repository when inside it
    line: int
    column: int
    kind: str       # line | branch | toggle
    comment: str    # `block`, `if`, `else`, ... or `signal[bit]:0->1`
    span: str = ""  # the source lines a block or branch stands for (`74-76`)

    @property
    def signal(self) -> str:
        return self.comment.rsplit(":", 1)[0]

    def lines(self) -> list[int]:
        return sorted({self.line} | set(_numbers(self.span)))


Counts = dict[Point, int]


def _numbers(text: str) -> list[int]:
    """`61-63,70` -> [61, 62, 63, 70]."""
    out = []
    for part in filter(None, text.split(",")):
        lo, _, hi = part.partition("-")
        out += range(int(lo), int(hi or lo) + 1)
    return out


def parse_dat(text: str, root: Path = ROOT) -> Counts:
    """A Verilator coverage file (`SystemC::Coverage-3`): points and counts."""
    out: Counts = {}
    for n, raw in enumerate(text.splitlines(), 1):
        if not raw.strip() or raw.startswith("#"):
            continue
        if not (hit := re.match(r"^C '(.*)' (\d+)\s*$", raw)):
            raise ValueError(f"line {n}: not a coverage record: {raw[:80]!r}")
        f = dict(item.partition("\x02")[::2] for item in hit.group(1).split("\x01") if item)
        page, path = f.get("page", ""), Path(f.get("f", "?"))
        module = page.split("/", 1)[1] if "/" in page else path.stem
        if module.startswith(path.stem + "__"):
            module = path.stem   # a parameterized copy (`bsd_exec__N7`) is the module
        rel = str(path.resolve().relative_to(root.resolve())) if path.is_absolute() and path.resolve().is_relative_to(
            root.resolve()) else str(path)
        p = Point(module, rel, int(f.get("l", 0)), int(f.get("n", 0)), f.get("t") or page.split("/")[0].removeprefix("v_"),
                  f.get("o", ""), f.get("S", ""))
        out[p] = out.get(p, 0) + int(hit.group(2))
    return out


def merge(parts: Iterable[Counts]) -> Counts:
    out: Counts = {}
    for part in parts:
        for p, c in part.items():
            out[p] = out.get(p, 0) + c
    return out


def write_dat(counts: Counts) -> str:
    """A coverage file verilator_coverage reads (the hierarchy field holds the module)."""
    lines = ["# SystemC::Coverage-3"]
    for p in sorted(counts):
        fields = [("f", p.file if Path(p.file).is_absolute() else str(ROOT / p.file)), ("l", p.line), ("n", p.column),
                  ("t", p.kind), ("page", f"v_{p.kind}/{p.module}"), ("o", p.comment), *([("S", p.span)] if p.span else []),
                  ("h", p.module)]
        lines.append("C '" + "".join(f"\x01{k}\x02{v}" for k, v in fields) + f"' {counts[p]}")
    return "\n".join(lines) + "\n"


def glob_match(name: str, pattern: str) -> bool:
    """`*` any text, `?` one character, the rest literal (`cnt_q[15]` is a bit, not a class)."""
    return fnmatch.fnmatchcase(name, pattern.replace("[", "[[]"))


@dataclass(frozen=True)
class Waiver:
    module: str
    signal: str   # a toggle point's signal or bit: `*` any text, `?` one character, [] literal
    reason: str

    def matches(self, p: Point) -> bool:
        return (p.module, p.kind) == (self.module, "toggle") and any(
            glob_match(x, self.signal) for x in (p.signal, p.comment))


def parse_waivers(text: str, where: str = "waivers") -> list[Waiver]:
    """`[module]` tables of `"signal pattern" = "reason"`; UsageError on any mistake."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise UsageError(f"{where}: {e}") from None
    out = []
    for module, table in data.items():
        if not isinstance(table, dict):
            raise UsageError(f"{where}: {module!r} is not a [module] table of \"signal\" = \"reason\"")
        for signal, reason in table.items():
            if not (isinstance(reason, str) and reason.strip()):
                raise UsageError(f"{where}: [{module}] {signal!r}: the reason is not a non-empty string")
            out.append(Waiver(module, signal, " ".join(reason.split())))
    return out


@dataclass
class Metric:
    covered: int = 0
    total: int = 0
    missed: list[tuple[str, Waiver | None]] = field(default_factory=list)   # (what, its waiver)

    @property
    def percent(self) -> float:
        return 100.0 * self.covered / self.total if self.total else 100.0

    def count(self, hit: bool, what: str, waiver: Waiver | None) -> None:
        self.total += 1
        self.covered += hit
        if not hit:
            self.missed.append((what, waiver))


@dataclass
class ModuleReport:
    module: str
    file: str
    metrics: dict[str, Metric]
    line_counts: dict[int, int]    # source line -> highest count of a point on it

    def status(self, targets: Mapping[str, float]) -> str:
        """`met`, `named` (below a target, every miss named) or `below`."""
        below = [k for k in KINDS if self.metrics[k].percent < targets.get(k, 0.0)]
        if not below:
            return "met"
        return "named" if all(w for k in below for _, w in self.metrics[k].missed) else "below"


def module_reports(counts: Counts, waivers: Sequence[Waiver]) -> dict[str, ModuleReport]:
    by_module: dict[str, list[tuple[Point, int]]] = {}
    for p, c in sorted(counts.items()):
        if p.file.startswith("rtl/") and p.kind in KINDS:
            by_module.setdefault(p.module, []).append((p, c))
    out = {}
    for module, pts in sorted(by_module.items()):
        metrics = {k: Metric() for k in KINDS}
        line_counts: dict[int, int] = {}
        for p, c in pts:
            for n in p.lines() if p.kind != "toggle" else []:
                line_counts[n] = max(line_counts.get(n, 0), c)
            if p.kind != "line":
                what = f"`{p.comment}`" if p.kind == "toggle" else f"line {p.line} ({p.comment})"
                metrics[p.kind].count(c > 0, what, next((w for w in waivers if w.matches(p)), None))
        for n, c in sorted(line_counts.items()):
            metrics["line"].count(c > 0, f"line {n}", None)
        out[module] = ModuleReport(module, pts[0][0].file, metrics, line_counts)
    return out


def stale_waivers(reports: Mapping[str, ModuleReport], waivers: Sequence[Waiver]) -> list[Waiver]:
    """Waivers that name no uncovered point (the module is gone, or a test covers it now)."""
    used = {id(w) for r in reports.values() for m in r.metrics.values() for _, w in m.missed if w}
    return [w for w in waivers if id(w) not in used]


def overall(reports: Mapping[str, ModuleReport], targets: Mapping[str, float], stale: Sequence[Waiver]) -> bool:
    return bool(reports) and not stale and all(r.status(targets) != "below" for r in reports.values())


def _compact(items: Sequence[str], most: int = 4) -> str:
    """Toggle misses by signal: its bits (a direction only when one was missed), or how many."""
    dirs: dict[str, set[str]] = {}
    for item in items:
        bit, _, d = item.strip("`").rpartition(":")
        dirs.setdefault(bit, set()).add(d)
    by_signal: dict[str, list[str]] = {}
    for bit, d in dirs.items():
        by_signal.setdefault(re.sub(r"\[\d+\]$", "", bit), []).append(bit if len(d) == 2 else f"{bit} ({'/'.join(sorted(d))})")
    return ", ".join(f"`{base}` ({len(bits)} bits)" if len(bits) > most else ", ".join(f"`{b}`" for b in bits)
                     for base, bits in by_signal.items())


def _pct(m: Metric) -> str:
    return f"{m.percent:.1f} % ({m.covered}/{m.total})" if m.total else "–"


def markdown(reports: Mapping[str, ModuleReport], targets: Mapping[str, float], runs: int, stale: Sequence[Waiver]) -> str:
    text = {"met": "met", "named": "below, every miss named", "below": "**BELOW TARGET**"}
    ok = overall(reports, targets, stale)
    out = [f"`make coverage` over {runs} Verilator runs (targets: "
           + ", ".join(f"{k} ≥ {targets[k]:g} %" for k in KINDS if targets.get(k)) + "). "
           + ("Target met or every exception named." if ok else "TARGET MISSED: see the list below."), "",
           "| module | line | toggle | branch | target |", "|---|---|---|---|---|"]
    out += [f"| `{r.module}` | {_pct(r.metrics['line'])} | {_pct(r.metrics['toggle'])} | {_pct(r.metrics['branch'])} "
            f"| {text[r.status(targets)]} |" for r in reports.values()]
    named, unnamed = [], []
    for r in reports.values():
        for k in KINDS:
            groups: dict[int, tuple[Waiver | None, list[str]]] = {}
            for what, w in r.metrics[k].missed:
                groups.setdefault(id(w), (w, []))[1].append(what)
            for w, whats in groups.values():
                shown = _compact(whats) if k == "toggle" else ", ".join(whats)
                (named if w else unnamed).append(f"- `{r.module}` {k} {shown}" + (f": {w.reason}" if w else ""))
    out += ["", "Uncovered points with a named exception (tools/coverage_waivers.toml):", "", *(named or ["- none"]),
            "", "Uncovered points without one (allowed only while the module meets the target):", "",
            *(unnamed or ["- none"])]
    if stale:
        out += ["", "Waivers that match no uncovered point (delete them):", "",
                *(f"- `{w.module}` `{w.signal}`" for w in stale)]
    return "\n".join(out) + "\n"


def write_sources(reports: Mapping[str, ModuleReport], out: Path) -> None:
    """Each module's source with its counts, `!` where a line or branch point is uncovered."""
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    for r in reports.values():
        missed = {int(what.split()[1]) for k in ("line", "branch") for what, _ in r.metrics[k].missed}
        src = (ROOT / r.file).read_text(errors="replace").splitlines() if (ROOT / r.file).is_file() else []
        (out / f"{r.module}.v.txt").write_text("".join(
            f"{'!' if n in missed else ' '}{r.line_counts.get(n, ''):>9} {n:5} {line}\n"
            for n, line in enumerate(src, 1)))


def run_regression(dat: Path, fcov: Path, jobs: int, extra: Sequence[str]) -> int:
    for d in (dat, fcov):
        shutil.rmtree(d, ignore_errors=True)
        d.mkdir(parents=True)
    env = dict(os.environ, BSD_COVERAGE="1", BSD_COVERAGE_DIR=str(dat), BSD_FCOV_DIR=str(fcov))
    cmd = [sys.executable, "-m", "pytest", "-n", str(jobs), "-q", "-rfE", "--dist", "loadgroup",
           "--no-loadscope-reorder", *PYTEST_SELECT, *extra]
    print("coverage: " + " ".join(cmd), flush=True)
    return subprocess.run(cmd, cwd=ROOT, env=env, check=False).returncode


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--no-run", action="store_true", help="report on the data files already in --dat")
    ap.add_argument("--jobs", "-n", type=int, default=2, help="pytest-xdist workers (default 2)")
    ap.add_argument("--dat", type=Path, default=OUT / "dat", help="data folder (default sim_build/coverage/dat)")
    ap.add_argument("--out", type=Path, default=OUT, help="report folder (default sim_build/coverage)")
    ap.add_argument("--waivers", type=Path, default=WAIVERS, help="named exceptions (TOML)")
    ap.add_argument("pytest_args", nargs="*", help="more pytest arguments, after `--`")
    args = ap.parse_args(argv)
    targets = TARGETS
    if args.jobs < 1:
        ap.error(f"--jobs {args.jobs}: at least 1")
    if args.no_run and args.pytest_args:
        ap.error("pytest arguments given with --no-run")
    status, fcov = 0, args.out / "fcov"
    try:
        waivers = parse_waivers(args.waivers.read_text(encoding="utf-8"), str(args.waivers)) if args.waivers.is_file() else []
        if not args.no_run and run_regression(args.dat, fcov, args.jobs, args.pytest_args):
            print("coverage: the regression failed; the figures below are incomplete", file=sys.stderr)
            status = 1
        if fcov.is_dir() and subprocess.run([sys.executable, str(ROOT / "tools" / "fcov_report.py"), "--in", str(fcov),
                                             "--check", "--md", str(args.out / "fcov.md")], cwd=ROOT, check=False).returncode:
            print("coverage: tools/fcov_report.py --check failed", file=sys.stderr)
            status = 1
        files = sorted(args.dat.glob("*.dat"))
        if not files:
            raise UsageError(f"no coverage data in {args.dat} (run without --no-run first)")
        counts = merge(parse_dat(f.read_text(errors="replace")) for f in files)
    except (UsageError, OSError, ValueError) as e:
        print(f"coverage: error: {e}", file=sys.stderr)
        return 2
    reports = module_reports(counts, waivers)
    stale = stale_waivers(reports, waivers)
    summary = markdown(reports, targets, len(files), stale)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "merged.dat").write_text(write_dat({p: c for p, c in counts.items() if p.file.startswith("rtl/")}))
    (args.out / "summary.md").write_text(summary)
    write_sources(reports, args.out / "src")
    print(summary + f"\ncoverage: {len(files)} data files merged into {args.out / 'merged.dat'}; "
          f"{args.out / 'summary.md'}, annotated sources in {args.out / 'src'}")
    if not overall(reports, targets, stale):
        bad = [r.module for r in reports.values() if r.status(targets) == "below"]
        print("coverage: FAILED: " + "; ".join([f"below target without a named exception: {', '.join(bad)}"] * bool(bad)
                                               + [f"{len(stale)} waiver(s) match no uncovered point"] * bool(stale)
                                               + ["no rtl/ points"] * (not reports)), file=sys.stderr)
        return 1
    return status


if __name__ == "__main__":
    sys.exit(main())
