#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The test plan: which tests, proofs and coverage bins check each part of the contract.

tools/testplan.toml has one `[[row]]` per contract item; docs/testplan.md is generated from it
(region `testplan`) and checked against the repository, so the plan cannot go stale:

    tools/testplan.py --check    # exit 1 with one line per problem (tb/repo/test_testplan.py runs it)
    tools/testplan.py --write    # regenerate docs/testplan.md's table (make testplan), then check

A row:

    [[row]]
    id = "PROTOCOL §4.1"                # or "PROTOCOL §3 cmdDIG_CFG set", "DESIGN decision 5"
    title = "what the row checks"
    tests = ["tb/brainstem_dio/test_latch.py::test_rearm_meets_edge",   # a cocotb test
             "tb/model/test_model.py::test_latch_*",                    # pytest functions
             "host/tests/test_host_framing.py"]                         # a whole pytest file
    proofs = ["bsd_trans_latch", "bsd_tick_gen/prove_clk2m"]            # formal/<job>.sby [tasks]
    bins = ["latch", "timer:outcome=timeout", "command:cmd=DIG_IO,outcome=reply/cmdIndexErr"]

Row ids name a part of a document, then optionally a topic (several rows may share a part):
- `PROTOCOL §N` / `PROTOCOL §N.M`: a `##` / `###` heading of docs/PROTOCOL.md (`## 3. Commands`,
  `### 4.1 Transition latch (ENA)`). Every such heading needs a row, except one with no text of
  its own before its first subheading (§4: its rows are §4.1 and §4.2). An unnumbered `##`/`###`
  heading there is named by its text (`PROTOCOL <heading>`) and needs a row too.
- `DESIGN decision N`: the numbered decisions (`N. **...**`) of docs/DESIGN.md; each needs a row.
  `DESIGN <heading>`: its other `##`/`###` headings (`DESIGN Latencies`); each needs a row too,
  except the one that holds the numbered decisions (its rows are the decisions).
- `FPGA <heading>`: a `##`/`###` heading of docs/fpga.md (the serial wrapper, outside the
  contract), backticks dropped (`FPGA brainstem_dio_uart`). Optional: a home for the wrapper's tests.
The `#` title of a document never counts.

--check verifies that (a) every required heading and decision has a row and every row names an
existing one; (b) every row has at least one test or proof (bins say what the tests reach, they
check nothing on their own); (c) every name exists, found without running anything:
- a cocotb test is `<file>::<name>`, an `async def` at the top of a tb/**/test_*.py file decorated
  with `@SUITE.test(...)` (any `X.test(...)` with `X = Suite(...)`) or `@cocotb.test(...)`, read
  with `ast`; a file that holds cocotb tests must be named with them, test by test (its pytest
  entry, which runs them all, is refused);
- a pytest entry is a path (a file or folder of test_*.py files without cocotb tests), or
  `<file>::<function>` / `<file>::<Class>::<method>` (a `[params]` suffix is ignored), or a prefix
  ending in `*` (`<file>::test_table_*`) that matches at least one test function, also by `ast`;
- a proof is a job (formal/<job>.sby), or `job/task` (a task of its [tasks] section);
- a bin is a coverpoint of tb/lib/fcov.py's COVERPOINTS, optionally `:axis=value[/value],...`;
  the pattern must match at least one bin that tools/fcov_unreachable.toml leaves reachable;
(d) every cocotb test of tb/ is in at least one row (a new test forces a plan update); and that
docs/testplan.md's region is what --write makes of the plan now. Formal tasks and coverpoints
that no row names are printed as `note:` lines, not errors (a proof can be merged before its row).

