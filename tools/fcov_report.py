# SPDX-License-Identifier: Apache-2.0
"""Merge the functional-coverage files of simulator runs and report bins hit.

Each simulation run with $BSD_FCOV_DIR set writes one JSON file there (tb/lib/fcov.py). Per
coverpoint: its bins, those unreachable by construction (tools/fcov_unreachable.toml, each with
its reason), the reachable ones hit, then the unhit reachable bins. Exit 2: bad arguments or input.
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
sys.path[:0] = [str(ROOT / "host"), str(ROOT / "tb" / "lib")]

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
        def hits(d: Mapping[str, frozenset[str]]) -> bool:
            return all(values[a] in vs for a, vs in d.items())
        return hits(self.match) and not (self.unless and hits(self.unless))

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
    unhit: list[Bin]  # reachable and not hit
    unreachable_hit: list[Bin]  # the rules call these unreachable, yet they were hit
    rule_counts: list[tuple[Rule, int]]

    @property
    def reachable(self) -> int:
        return self.bins - len(self.unreachable)

    @property
    def reachable_hit(self) -> int:
        return len(self.hit - self.unreachable)


def merge(docs: Sequence[tuple[str, Mapping[str, object]]]) -> Runs:
    """Merge the decoded JSON documents [(where, doc)] of several runs."""
    runs = Runs({name: Counter() for name in COVERPOINTS})
    for where, doc in docs:
        hits = doc.get("hits") if isinstance(doc, Mapping) else None
        if not isinstance(hits, Mapping) or doc.get("format") != FORMAT:
            raise InputError(f"{where}: not a functional-coverage file of format {FORMAT}")
        for name, bins in hits.items():
            if name not in COVERPOINTS or not isinstance(bins, Mapping):
                raise InputError(f"{where}: unknown coverpoint {name!r}, or its bins are not an object")
            valid = set(all_bins(name))
            for key, n in bins.items():
                if (b := tuple(key.split("|"))) not in valid or type(n) is not int or n < 0:
                    raise InputError(f"{where}: {name} {key!r}: not a bin of {name} with a count of 0 or more")
                runs.hits[name][b] += n
        runs.files += 1
        runs.tests.add(str(doc.get("test", "?")))
        runs.sims.add(str(doc.get("sim", "?")))
    return runs


def load_dir(directory: Path) -> Runs:
    paths = sorted(directory.glob("*.json")) if directory.is_dir() else None
    if not paths:
        raise InputError(f"{directory}: no such directory" if paths is None else
                         f"{directory}: no coverage files (*.json); run the tests with BSD_FCOV_DIR={directory}")
    try:
        return merge([(str(p), json.loads(p.read_text(encoding="utf-8"))) for p in paths])
    except (OSError, json.JSONDecodeError) as e:
        raise InputError(str(e)) from None


def parse_rules(doc: Mapping[str, object], where: str = "<rules>", points: Mapping[str, Axes] = COVERPOINTS) -> list[Rule]:
    if not isinstance(raw := doc.get("rule", []), list):
        raise InputError(f"{where}: `rule` must be an array of tables")
    rules = []
    for i, r in enumerate(raw, 1):
        w = f"{where}: rule {i}"
        if not isinstance(r, Mapping) or set(r) - {"coverpoint", "match", "unless", "reason"}:
            raise InputError(f"{w}: not a table of coverpoint, match, unless, reason")
        if r.get("coverpoint") not in points:
            raise InputError(f"{w}: unknown coverpoint {r.get('coverpoint')!r}")
        if not isinstance(r.get("reason"), str) or not r["reason"].strip():
            raise InputError(f"{w}: every unreachable bin needs a reason")
        axes, sets = dict(points[r["coverpoint"]]), []
        for spec in (r.get("match"), r.get("unless", {})):
            if not isinstance(spec, Mapping):
                raise InputError(f"{w}: match/unless must be tables")
            sets.append({})
            for axis, v in spec.items():
                vs = [v] if isinstance(v, str) else v
                if axis not in axes or not isinstance(vs, list) or not vs or not all(x in axes[axis] for x in vs):
                    raise InputError(f"{w}: {axis} = {v!r}: not an axis of {r['coverpoint']} with values of it")
                sets[-1][axis] = frozenset(vs)
        if not sets[0]:
            raise InputError(f"{w}: empty match")
        rules.append(Rule(r["coverpoint"], *sets, r["reason"]))
    return rules


def load_rules(path: Path, points: Mapping[str, Axes] = COVERPOINTS) -> list[Rule]:
    try:
        return parse_rules(tomllib.loads(path.read_text(encoding="utf-8")), str(path), points)
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise InputError(f"{path}: {e}") from None


def summarize(runs: Runs, rules: Sequence[Rule]) -> list[PointSummary]:
    out = []
    for name, axes_def in COVERPOINTS.items():
        axes, bins = tuple(a for a, _ in axes_def), all_bins(name)
        counts = [(r, {b for b in bins if r.covers(axes, b)}) for r in rules if r.coverpoint == name]
        unreachable = set().union(*(c for _, c in counts))
        hit = {b for b, n in runs.hits[name].items() if n > 0}
        out.append(PointSummary(name, axes, len(bins), unreachable, hit, [b for b in bins if b not in unreachable | hit],
                                [b for b in bins if b in unreachable & hit], [(r, len(c)) for r, c in counts]))
    return out


def failed(summary: Sequence[PointSummary]) -> bool:
    return any(s.unhit or s.unreachable_hit for s in summary)


def render(summary: Sequence[PointSummary], runs: Runs, max_unhit: int = 200) -> str:
    lines = [(f"Merged from {runs.files} simulator runs ({len(runs.tests)} tests; "
              f"{', '.join(sorted(runs.sims)) or 'no simulator'})."), "",
             "| coverpoint | axes | bins | unreachable | reachable | reachable hit | unhit |",
             "|---|---|---:|---:|---:|---:|---:|"]
    for s in summary:
        pct = f" ({100 * s.reachable_hit / s.reachable:.0f} %)" if s.reachable else ""
        lines.append(f"| {s.name} | {' × '.join(s.axes)} | {s.bins} | {len(s.unreachable)} | "
                     f"{s.reachable} | {s.reachable_hit}{pct} | {len(s.unhit)} |")
    lines += ["", "Unreachable by construction (tools/fcov_unreachable.toml):", ""]
    lines += [f"- {s.name}: {r.describe()} ({n} bins): {r.reason}" for s in summary for r, n in s.rule_counts] or ["- none"]
    lines += ["", "Reachable bins not hit:", ""]
    unhit = [(s, b) for s in summary for b in s.unhit]
    lines += [f"- {s.name}: {', '.join(f'{a}={v}' for a, v in zip(s.axes, b))}" for s, b in unhit[:max_unhit]] or ["- none"]
    lines += [f"- … and {len(unhit) - max_unhit} more"] * (len(unhit) > max_unhit)
    if wrong := [f"- {s.name}: {bin_key(b)}" for s in summary for b in s.unreachable_hit]:
        lines += ["", "Hit, yet listed as unreachable (the list is wrong):", "", *wrong]
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--in", dest="indir", type=Path, required=True, metavar="DIR", help="the folder $BSD_FCOV_DIR pointed at")
    ap.add_argument("--unreachable", type=Path, default=DEFAULT_RULES, metavar="TOML",
                    help="the unreachable-bin list (default tools/fcov_unreachable.toml)")
    ap.add_argument("--md", type=Path, metavar="FILE", help="also write the table to FILE")
    ap.add_argument("--check", action="store_true", help="exit 1 if a reachable bin is unhit or an unreachable one was hit")
    args = ap.parse_args(argv)
    try:
        summary = summarize(runs := load_dir(args.indir), load_rules(args.unreachable))
        sys.stdout.write(text := render(summary, runs))
        if args.md:
            args.md.write_text(text, encoding="utf-8")
    except (InputError, OSError) as e:
        print(f"fcov_report: error: {e}", file=sys.stderr)
        return 2
    if args.check and failed(summary):
        print(f"fcov_report: {sum(len(s.unhit) for s in summary)} reachable bins unhit, "
              f"{sum(len(s.unreachable_hit) for s in summary)} unreachable bins hit", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
