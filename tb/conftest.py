# SPDX-License-Identifier: Apache-2.0
"""pytest set-up for the whole tree: the library folder on sys.path, and after the summary
the figures the tests measured (tb/lib/figures.py) and how many builds this run made."""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent / "lib"))

import figures  # noqa: E402
import runner  # noqa: E402

_START = time.time()


def pytest_terminal_summary(terminalreporter) -> None:
    lines = figures.written_since(_START)
    if lines:
        terminalreporter.section("measured figures")
        for line in lines:
            terminalreporter.write_line(line)
    builds = runner.builds_since(_START)
    if builds:
        terminalreporter.section("builds")
        for sim in sorted(builds):
            n, seconds = builds[sim]
            terminalreporter.write_line(f"{sim}: {n} builds, {seconds:.0f} s of build time")


def pytest_runtest_logreport(report) -> None:
    """Every test's set-up + call + tear-down time, by worker, for sim/test_time.py."""
    runner.record_timing("item", nodeid=report.nodeid, when=report.when, seconds=report.duration)


def pytest_sessionfinish(session) -> None:
    if not hasattr(session.config, "workerinput"):  # the controller, not an xdist worker
        workers = getattr(session.config.option, "numprocesses", 0) or 1
        runner.record_timing("session", seconds=time.time() - _START, workers=workers)
