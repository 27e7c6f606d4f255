#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Check docs/testplan.md's hand-written table against the repository (exit 1 per problem).

A row is `| **<id>**[<br>title] | what | tests | proofs | bins |`; tests are
`` `file`: `name`, `name`<br>`file` `` (a cocotb file is named test by test; a pytest file or
folder alone, or `name` / `Class::method` / `prefix*`), proofs the [tasks] of formal/<job>.sby (`job` or
`job/task`), bins tb/lib/fcov.py COVERPOINTS (`point[:axis=v[/v],...]`, some bin reachable).
Checked: every PROTOCOL.md `##`/`###` section with text of its own, every DESIGN.md decision
and other section has a row and every id names one (`FPGA <heading>` optional); every row has
a test or proof; every name exists (read with `ast`); every cocotb test file of tb/ is in a row;
every message of tools/protocol.toml (the contract's error paths) is used by a named test file.
Exit status: 0 fine, 1 problems, 2 unreadable input.
"""

from __future__ import annotations

import argparse
import ast
import fnmatch
import re
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import fcov_report
from fcov import COVERPOINTS

PLAN = "docs/testplan.md"


def anchors(root: Path) -> dict[str, bool]:
    """Part name (`PROTOCOL §4.1`, `DESIGN decision 5`, `FPGA Bit timing`) -> needs a row."""
    out: dict[str, bool] = {}
    for doc, rel in (("PROTOCOL", "PROTOCOL.md"), ("DESIGN", "DESIGN.md"), ("FPGA", "fpga.md")):
        secs: list[list] = []   # [level, key, body lines]
        fence = False
        for line in (root / "docs" / rel).read_text(encoding="utf-8").splitlines():
            fence ^= line.lstrip().startswith("```")
            if (m := re.match(r"^(#{1,6})\s+(.*?)\s*$", line)) and not fence:
                head = m.group(2).replace("`", "")
                num = re.match(r"^(\d+(?:\.\d+)*)\.?\s", head)
                secs.append([len(m.group(1)), f"§{num.group(1)}" if num else re.sub(r"\s*\([^()]*\)$", "", head), []])
            elif secs:
                secs[-1][2].append(line)
        for k, (level, key, body) in enumerate(secs):
            if level not in (2, 3):
                continue
            decisions = [m.group(1) for ln in body if doc == "DESIGN" and (m := re.match(r"^(\d+)\.\s+\*\*", ln))]
            own = "".join(body).strip() or not (k + 1 < len(secs) and secs[k + 1][0] > level)
            out[f"{doc} {key}"] = doc != "FPGA" and not decisions and bool(own)
            out |= {f"DESIGN decision {n}": True for n in decisions}
    return out


def scan_tests(root: Path) -> tuple[dict[str, list[str]], dict[str, list[str]]]:
    """(file -> cocotb tests under tb/, file -> pytest functions) of tb/ and host/tests."""
    cocotb: dict[str, list[str]] = {}
    plain: dict[str, list[str]] = {}
    for path in sorted([*(root / "tb").rglob("test_*.py"), *(root / "host/tests").rglob("test_*.py")]):
        rel = path.relative_to(root).as_posix()
        for node in ast.parse(path.read_text(encoding="utf-8"), filename=rel).body:
            decs = [d.func if isinstance(d, ast.Call) else d for d in getattr(node, "decorator_list", [])]
            if isinstance(node, ast.AsyncFunctionDef) and any(isinstance(d, ast.Attribute) and d.attr == "test" for d in decs):
                calls = [d for d in node.decorator_list if isinstance(d, ast.Call) and getattr(d.func, "attr", "") == "test"]
                name = next((k.value.value for c in calls for k in c.keywords if k.arg == "name"), node.name)
                cocotb.setdefault(rel, []).append(name)
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name.startswith("test"):
                plain.setdefault(rel, []).append(node.name)
            elif isinstance(node, ast.ClassDef) and node.name.startswith("Test"):
                plain.setdefault(rel, []).extend(f"{node.name}::{s.name}" for s in node.body
                                                 if isinstance(s, ast.FunctionDef) and s.name.startswith("test"))
    return {f: v for f, v in cocotb.items() if f.startswith("tb/")}, plain


def formal_jobs(root: Path) -> set[str]:
    """`job` and `job/task` of each formal/<job>.sby (the first word of each [tasks] line)."""
    out: set[str] = set()
    for sby in sorted((root / "formal").glob("*.sby")):
        section = ""
        for line in sby.read_text(encoding="utf-8").splitlines():
            if line.startswith("["):
                section = line.strip()
            elif section == "[tasks]" and line.split() and not line.startswith("#"):
                out |= {sby.stem, f"{sby.stem}/{line.split()[0]}"}
    if not out:
        raise ValueError("formal/ has no .sby file with a [tasks] section")
    return out


def reachable_bins() -> dict[str, tuple]:
    """Coverpoint -> (its axes, the bins tools/fcov_unreachable.toml leaves reachable)."""
    summary = fcov_report.summarize(fcov_report.merge([]), fcov_report.load_rules(fcov_report.DEFAULT_RULES))
    return {s.name: (COVERPOINTS[s.name], s.unhit) for s in summary}


def parse(text: str) -> list[tuple[str, list[str], list[str], list[str]]]:
    """(id, tests, proofs, bins) of each table row."""
    rows = []
    for line in text.splitlines():
        if line.startswith("| **"):
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]
            tests = []
            for part in cells[2].split("<br>"):
                path, _, names = part.partition(":")
                names = re.findall(r"`([^`]+)`", names)
                tests += [f"{path.strip(' `')}::{n}" for n in names] or [path.strip(" `")] * (path.strip() not in ("", "—"))
            rows.append((cells[0].split("**")[1], tests, *(re.findall(r"`([^`]+)`", c.replace("&#124;", "|")) for c in cells[3:5])))
    return rows


def check(text: str, root: Path = ROOT) -> list[str]:
    parts, (cocotb, plain), jobs, points = anchors(root), scan_tests(root), formal_jobs(root), reachable_bins()
    errors, covered, mapped, files = [], set(), set(), set()
    rows = parse(text)
    if not rows:
        return [f"{PLAN}: no table rows (`| **id** | ...`)"]
    for rid, tests, proofs, bins in rows:
        where = f"{PLAN}: {rid!r}"
        part = max((p for p in parts if rid == p or rid.startswith(p + " ")), key=len, default=None)
        if part is None:
            errors.append(f"{where}: names no section or decision of docs/PROTOCOL.md, DESIGN.md or fpga.md")
        covered.add(part)
        if not tests and not proofs:
            errors.append(f"{where}: no test and no proof checks it")
        for t in tests:
            path, sep, name = t.partition("::")
            name = name.split("[", 1)[0]
            files.add(path)
            under = [f for f in {**cocotb, **plain} if f == path or f.startswith(path.rstrip("/") + "/")]
            if path in cocotb:
                why = None if name in cocotb[path] else f"no cocotb test {name!r} (a cocotb file is named test by test)"
                mapped.add((path, name))
            elif not under or (sep and path not in plain):
                why = "no such test file or folder"
            elif any(f in cocotb for f in under):
                why = "a folder with cocotb tests: name them one by one"
            else:
                funcs = plain.get(path, [])
                ok = not sep or any(fnmatch.fnmatchcase(f, name) or f == name or f.startswith(name + "::") for f in funcs)
                why = None if ok else f"no test function {name!r}"
                files.update(under)
            if why:
                errors.append(f"{where}: unknown test {t!r}: {why}")
        errors += [f"{where}: unknown proof {p!r} (no formal/<job>.sby task)" for p in proofs if p not in jobs]
        for b in bins:
            name, _, rest = b.partition(":")
            want = dict(kv.split("=", 1) for kv in rest.split(",") if "=" in kv)
            ax, ok = points.get(name, ((), []))
            axes = [a for a, _ in ax]
            if name not in points or any(a not in axes for a in want) or (rest and not want) or not any(
                    all(dict(zip(axes, bn))[a] in v.split("/") for a, v in want.items()) for bn in ok):
                errors.append(f"{where}: unknown or unreachable bin {b!r} (tb/lib/fcov.py, tools/fcov_unreachable.toml)")
    errors += [f"{PLAN}: {p} has no row" for p, need in parts.items() if need and p not in covered]
    # A file, not each test, must have a row: a new test in a planned file needs no edit here.
    errors += [f"{f}: this cocotb test file is in no row of {PLAN}" for f in cocotb
               if not any(path == f for path, _ in mapped)]
    used = "\n".join((root / f).read_text(encoding="utf-8") for f in sorted(files) if (root / f).is_file())
    for m in tomllib.loads((root / "tools/protocol.toml").read_text(encoding="utf-8"))["message"]:
        const = "MSG_" + re.sub(r"(?<!^)([A-Z])", r"_\1", m["name"]).upper()
        if m["name"] not in used and const not in used:
            errors.append(f"{PLAN}: message {m['name']} ({const}) is used by no test file of the plan")
    return errors


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="accepted for symmetry: checking is all it does")
    ap.parse_args(argv)
    try:
        errors = check((ROOT / PLAN).read_text(encoding="utf-8"))
    except (OSError, SyntaxError, ValueError, fcov_report.InputError) as e:
        print(f"testplan: error: {e}", file=sys.stderr)
        return 2
    print("\n".join(errors) or f"testplan: {PLAN} is complete", file=sys.stderr if errors else sys.stdout)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