Exit status: 0 fine; 1 the check failed; 2 bad arguments or an unreadable plan.
"""

from __future__ import annotations

import argparse
import ast
import fnmatch
import importlib.util
import re
import sys
import tomllib
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))

import fcov_report
from docregions import RegionError, fill, fill_file
from fcov import bins_of

REGION = "testplan"
DOCS = ("PROTOCOL", "DESIGN", "FPGA")
ROW_KEYS = {"id", "title", "tests", "proofs", "bins"}


class PlanError(Exception):
    """The plan or a file it reads cannot be parsed (exit status 2)."""


@dataclass(frozen=True)
class Layout:
    """Where everything is (the repository's own files by default; tests use a small copy)."""

    root: Path = ROOT
    plan: str = "tools/testplan.toml"
    doc: str = "docs/testplan.md"
    protocol: str = "docs/PROTOCOL.md"
    design: str = "docs/DESIGN.md"
    fpga: str = "docs/fpga.md"
    formal: str = "formal"
    fcov: str = "tb/lib/fcov.py"
    unreachable: str = "tools/fcov_unreachable.toml"
    test_dirs: tuple[str, ...] = ("tb", "host/tests")
    cocotb_dir: str = "tb"

    def path(self, rel: str) -> Path:
        return self.root / rel


@dataclass(frozen=True)
class Anchor:
    doc: str          # PROTOCOL, DESIGN or FPGA
    key: str          # "§4.1", "decision 5", "Latencies"
    title: str
    required: bool
    line: int

    @property
    def name(self) -> str:
        return f"{self.doc} {self.key}"


@dataclass(frozen=True)
class Row:
    id: str
    title: str
    tests: tuple[str, ...] = ()
    proofs: tuple[str, ...] = ()
    bins: tuple[str, ...] = ()


@dataclass
class Tests:
    """The tests found by `ast` under the layout's test folders."""

    cocotb: dict[str, list[str]] = field(default_factory=dict)    # file -> cocotb test names
    pytest: dict[str, list[str]] = field(default_factory=dict)    # file -> pytest node names
    entries: dict[str, set[str]] = field(default_factory=dict)    # file -> its Suite pytest entries


# ------------------------------------------------------------------------------ documents

_HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
_NUMBERED = re.compile(r"^(\d+(?:\.\d+)*)\.?\s+(.*)$")
_DECISION = re.compile(r"^(\d+)\.\s+\*\*(.+?)\*\*")


def _sections(text: str) -> list[tuple[int, str, int, list[str]]]:
    """(level, heading text, line number, body lines up to the next heading of any level)."""
    out: list[tuple[int, str, int, list[str]]] = []
    fence = False
    for i, line in enumerate(text.splitlines(), 1):
        if line.lstrip().startswith("```"):
            fence = not fence
        hit = None if fence else _HEADING.match(line)
        if hit:
            out.append((len(hit.group(1)), hit.group(2).replace("`", ""), i, []))
        elif out:
            out[-1][3].append(line)
    return out


def _own_text(sections: list[tuple[int, str, int, list[str]]], k: int) -> bool:
    """Whether section k has text of its own, or no subsection to carry its rows."""
    level = sections[k][0]
    has_sub = k + 1 < len(sections) and sections[k + 1][0] > level
    return bool("".join(sections[k][3]).strip()) or not has_sub


def _plain_key(head: str) -> str:
    """An unnumbered heading's key: its text without a trailing `(...)` (`Latencies`)."""
    return re.sub(r"\s*\([^()]*\)$", "", head) or head


def heading_anchors(doc: str, text: str, required: bool) -> list[Anchor]:
    """The `##` and `###` headings of a document; numbered ones are keyed `§N`."""
    secs = _sections(text)
    out = []
    for k, (level, head, line, _) in enumerate(secs):
        if level not in (2, 3):
            continue
        num = _NUMBERED.match(head)
        key, title = (f"§{num.group(1)}", num.group(2)) if num else (_plain_key(head), head)
        out.append(Anchor(doc, key, title, required and _own_text(secs, k), line))
    return out


def design_anchors(text: str) -> list[Anchor]:
    """DESIGN.md's numbered decisions and its other headings."""
    secs = _sections(text)
    out = []
    for k, (level, head, line, body) in enumerate(secs):
        if level not in (2, 3):
            continue
        decisions = []
        for j, ln in enumerate(body):
            hit = _DECISION.match(ln)
            if hit:
                decisions.append(Anchor("DESIGN", f"decision {hit.group(1)}", hit.group(2).rstrip("."),
                                        True, line + 1 + j))
        out.append(Anchor("DESIGN", _plain_key(head), head, not decisions and _own_text(secs, k), line))
        out.extend(decisions)
    return out


def load_anchors(lay: Layout) -> list[Anchor]:
    def read(rel: str) -> str:
        try:
            return lay.path(rel).read_text(encoding="utf-8")
        except OSError as e:
            raise PlanError(f"{rel}: {e.strerror or e}") from None

    anchors = heading_anchors("PROTOCOL", read(lay.protocol), True) + design_anchors(read(lay.design))
    if lay.path(lay.fpga).is_file():
        anchors += heading_anchors("FPGA", read(lay.fpga), False)
    return anchors


def resolve(row_id: str, anchors: Sequence[Anchor]) -> Anchor | None:
    """The anchor a row id names: `<DOC> <key>` and optionally ` <topic>`, longest key first."""
    doc, _, rest = row_id.partition(" ")
    best = None
    for a in anchors:
        if (a.doc == doc and (rest == a.key or rest.startswith(a.key + " "))
                and (best is None or len(a.key) > len(best.key))):
            best = a
    return best


# ---------------------------------------------------------------------------------- tests

def _is_cocotb_decorator(dec: ast.expr, suites: set[str]) -> bool:
    fn = dec.func if isinstance(dec, ast.Call) else dec
    return (isinstance(fn, ast.Attribute) and fn.attr == "test" and isinstance(fn.value, ast.Name)
            and (fn.value.id == "cocotb" or fn.value.id in suites))


def _suite_names(tree: ast.Module) -> set[str]:
    names = {"SUITE"}
    for node in tree.body:
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Call):
            f = node.value.func
            if (isinstance(f, ast.Name) and f.id == "Suite") or (isinstance(f, ast.Attribute) and f.attr == "Suite"):
                names |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    return names


