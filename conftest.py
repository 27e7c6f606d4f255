# SPDX-License-Identifier: Apache-2.0
"""pytest set-up for the whole tree: the library folder on sys.path, and after the summary
the figures the tests measured (tb/lib/figures.py) and how many builds this run made."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

# At the repository root, not in tb/: tb/ on sys.path would make tb/brainstem_dio/ (the top
# level's tests) shadow the host library's package brainstem_dio.
sys.path.insert(0, str(Path(__file__).resolve().parent / "tb" / "lib"))

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
    """Every test's set-up + call + tear-down time, by worker, for sim/test_time.py (under
    pytest-xdist the controller sees each report again: only the worker records it)."""
    if os.environ.get("PYTEST_XDIST_WORKER") or not _under_xdist:
        runner.record_timing("item", nodeid=report.nodeid, when=report.when, seconds=report.duration)


_under_xdist = False


def pytest_configure(config) -> None:
    global _under_xdist
    _under_xdist = bool(getattr(config.option, "numprocesses", None))


def pytest_sessionfinish(session) -> None:
    if not hasattr(session.config, "workerinput"):  # the controller, not an xdist worker
        workers = getattr(session.config.option, "numprocesses", 0) or 1
        runner.record_timing("session", seconds=time.time() - _START, workers=workers)


def pytest_collection_modifyitems(config, items) -> None:
    """Longest first, so that pytest-xdist does not end the run waiting on one long test:
    ordered by the durations this checkout's last run recorded; with none (a fresh clone),
    the top-level and serial-link files, which hold the long simulations, go first. Only
    the order changes, never the selection."""
    known = runner.item_durations()

    def weight(item) -> tuple[float, int]:
        if known:
            return (-known.get(item.nodeid, 0.0), 0)
        path = item.nodeid.split("::", 1)[0]
        return (0.0, 0 if path.startswith(("tb/brainstem_dio", "tb/bsd_tick_gen/test_bsd_tick_gen_drift", "tb/virtual", "tb/host_virtual")) else 1)

    items.sort(key=weight)  # stable: ties keep their collection order
