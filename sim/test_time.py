#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Where `make test`'s time goes on a fresh clone of HEAD (what a new user and CI pay): `make venv`
and `make test` timed, the time per test file from pytest's JUnit XML, the build folders made.
The table is printed and written to sim/build/test_time.md.

    .venv/bin/python sim/test_time.py [--jobs 2]
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


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--jobs", type=int, default=2, metavar="N", help="pytest-xdist workers (default 2)")
    if (jobs := ap.parse_args(argv).jobs) < 1:
        ap.error("--jobs must be at least 1")
    tmp = Path(tempfile.mkdtemp(prefix="bsd-fresh-"))
    clone, junit = tmp / "brainstem_dio", tmp / "junit.xml"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "VERILATOR_ROOT")}
    t0 = time.time()
    subprocess.run(["make", "-s", "venv"], cwd=clone, env=env, check=True)
    t1 = time.time()
    with open(tmp / "make-test.log", "w") as log:
        if subprocess.run(["make", "test", f"JOBS={jobs}", f"PYTEST_ARGS=--junitxml={junit}"], cwd=clone, env=env,
                          stdout=log, stderr=subprocess.STDOUT, check=False).returncode:
            raise SystemExit(f"test_time: make test failed in the fresh clone; see {log.name}")
    venv_s, test_s = t1 - t0, time.time() - t1
    per_file: dict[str, float] = defaultdict(float)
    cases = list(ElementTree.parse(junit).getroot().iter("testcase"))
    for case in cases:
        per_file[case.get("classname", "?").replace(".", "/") + ".py"] += float(case.get("time", 0))
    builds = Counter(d.name.split("-", 1)[0] for d in (clone / "sim_build").glob("*/*-*") if d.is_dir())
    out = [(f"Measured {dt.date.today().isoformat()} by `python sim/test_time.py --jobs {jobs}` (a fresh clone of "
            f"HEAD) on {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f} at the end."), "", "| what | time |", "|---|---|",
           f"| fresh clone: `make venv` + `make test`, wall | {venv_s + test_s:.0f} s |",
           f"| venv (pip install of requirements.txt) | {venv_s:.0f} s |",
           f"| `make test` (lint, pytest with {jobs} workers, {len(cases)} tests) | {test_s:.0f} s |",
           *(f"| {sim}: build folders made | {k} |" for sim, k in sorted(builds.items())), "",
           "Per test file (set-up + call + tear-down, summed over workers):", "", "| test file | time |", "|---|---|",
           *(f"| `{p}` | {s:.0f} s |" for p, s in sorted(per_file.items(), key=lambda kv: -kv[1]))]
    text = "\n".join(out)
    print(f"fresh clone in {tmp}\n{text}")
    (ROOT / "sim" / "build").mkdir(parents=True, exist_ok=True)
    (ROOT / "sim" / "build" / "test_time.md").write_text(text + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