def _cocotb_name(node: ast.AsyncFunctionDef, suites: set[str]) -> str | None:
    for dec in node.decorator_list:
        if _is_cocotb_decorator(dec, suites):
            if isinstance(dec, ast.Call):
                for kw in dec.keywords:
                    if kw.arg == "name" and isinstance(kw.value, ast.Constant) and isinstance(kw.value.value, str):
                        return kw.value.value
            return node.name
    return None


def _calls_suite_run(fn: ast.FunctionDef | ast.AsyncFunctionDef, suites: set[str]) -> bool:
    for node in ast.walk(fn):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in ("run", "cases")
                and isinstance(node.func.value, ast.Name) and node.func.value.id in suites):
            return True
    for dec in fn.decorator_list:
        for node in ast.walk(dec):
            if (isinstance(node, ast.Attribute) and node.attr == "cases" and isinstance(node.value, ast.Name)
                    and node.value.id in suites):
                return True
    return False


def scan_file(path: Path, rel: str) -> tuple[list[str], list[str], set[str]]:
    """(cocotb test names, pytest node names, the Suite's pytest entries) of one file."""
    try:
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=rel)
    except (OSError, SyntaxError) as e:
        raise PlanError(f"{rel}: cannot be parsed: {e}") from None
    suites = _suite_names(tree)
    cocotb, plain, entries = [], [], set()
    for node in tree.body:
        if isinstance(node, ast.AsyncFunctionDef) and (name := _cocotb_name(node, suites)):
            cocotb.append(name)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name.startswith("test"):
            plain.append(node.name)
            if _calls_suite_run(node, suites):
                entries.add(node.name)
        elif isinstance(node, ast.ClassDef) and node.name.startswith("Test"):
            for sub in node.body:
                if isinstance(sub, (ast.FunctionDef, ast.AsyncFunctionDef)) and sub.name.startswith("test"):
                    plain.append(f"{node.name}::{sub.name}")
    return cocotb, plain, entries


