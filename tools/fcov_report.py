# SPDX-License-Identifier: Apache-2.0
"""Merge the functional-coverage files of simulator runs and report bins hit.

Each top-level simulation run with $BSD_FCOV_DIR set writes one JSON file there
(tb/lib/fcov.py). This tool merges them and prints, per coverpoint/cross, how many bins exist,
how many are unreachable by construction (tools/fcov_unreachable.toml, each with its reason),
and how many of the reachable ones were hit, then the unhit reachable bins.

    tools/fcov_report.py --in DIR                 # print the table
    tools/fcov_report.py --in DIR --check         # exit 1 if a reachable bin is unhit
    tools/fcov_report.py --in DIR --md FILE       # also write the table to FILE (make coverage)

Exit status: 0 fine; 1 --check failed (a reachable bin unhit, or a bin the list calls
unreachable was hit); 2 bad arguments or input.
"""

from __future__ import annotations

import argparse
import json
import sys
import tomllib
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# fcov's protocol numbers come from the host library (through tb/lib/bsd_protocol.py): this
# tool also runs outside the venv (make testplan).
sys.path.insert(0, str(ROOT / "host"))
sys.path.insert(0, str(ROOT / "tb" / "lib"))
sys.path.insert(0, str(ROOT / "tools"))

from fcov import COVERPOINTS, FORMAT, Axes, Bin, all_bins, bin_key

DEFAULT_RULES = ROOT / "tools" / "fcov_unreachable.toml"


class InputError(Exception):
    """Bad input files or rules (exit status 2)."""


@dataclass(frozen=True)
class Rule:
    coverpoint: str
    match: Mapping[str, frozenset[str]]
    unless: Mapping[str, frozenset[str]]
    reason: str

    def covers(self, axes: Sequence[str], b: Bin) -> bool:
        values = dict(zip(axes, b))
        if not all(values[a] in vs for a, vs in self.match.items()):
            return False
        return not (self.unless and all(values[a] in vs for a, vs in self.unless.items()))

    def describe(self) -> str:
        return " unless ".join(", ".join(f"{a}={'/'.join(sorted(vs))}" for a, vs in d.items())
                               for d in (self.match, self.unless) if d)


@dataclass
class Runs:
    hits: dict[str, Counter[Bin]]
    files: int = 0
    tests: set[str] = field(default_factory=set)
    sims: set[str] = field(default_factory=set)


@dataclass
class PointSummary:
    name: str
    axes: tuple[str, ...]
    bins: int
    unreachable: set[Bin]
    hit: set[Bin]
    unhit: list[Bin]             # reachable and not hit
    unreachable_hit: list[Bin]   # the rules call these unreachable, yet they were hit
    rule_counts: list[tuple[Rule, int]]

    @property
    def reachable(self) -> int:
        return self.bins - len(self.unreachable)

    @property
    def reachable_hit(self) -> int:
        return len(self.hit - self.unreachable)


# ----------------------------------------------------------------------------------- input

def _parse_bin(name: str, key: str, where: str) -> Bin:
    axes = COVERPOINTS[name]
    b = tuple(key.split("|"))
    if len(b) != len(axes) or any(v not in vals for v, (_, vals) in zip(b, axes)):
        raise InputError(f"{where}: {key!r} is not a bin of {name}")
    return b


def merge(docs: Sequence[tuple[str, Mapping[str, object]]]) -> Runs:
    """Merge the decoded JSON documents [(where, doc)] of several runs."""
    runs = Runs({name: Counter() for name in COVERPOINTS})
    for where, doc in docs:
        hits = doc.get("hits") if isinstance(doc, Mapping) else None
        if not isinstance(hits, Mapping) or doc.get("format") != FORMAT:
            raise InputError(f"{where}: not a functional-coverage file of format {FORMAT}")
        for name, bins in hits.items():
            if name not in COVERPOINTS:
                raise InputError(f"{where}: unknown coverpoint {name!r}")
            if not isinstance(bins, Mapping):
                raise InputError(f"{where}: {name}: bins must be an object")
            for key, n in bins.items():
                if not isinstance(n, int) or isinstance(n, bool) or n < 0:
                    raise InputError(f"{where}: {name} {key}: count must be a non-negative integer")
                runs.hits[name][_parse_bin(name, key, where)] += n
        runs.files += 1
        runs.tests.add(str(doc.get("test", "?")))
        runs.sims.add(str(doc.get("sim", "?")))
    return runs


def load_dir(directory: Path) -> Runs:
    if not directory.is_dir():
        raise InputError(f"{directory}: no such directory")
    paths = sorted(directory.glob("*.json"))
    if not paths:
        raise InputError(f"{directory}: no coverage files (*.json); run the tests with BSD_FCOV_DIR={directory}")
    docs = []
    for path in paths:
        try:
            docs.append((str(path), json.loads(path.read_text(encoding="utf-8"))))
        except (OSError, json.JSONDecodeError) as e:
            raise InputError(f"{path}: {e}") from None
    return merge(docs)


def _values(name: str, axis_values: Mapping[str, tuple[str, ...]], spec: object, where: str) -> dict[str, frozenset[str]]:
    if not isinstance(spec, Mapping):
        raise InputError(f"{where}: match/unless must be tables")
    out = {}
    for axis, v in spec.items():
        if axis not in axis_values:
            raise InputError(f"{where}: {name} has no axis {axis!r}")
        vs = [v] if isinstance(v, str) else v
        if not isinstance(vs, list) or not vs or not all(isinstance(x, str) for x in vs):
            raise InputError(f"{where}: {axis}: a value or a list of values")
        bad = [x for x in vs if x not in axis_values[axis]]
        if bad:
            raise InputError(f"{where}: {axis} has no value {bad[0]!r}")
        out[axis] = frozenset(vs)
    return out


