#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Where `make test`'s time goes: venv, Verilator builds, Icarus builds, simulation per test
file, pytest-xdist idle time, and the number of distinct builds.

    .venv/bin/python sim/test_time.py            # a fresh clone of HEAD in a temporary folder
    .venv/bin/python sim/test_time.py --here     # the timing records of the last run here
    .venv/bin/python sim/test_time.py --write    # ... and fill the table in docs/benchmarks.md

A fresh clone measures what a new user (and CI) pays: the venv from PyPI and every build
from cold, as in `git clone ... && make test`. Nothing of this checkout's caches is used.
Its figures come from the timing records that tb/lib/runner.py and tb/conftest.py append to
sim_build/timing/*.jsonl during the run.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))


def load_records(timing: Path) -> list[dict]:
    if not timing.is_dir():
        raise SystemExit(f"test_time: no timing records in {timing}: run `make test` first")
    records = []
    for path in sorted(timing.glob("*.jsonl")):
        for line in path.read_text().splitlines():
            rec = json.loads(line)
            rec["worker"] = path.stem
            records.append(rec)
    return records


def summarize(records: list[dict]) -> dict:
    """Figures of the last pytest session in the records."""
    sessions = [r for r in records if r["kind"] == "session"]
    if not sessions:
        raise SystemExit("test_time: the records hold no finished pytest session")
    last = max(sessions, key=lambda r: r["t_end"])
    t_start = last["t_end"] - last["seconds"]
    recs = [r for r in records if t_start <= r["t_end"] <= last["t_end"]]
    builds: dict[str, list[float]] = defaultdict(list)
    distinct: dict[str, set] = defaultdict(set)
    for r in recs:
        if r["kind"] == "build":
            builds[r["sim"]].append(r["seconds"])
            distinct[r["sim"]].add((r["toplevel"], r["build"]))
    per_file: dict[str, float] = defaultdict(float)
    per_worker: dict[str, float] = defaultdict(float)
    sim_run: dict[str, float] = defaultdict(float)
    items = 0
    for r in recs:
        if r["kind"] == "item":
            path = r["nodeid"].split("::", 1)[0]
            per_file[path] += r["seconds"]
            per_worker[r["worker"]] += r["seconds"]
            items += r["when"] == "call"
        elif r["kind"] == "test":
            sim_run[r["sim"]] += r["seconds"]
    wall = last["seconds"]
    workers = last["workers"]
    busy = sum(per_worker.values())
    return {
        "wall": wall, "workers": workers, "items": items,
        "builds": {s: (len(distinct[s]), sum(v)) for s, v in builds.items()},
        "sim_run": dict(sim_run), "per_file": dict(per_file),
        "idle": max(0.0, workers * wall - busy),
        "slowest": sorted(per_file.items(), key=lambda kv: -kv[1]),
    }


def fresh_clone_run(jobs: int) -> tuple[dict, float, float, Path]:
    """Clone HEAD, time `make venv` and `make test` there; return figures and times."""
    tmp = Path(tempfile.mkdtemp(prefix="bsd-fresh-"))
    clone = tmp / "brainstem_dio"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "VERILATOR_ROOT")}
    t0 = time.time()
    subprocess.run(["make", "-s", "venv"], cwd=clone, env=env, check=True)
    venv_s = time.time() - t0
    t0 = time.time()
    res = subprocess.run(["make", "test", f"JOBS={jobs}"], cwd=clone, env=env,
                         capture_output=True, text=True, check=False)
    test_s = time.time() - t0
    (tmp / "make-test.log").write_text(res.stdout + res.stderr)
    if res.returncode != 0:
        raise SystemExit(f"test_time: make test failed in the fresh clone; see {tmp}/make-test.log")
    return summarize(load_records(clone / "sim_build" / "timing")), venv_s, test_s, tmp


def table(s: dict, venv_s: float | None, total_s: float | None, how: str) -> str:
    rows = []
    if total_s is not None:
        rows.append(("fresh clone: `make venv` + `make test`, wall", f"{(venv_s or 0) + total_s:.0f} s"))
    if venv_s is not None:
        rows.append(("venv (pip install of requirements.txt)", f"{venv_s:.0f} s"))
    rows.append((f"pytest wall ({s['workers']} workers, {s['items']} tests)", f"{s['wall']:.0f} s"))
    for sim in sorted(s["builds"]):
        n, secs = s["builds"][sim]
        rows.append((f"{sim}: builds (distinct / build time, all workers)", f"{n} / {secs:.0f} s"))
    for sim in sorted(s["sim_run"]):
        rows.append((f"{sim}: simulation time of cocotb runs", f"{s['sim_run'][sim]:.0f} s"))
    rows.append(("pytest-xdist idle (workers x wall - busy)", f"{s['idle']:.0f} s"))
    out = [f"Measured {dt.date.today().isoformat()} by `{how}` on {os.cpu_count()} cores.", "",
           "| what | time |", "|---|---|"]
    out += [f"| {a} | {b} |" for a, b in rows]
    out += ["", "Per test file (set-up + call + tear-down, summed over workers):", "",
            "| test file | time |", "|---|---|"]
    out += [f"| `{path}` | {secs:.0f} s |" for path, secs in s["slowest"]]
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--here", action="store_true", help="use this checkout's last run")
    ap.add_argument("--write", action="store_true", help="fill the table in docs/benchmarks.md")
    ap.add_argument("--jobs", type=int, default=2, help="pytest-xdist workers (default 2)")
    args = ap.parse_args(argv)
    if args.jobs < 1:
        ap.error("--jobs must be at least 1")
    if args.here:
        s, venv_s, total_s = summarize(load_records(ROOT / "sim_build" / "timing")), None, None
        how = "make test; python sim/test_time.py --here"
    else:
        s, venv_s, total_s, tmp = fresh_clone_run(args.jobs)
        how = f"python sim/test_time.py --jobs {args.jobs} (a fresh clone of HEAD)"
        print(f"fresh clone in {tmp}")
    text = table(s, venv_s, total_s, how)
    print(text)
    if args.write:
        import docregions

        docregions.fill_file(ROOT / "docs" / "benchmarks.md", {"test-time": text})
    return 0


if __name__ == "__main__":
    sys.exit(main())