def find_tests(lay: Layout) -> Tests:
    found = Tests()
    for top in lay.test_dirs:
        base = lay.path(top)
        if not base.is_dir():
            continue
        for path in sorted(base.rglob("test_*.py")):
            rel = path.relative_to(lay.root).as_posix()
            cocotb, plain, entries = scan_file(path, rel)
            if cocotb and rel.startswith(lay.cocotb_dir.rstrip("/") + "/"):
                found.cocotb[rel] = cocotb
                found.entries[rel] = entries
            if plain:
                found.pytest[rel] = plain
    return found


# --------------------------------------------------------------------------- proofs, bins

def formal_jobs(lay: Layout) -> list[tuple[str, str]]:
    """(job, task) of each formal/<job>.sby: the first word of each line of its [tasks] section."""
    jobs, section = [], ""
    for sby in sorted(lay.path(lay.formal).glob("*.sby")):
        for line in sby.read_text(encoding="utf-8").splitlines():
            if line.startswith("["):
                section = f"{sby.stem}{line.strip()}"
            elif section == f"{sby.stem}[tasks]" and line.split() and not line.startswith("#"):
                jobs.append((sby.stem, line.split()[0]))
    if not jobs:
        raise PlanError(f"{lay.formal}/: no .sby file with a [tasks] section")
    return jobs


def coverpoints(lay: Layout) -> dict[str, tuple[tuple[str, tuple[str, ...]], ...]]:
    """tb/lib/fcov.py's COVERPOINTS (the module imports nothing of cocotb at load time)."""
    rel = lay.fcov
    spec = importlib.util.spec_from_file_location("_testplan_fcov", lay.path(rel))
    if spec is None or spec.loader is None:
        raise PlanError(f"{rel}: cannot be loaded")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # its dataclasses look their module up there
    try:
        spec.loader.exec_module(mod)
        return dict(mod.COVERPOINTS)
    except Exception as e:  # noqa: BLE001 - any failure to load is a bad input
        raise PlanError(f"{rel}: cannot be loaded: {e}") from None
    finally:
        sys.modules.pop(spec.name, None)


def unreachable_bins(lay: Layout, points: Mapping[str, tuple[tuple[str, tuple[str, ...]], ...]]
                     ) -> dict[str, set[tuple[str, ...]]]:
    """The bins tools/fcov_unreachable.toml calls unreachable, read by tools/fcov_report.py's
    own rule reader (so the plan and the report cannot disagree)."""
    out: dict[str, set[tuple[str, ...]]] = {name: set() for name in points}
    path = lay.path(lay.unreachable)
    if not path.is_file():
        return out
    try:
        rules = fcov_report.load_rules(path, points)
    except fcov_report.InputError as e:
        raise PlanError(str(e)) from None
    for name, axes_def in points.items():
        axes = [a for a, _ in axes_def]
        mine = [r for r in rules if r.coverpoint == name]
        out[name] = {b for b in bins_of(axes_def) if any(r.covers(axes, b) for r in mine)}
    return out


def check_bin(spec: str, points: Mapping[str, tuple[tuple[str, tuple[str, ...]], ...]],
              unreachable: Mapping[str, set[tuple[str, ...]]]) -> str | None:
    """None if `spec` (`point` or `point:axis=v[/v],...`) names reachable bins, else why not."""
    name, _, rest = spec.partition(":")
    if name not in points:
        return f"no coverpoint {name!r} in tb/lib/fcov.py (coverpoints: {', '.join(points)})"
    axes = dict(points[name])
    want: dict[str, set[str]] = {}
    for part in filter(None, (p.strip() for p in rest.split(","))) if rest else ():
        axis, eq, vals = part.partition("=")
        if not eq or axis not in axes:
            return f"{part!r} is not `axis=value` with an axis of {name} ({', '.join(axes)})"
        chosen = set(vals.split("/"))
        bad = sorted(chosen - set(axes[axis]))
        if bad:
            return f"{name}: {axis} has no value {', '.join(bad)} (values: {', '.join(axes[axis])})"
        want[axis] = chosen
    if rest and not want:
        return f"empty bin pattern after {name!r}:"
    order = [a for a, _ in points[name]]
    matching = [b for b in bins_of(points[name])
                if all(dict(zip(order, b))[a] in vs for a, vs in want.items())]
    if all(b in unreachable.get(name, set()) for b in matching):
        return "every bin it matches is unreachable (tools/fcov_unreachable.toml)"
    return None


