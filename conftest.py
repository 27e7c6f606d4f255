# SPDX-License-Identifier: Apache-2.0
"""pytest set-up for the whole tree: the library folder on sys.path, and after the summary
the figures the tests measured (tb/lib/figures.py)."""

from __future__ import annotations

import sys
import time
from pathlib import Path

# At the repository root, not in tb/: tb/ on sys.path would make tb/brainstem_dio/ (the top
# level's tests) shadow the host library's package brainstem_dio.
sys.path.insert(0, str(Path(__file__).resolve().parent / "tb" / "lib"))

import figures

_START = time.time()


def pytest_terminal_summary(terminalreporter) -> None:
    lines = figures.written_since(_START)
    if lines:
        terminalreporter.section("measured figures")
        for line in lines:
            terminalreporter.write_line(line)