def parse_rules(doc: Mapping[str, object], where: str = "<rules>",
                points: Mapping[str, Axes] = COVERPOINTS) -> list[Rule]:
    rules = []
    raw = doc.get("rule", [])
    if not isinstance(raw, list):
        raise InputError(f"{where}: `rule` must be an array of tables")
    for i, r in enumerate(raw):
        w = f"{where}: rule {i + 1}"
        if not isinstance(r, Mapping):
            raise InputError(f"{w}: not a table")
        extra = set(r) - {"coverpoint", "match", "unless", "reason"}
        if extra:
            raise InputError(f"{w}: unknown keys {sorted(extra)}")
        name = r.get("coverpoint")
        if name not in points:
            raise InputError(f"{w}: unknown coverpoint {name!r}")
        reason = r.get("reason")
        if not isinstance(reason, str) or not reason.strip():
            raise InputError(f"{w}: every unreachable bin needs a reason")
        axis_values = dict(points[name])
        match = _values(name, axis_values, r.get("match"), w)
        if not match:
            raise InputError(f"{w}: empty match")
        rules.append(Rule(name, match, _values(name, axis_values, r.get("unless", {}), w), reason))
    return rules


def load_rules(path: Path, points: Mapping[str, Axes] = COVERPOINTS) -> list[Rule]:
    try:
        doc = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise InputError(f"{path}: {e}") from None
    return parse_rules(doc, str(path), points)


# -------------------------------------------------------------------------------- summary

def summarize(runs: Runs, rules: Sequence[Rule]) -> list[PointSummary]:
    out = []
    for name, axes_def in COVERPOINTS.items():
        axes = tuple(a for a, _ in axes_def)
        bins = all_bins(name)
        mine = [r for r in rules if r.coverpoint == name]
        unreachable: set[Bin] = set()
        counts = []
        for r in mine:
            covered = {b for b in bins if r.covers(axes, b)}
            counts.append((r, len(covered)))
            unreachable |= covered
        hit = {b for b, n in runs.hits[name].items() if n > 0}
        out.append(PointSummary(
            name, axes, len(bins), unreachable, hit,
            unhit=[b for b in bins if b not in unreachable and b not in hit],
            unreachable_hit=[b for b in bins if b in unreachable and b in hit],
            rule_counts=counts,
        ))
    return out


def failed(summary: Sequence[PointSummary]) -> bool:
    return any(s.unhit or s.unreachable_hit for s in summary)


def render(summary: Sequence[PointSummary], runs: Runs, max_unhit: int = 200) -> str:
    lines = [
        (f"Merged from {runs.files} simulator runs ({len(runs.tests)} tests; "
        f"{', '.join(sorted(runs.sims)) or 'no simulator'})."),
        "",
        "| coverpoint | axes | bins | unreachable | reachable | reachable hit | unhit |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for s in summary:
        pct = f" ({100 * s.reachable_hit / s.reachable:.0f} %)" if s.reachable else ""
        lines.append(f"| {s.name} | {' × '.join(s.axes)} | {s.bins} | {len(s.unreachable)} | "
                     f"{s.reachable} | {s.reachable_hit}{pct} | {len(s.unhit)} |")
    lines += ["", "Unreachable by construction (tools/fcov_unreachable.toml):", ""]
    lines += [f"- {s.name}: {r.describe()} ({n} bins): {r.reason}" for s in summary for r, n in s.rule_counts] or ["- none"]
    lines += ["", "Reachable bins not hit:", ""]
    unhit = [(s, b) for s in summary for b in s.unhit]
    lines += [f"- {s.name}: {', '.join(f'{a}={v}' for a, v in zip(s.axes, b))}" for s, b in unhit[:max_unhit]] or ["- none"]
    if len(unhit) > max_unhit:
        lines.append(f"- … and {len(unhit) - max_unhit} more")
    wrong = [(s, b) for s in summary for b in s.unreachable_hit]
    if wrong:
        lines += ["", "Hit, yet listed as unreachable (the list is wrong):", ""]
        lines += [f"- {s.name}: {bin_key(b)}" for s, b in wrong]
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------------- main

def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--in", dest="indir", type=Path, required=True, metavar="DIR",
                    help="the folder $BSD_FCOV_DIR pointed at")
    ap.add_argument("--unreachable", type=Path, default=DEFAULT_RULES, metavar="TOML",
                    help=f"the unreachable-bin list (default {DEFAULT_RULES.relative_to(ROOT)})")
    ap.add_argument("--md", type=Path, metavar="FILE", help="also write the table to FILE")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 if a reachable bin is unhit or an unreachable one was hit")
    args = ap.parse_args(argv)
    try:
        runs = load_dir(args.indir)
        rules = load_rules(args.unreachable)
    except InputError as e:
        print(f"fcov_report: error: {e}", file=sys.stderr)
        return 2
    summary = summarize(runs, rules)
    text = render(summary, runs)
    sys.stdout.write(text)
    if args.md:
        try:
            args.md.write_text(text, encoding="utf-8")
        except OSError as e:
            print(f"fcov_report: error: {e}", file=sys.stderr)
            return 2
    if args.check and failed(summary):
        n = sum(len(s.unhit) for s in summary)
        m = sum(len(s.unreachable_hit) for s in summary)
        print(f"fcov_report: {n} reachable bins unhit, {m} unreachable bins hit", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