# ----------------------------------------------------------------------------------- plan

def load_plan(lay: Layout) -> list[Row]:
    rel = lay.plan
    try:
        doc = tomllib.loads(lay.path(rel).read_text(encoding="utf-8"))
    except OSError as e:
        raise PlanError(f"{rel}: {e.strerror or e}") from None
    except tomllib.TOMLDecodeError as e:
        raise PlanError(f"{rel}: {e}") from None
    extra = set(doc) - {"row"}
    if extra:
        raise PlanError(f"{rel}: unknown top-level key(s) {', '.join(sorted(extra))} (only [[row]])")
    rows = []
    for i, raw in enumerate(doc.get("row", []), 1):
        where = f"{rel}: row {i}"
        if not isinstance(raw, Mapping):
            raise PlanError(f"{where}: not a table")
        bad = set(raw) - ROW_KEYS
        if bad:
            raise PlanError(f"{where}: unknown key(s) {', '.join(sorted(bad))} (keys: {', '.join(sorted(ROW_KEYS))})")
        for key in ("id", "title"):
            if not isinstance(raw.get(key), str) or not raw[key].strip():
                raise PlanError(f"{where}: `{key}` must be a non-empty string")
        lists = {}
        for key in ("tests", "proofs", "bins"):
            val = raw.get(key, [])
            if not isinstance(val, list) or not all(isinstance(v, str) and v.strip() for v in val):
                raise PlanError(f"{where} ({raw['id']}): `{key}` must be a list of non-empty strings")
            lists[key] = tuple(v.strip() for v in val)
        rows.append(Row(raw["id"].strip(), " ".join(raw["title"].split()), **lists))
    if not rows:
        raise PlanError(f"{rel}: no [[row]]")
    return rows


@dataclass
class Context:
    anchors: list[Anchor]
    tests: Tests
    jobs: list[tuple[str, str]]
    points: dict[str, tuple[tuple[str, tuple[str, ...]], ...]]
    unreachable: dict[str, set[tuple[str, ...]]]


def load_context(lay: Layout) -> Context:
    points = coverpoints(lay)
    return Context(load_anchors(lay), find_tests(lay), formal_jobs(lay), points, unreachable_bins(lay, points))


def check_test(entry: str, lay: Layout, t: Tests) -> tuple[str | None, list[tuple[str, str]]]:
    """(why `entry` is wrong or None, the cocotb tests (file, name) it names)."""
    path, sep, name = entry.partition("::")
    if path.startswith("/") or ".." in Path(path).parts:
        return "not a path relative to the repository", []
    full = lay.path(path)
    if not full.exists():
        return f"no file or folder {path}", []
    if full.is_dir():
        inside = [f for f in t.cocotb if f.startswith(path.rstrip("/") + "/")]
        if inside:
            return f"{path} holds cocotb tests ({inside[0]}...): name them one by one", []
        if sep:
            return "a folder takes no `::name`", []
        if not any(f.startswith(path.rstrip("/") + "/") for f in t.pytest):
            return f"no pytest test function under {path}", []
        return None, []
    if path in t.cocotb:
        if not sep:
            return f"{path} holds cocotb tests: name them one by one (`{path}::<cocotb test>`)", []
        if name in t.cocotb[path]:
            return None, [(path, name)]
        if name in t.entries.get(path, set()):
            return f"{name} is the file's pytest entry (it runs every cocotb test): name the cocotb tests", []
        return f"no cocotb test {name!r} in {path} (its tests: {', '.join(t.cocotb[path])})", []
    funcs = t.pytest.get(path)
    if funcs is None:
        return f"{path} holds no cocotb test and no pytest test function", []
    if not sep:
        return None, []
    base = name.split("[", 1)[0]
    if base.endswith("*"):
        if not any(fnmatch.fnmatchcase(f, base) for f in funcs):
            return f"no test function of {path} matches {base!r}", []
        return None, []
    if base in funcs or any(f.startswith(base + "::") for f in funcs):
        return None, []
    return f"no test function {base!r} in {path}", []


