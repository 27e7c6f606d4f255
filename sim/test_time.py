#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Where `make test`'s time goes, on a fresh clone of HEAD: the venv, the pytest run, the
builds per simulator and the time per test file.

    .venv/bin/python sim/test_time.py [--jobs 2]   # the table: printed and in sim/build/test_time.md

A fresh clone measures what a new user (and CI) pays: the venv from PyPI and every build
from cold, as in `git clone ... && make test`. The per-file times come from pytest's own
JUnit report (`--junitxml`), the build count from the build folders the run left.
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import subprocess
import sys
import tempfile
import time
from collections import Counter, defaultdict
from pathlib import Path
from xml.etree import ElementTree

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))


def fresh_clone_run(jobs: int) -> tuple[str, Path]:
    """Clone HEAD, time `make venv` and `make test` there; return the table and the folder."""
    tmp = Path(tempfile.mkdtemp(prefix="bsd-fresh-"))
    clone, junit = tmp / "brainstem_dio", tmp / "junit.xml"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "VERILATOR_ROOT")}
    t0 = time.time()
    subprocess.run(["make", "-s", "venv"], cwd=clone, env=env, check=True)
    venv_s, t0 = time.time() - t0, time.time()
    res = subprocess.run(["make", "test", f"JOBS={jobs}", f"PYTEST_ARGS=--junitxml={junit}"], cwd=clone,
                         env=env, capture_output=True, text=True, check=False)
    test_s = time.time() - t0
    (tmp / "make-test.log").write_text(res.stdout + res.stderr)
    if res.returncode != 0:
        raise SystemExit(f"test_time: make test failed in the fresh clone; see {tmp}/make-test.log")
    per_file: dict[str, float] = defaultdict(float)
    cases = ElementTree.parse(junit).getroot().iter("testcase")
    n = 0
    for n, case in enumerate(cases, 1):
        per_file[case.get("classname", "?").replace(".", "/") + ".py"] += float(case.get("time", 0))
    builds = Counter(d.name.split("-", 1)[0] for d in (clone / "sim_build").glob("*/*-*") if d.is_dir())
    load = os.getloadavg()[0]
    how = f"`python sim/test_time.py --jobs {jobs}` (a fresh clone of HEAD)"
    out = [f"Measured {dt.date.today().isoformat()} by {how} on {os.cpu_count()} cores, load {load:.1f} at the end.", "",
           "| what | time |", "|---|---|",
           f"| fresh clone: `make venv` + `make test`, wall | {venv_s + test_s:.0f} s |",
           f"| venv (pip install of requirements.txt) | {venv_s:.0f} s |",
           f"| `make test` (lint, pytest with {jobs} workers, {n} tests) | {test_s:.0f} s |"]
    out += [f"| {sim}: build folders made | {k} |" for sim, k in sorted(builds.items())]
    out += ["", "Per test file (set-up + call + tear-down, summed over workers):", "",
            "| test file | time |", "|---|---|"]
    out += [f"| `{p}` | {s:.0f} s |" for p, s in sorted(per_file.items(), key=lambda kv: -kv[1])]
    return "\n".join(out), tmp


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=2, help="pytest-xdist workers (default 2)")
    args = ap.parse_args(argv)
    if args.jobs < 1:
        ap.error("--jobs must be at least 1")
    text, tmp = fresh_clone_run(args.jobs)
    print(f"fresh clone in {tmp}\n{text}")
    out = ROOT / "sim" / "build" / "test_time.md"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text + "\n", encoding="utf-8")
    print(f"written to {out.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
