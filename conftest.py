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

import figures
import runner
import suite

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
    ordered by the durations this checkout's last run recorded, an xdist group (the cases
    that share one simulator run, tb/lib/suite.py, or a file that keeps to one worker) weighed
    as a whole and kept together in its collection order; with no record
    (a fresh clone), the top-level and serial-link files, which hold the long simulations,
    go first. Only the order changes, never the selection."""
    known = runner.item_durations()
    group_of = {id(item): _group(item) or item.nodeid for item in items}
    weight: dict[str, float] = {}
    for item in items:
        g = group_of[id(item)]
        weight[g] = weight.get(g, 0.0) + known.get(runner.plain_nodeid(item.nodeid), 0.0)
    first = {}
    for i, item in enumerate(items):
        first.setdefault(group_of[id(item)], i)

    def key(item) -> tuple[float, int]:
        g = group_of[id(item)]
        if known:
            return (-weight[g], first[g])
        path = item.nodeid.split("::", 1)[0]
        early = path.startswith(("tb/brainstem_dio", "tb/bsd_tick_gen/test_bsd_tick_gen_drift",
                                 "tb/virtual", "tb/host_virtual"))
        return (0.0 if early else 1.0, first[g])

    items.sort(key=key)  # stable: a group's cases keep their collection order
    if not known:
        # A fresh clone's first Verilator build also compiles Verilator's runtime into the
        # empty compiler cache: give the second worker the proofs (no C++) meanwhile, rather
        # than a second build compiling the same runtime at the same time.
        formal = [i for i in items if i.nodeid.startswith("tb/formal/")]
        rest = [i for i in items if not i.nodeid.startswith("tb/formal/")]
        g0 = group_of[id(rest[0])] if rest else None
        n0 = sum(1 for i in rest if group_of[id(i)] == g0)
        items[:] = rest[:n0] + formal + rest[n0:]


def pytest_collection_finish(session) -> None:
    """Tell tb/lib/suite.py which cases of each group this session runs, so that the first
    case of a group runs the group's tests in one simulator run."""
    suite.select([c for c in (_case(item) for item in session.items) if c is not None])


def _case(item):
    callspec = getattr(item, "callspec", None)
    case = callspec.params.get("case") if callspec is not None else None
    return case if isinstance(case, suite.Case) else None


def _group(item) -> str | None:
    """The item's xdist_group: a suite's cases that share a simulator run (tb/lib/suite.py
    marks them), or a file that wants one worker (pytestmark). Its items keep their order."""
    mark = item.get_closest_marker("xdist_group")
    return str(mark.kwargs.get("name", mark.args[0] if mark.args else "")) if mark else None