def check(lay: Layout, rows: Sequence[Row], ctx: Context) -> list[str]:
    """Every problem of the plan against the repository, one message each (empty: fine)."""
    errors: list[str] = []
    seen_ids: set[str] = set()
    covered: set[str] = set()
    mapped: set[tuple[str, str]] = set()
    jobs = {j for j, _ in ctx.jobs}
    tasks = {f"{j}/{t}" for j, t in ctx.jobs}
    for row in rows:
        where = f"{lay.plan}: row {row.id!r}"
        if row.id in seen_ids:
            errors.append(f"{where}: a second row with this id")
        seen_ids.add(row.id)
        anchor = resolve(row.id, ctx.anchors)
        if anchor is None:
            doc = row.id.split(" ", 1)[0]
            known = ", ".join(a.name for a in ctx.anchors if a.doc == doc)
            hint = f" (its parts: {known})" if known else f" (an id starts with one of {', '.join(DOCS)})"
            errors.append(f"{where}: names no heading or decision{hint}")
        else:
            covered.add(anchor.name)
        if not row.tests and not row.proofs:
            errors.append(f"{where}: no test and no proof checks it")
        for key, entries in (("tests", row.tests), ("proofs", row.proofs), ("bins", row.bins)):
            dup = sorted({e for e in entries if entries.count(e) > 1})
            if dup:
                errors.append(f"{where}: {key} lists {', '.join(dup)} twice")
        for entry in row.tests:
            why, cocotb = check_test(entry, lay, ctx.tests)
            if why:
                errors.append(f"{where}: unknown test {entry!r}: {why}")
            mapped.update(cocotb)
        for proof in row.proofs:
            job = proof.split("/", 1)[0]
            if job not in jobs:
                errors.append(f"{where}: unknown proof {proof!r}: {lay.formal}/ has no job {job!r} "
                              f"(jobs: {', '.join(sorted(jobs))})")
            elif "/" in proof and proof not in tasks:
                errors.append(f"{where}: unknown proof {proof!r}: job {job} has the tasks "
                              f"{', '.join(t for j, t in ctx.jobs if j == job)}")
        for spec in row.bins:
            why = check_bin(spec, ctx.points, ctx.unreachable)
            if why:
                errors.append(f"{where}: unknown bin {spec!r}: {why}")
    for a in ctx.anchors:
        if a.required and a.name not in covered:
            src = {"PROTOCOL": lay.protocol, "DESIGN": lay.design}.get(a.doc, lay.fpga)
            errors.append(f"{src}:{a.line}: {a.name} ({a.title}) has no row in {lay.plan}: add one "
                          f"(id = \"{a.name}\" or \"{a.name} <topic>\")")
    for path, names in ctx.tests.cocotb.items():
        for name in names:
            if (path, name) not in mapped:
                errors.append(f"{path}::{name}: this cocotb test is in no row of {lay.plan}: "
                              "add it to the rows of what it checks")
    return errors


def unmapped_info(rows: Sequence[Row], ctx: Context) -> list[str]:
    """What no row names (not an error): formal tasks and coverpoints."""
    named = set()
    for row in rows:
        for p in row.proofs:
            named |= {(j, t) for j, t in ctx.jobs if p in (j, f"{j}/{t}")}
    out = [f"formal task in no row: {j}/{t}" for j, t in ctx.jobs if (j, t) not in named]
    points = {b.split(":", 1)[0] for row in rows for b in row.bins}
    out += [f"coverpoint in no row: {p}" for p in ctx.points if p not in points]
    return out


# --------------------------------------------------------------------------------- render

def _code(s: str) -> str:
    return f"`{s}`"


def _tests_cell(tests: Iterable[str]) -> str:
    by_file: dict[str, list[str]] = {}
    for t in tests:
        path, sep, name = t.partition("::")
        by_file.setdefault(path, [])
        if sep:
            by_file[path].append(name)
    parts = []
    for path, names in by_file.items():
        parts.append(_code(path) + (": " + ", ".join(_code(n) for n in names) if names else ""))
    return "<br>".join(parts) or "—"


