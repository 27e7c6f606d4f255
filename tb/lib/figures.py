# SPDX-License-Identifier: Apache-2.0
"""Measured figures (timer error, run times) that tests print in pytest's summary.

A cocotb test runs inside the simulator's own process, so it leaves its figure in a file;
conftest.py shows the files written during the current pytest session.
"""

from __future__ import annotations

import re
from pathlib import Path

FIGURES = Path(__file__).resolve().parent.parent / "sim_build" / "figures"


def record(name: str, text: str) -> None:
    """Keep one figure line under a unique name (e.g. test, simulator and clock)."""
    FIGURES.mkdir(parents=True, exist_ok=True)
    safe = re.sub(r"[^A-Za-z0-9_.-]+", "_", name)
    (FIGURES / f"{safe}.txt").write_text(text.rstrip() + "\n")


def written_since(t: float) -> list[str]:
    if not FIGURES.is_dir():
        return []
    files = sorted(f for f in FIGURES.glob("*.txt") if f.stat().st_mtime >= t)
    return [f.read_text().rstrip() for f in files]
