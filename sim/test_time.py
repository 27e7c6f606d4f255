#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Where `make test`'s time goes on a fresh clone of HEAD (what a new user and CI pay): `make venv`
and `make test` timed, with pytest's own count of the tests and its slowest durations (make test
runs it with --durations=15). The table is printed and written to sim/build/test_time.md.

    .venv/bin/python sim/test_time.py [--jobs 2]
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--jobs", type=int, default=2, metavar="N", help="pytest-xdist workers (default 2)")
    if (jobs := ap.parse_args(argv).jobs) < 1:
        ap.error("--jobs must be at least 1")
    tmp = Path(tempfile.mkdtemp(prefix="bsd-fresh-"))
    clone = tmp / "brainstem_dio"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "VERILATOR_ROOT")}
    t0 = time.time()
    subprocess.run(["make", "-s", "venv"], cwd=clone, env=env, check=True)
    t1 = time.time()
    test = subprocess.run(["make", "test", f"JOBS={jobs}"], cwd=clone, env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, check=False)
    (tmp / "make-test.log").write_text(test.stdout, encoding="utf-8")
    if test.returncode:
        raise SystemExit(f"test_time: make test failed in the fresh clone; see {tmp / 'make-test.log'}")
    venv_s, test_s = t1 - t0, time.time() - t1
    summary = re.findall(r"^=+ (\d+ passed.*) in [\d.]+s", test.stdout, re.MULTILINE)[-1]
    slowest = re.search(r"^=+ (slowest \d+ durations) =+\n(.*?)\n*(?=^=)", test.stdout, re.MULTILINE | re.DOTALL)
    text = "\n".join([
        (f"Measured {dt.date.today().isoformat()} by `python sim/test_time.py --jobs {jobs}` (a fresh clone of "
         f"HEAD) on {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f} at the end."), "", "| what | time |", "|---|---|",
        f"| fresh clone: `make venv` + `make test`, wall | {venv_s + test_s:.0f} s |",
        f"| venv (pip install of requirements.txt) | {venv_s:.0f} s |",
        f"| `make test` (lint, pytest with {jobs} workers: {summary}) | {test_s:.0f} s |", "",
        f"pytest's {slowest[1]}:", "", "```", slowest[2], "```"])
    print(f"fresh clone in {tmp}\n{text}")
    (ROOT / "sim" / "build").mkdir(parents=True, exist_ok=True)
    (ROOT / "sim" / "build" / "test_time.md").write_text(text + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