def render(rows: Sequence[Row], ctx: Context) -> str:
    n_cocotb = sum(len(v) for v in ctx.tests.cocotb.values())
    proofs = sorted({p for r in rows for p in r.proofs})
    lines = [
        (f"{len(rows)} rows; {n_cocotb} cocotb tests in {len(ctx.tests.cocotb)} files, each in at least "
        f"one row; {len(proofs)} formal jobs/tasks named; generated by `tools/testplan.py --write` "
        "from `tools/testplan.toml`."),
        "",
        "| contract | what is checked | tests | proofs | coverage bins |",
        "|---|---|---|---|---|",
    ]
    for r in rows:
        anchor = resolve(r.id, ctx.anchors)
        where = f"**{r.id}**" + (f"<br>{anchor.title}" if anchor and anchor.title != anchor.key else "")
        cells = [where, r.title, _tests_cell(r.tests),
                 "<br>".join(_code(p) for p in r.proofs) or "—",
                 "<br>".join(_code(b) for b in r.bins) or "—"]
        lines.append("| " + " | ".join(c.replace("|", "\\|") if i < 2 else c.replace("|", "&#124;")
                                       for i, c in enumerate(cells)) + " |")
    return "\n".join(lines) + "\n"


def stale(lay: Layout, body: str) -> str | None:
    """Why docs/testplan.md's region is not `body`, or None."""
    path = lay.path(lay.doc)
    try:
        old = path.read_text(encoding="utf-8")
    except OSError:
        return f"{lay.doc}: missing (it is hand-written around the region `{REGION}`)"
    try:
        new = fill(old, {REGION: body}, where=lay.doc)
    except RegionError as e:
        return str(e)
    if new != old:
        return f"{lay.doc}: the table is stale: run `make testplan` (tools/testplan.py --write) and commit it"
    return None


# ----------------------------------------------------------------------------------- main

def run(lay: Layout, write: bool) -> tuple[int, list[str], list[str]]:
    """(exit status, messages, notes) of --check (write False) or --write; the notes name
    what no row names (formal tasks, coverpoints), which is not an error."""
    rows = load_plan(lay)
    ctx = load_context(lay)
    errors = check(lay, rows, ctx)
    body = render(rows, ctx)
    if write:
        try:
            changed = fill_file(lay.path(lay.doc), {REGION: body})
        except RegionError as e:
            raise PlanError(str(e)) from None
        note = f"{lay.doc}: {'written' if changed else 'unchanged'} ({len(rows)} rows)"
        return (1 if errors else 0), errors + [note], unmapped_info(rows, ctx)
    why = stale(lay, body)
    msgs = errors + ([why] if why else [])
    return (1 if msgs else 0), msgs, unmapped_info(rows, ctx)


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Check or regenerate the test plan (docs/testplan.md).",
                                 epilog="Exit status: 0 fine, 1 the check failed, 2 bad arguments or input.")
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--check", action="store_true", help="check the plan and docs/testplan.md, write nothing")
    mode.add_argument("--write", action="store_true", help="regenerate docs/testplan.md's table, then check")
    ap.add_argument("--root", type=Path, default=ROOT, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    lay = Layout(root=args.root.resolve())
    try:
        status, msgs, notes = run(lay, write=args.write)
    except PlanError as e:
        print(f"testplan: error: {e}", file=sys.stderr)
        return 2
    for m in msgs:
        print(m, file=sys.stderr if status else sys.stdout)
    for note in notes:
        print(f"note: {note}")
    if status:
        print(f"testplan: {len(msgs) - bool(args.write)} problem(s); the plan is tools/testplan.toml (see tools/testplan.py's "
              "docstring for its rows' form)", file=sys.stderr)
    elif not args.write:
        print("testplan: the plan is complete and docs/testplan.md is up to date")
    return status


if __name__ == "__main__":
    sys.exit(main())
