"""pytest hooks: show the figures the tests measured (tb/figures.py) after the summary."""

from __future__ import annotations

import time

import figures

_START = time.time()


def pytest_terminal_summary(terminalreporter) -> None:
    lines = figures.written_since(_START)
    if lines:
        terminalreporter.section("measured figures")
        for line in lines:
            terminalreporter.write_line(line)
