# SPDX-License-Identifier: Apache-2.0
"""The standalone Verilator harnesses (sim/session.cpp, sim/virtual.cpp) from the tests: built
by make once per parameter set, and their output streams read line by line."""

from __future__ import annotations

import fcntl
import re
import subprocess
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TIMEOUT = 30.0  # wall seconds for anything to happen, however loaded the machine


def make_built(build: str, path: str, make_vars: list[str]) -> Path:
    """Run `make build VARS` once, whichever xdist worker gets here first (a lock per build
    target), and return the binary that `make path VARS` names."""
    lock_path = ROOT / "sim" / "build" / f".{build}.lock"
    lock_path.parent.mkdir(parents=True, exist_ok=True)
    with open(lock_path, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        subprocess.run(["make", "-s", build, *make_vars], cwd=ROOT, check=True)
    out = subprocess.run(["make", "-s", "--no-print-directory", path, *make_vars], cwd=ROOT,
                         check=True, capture_output=True, text=True).stdout.strip()
    return ROOT / out


class Lines:
    """The lines of one of a process's output streams, collected by a thread."""

    def __init__(self, stream) -> None:
        self.lines: list[str] = []
        self.cond = threading.Condition()
        self.closed = False
        threading.Thread(target=self._read, args=(stream,), daemon=True).start()

    def _read(self, stream) -> None:
        for raw in stream:
            with self.cond:
                self.lines.append(raw.decode(errors="replace").rstrip("\n"))
                self.cond.notify_all()
        with self.cond:
            self.closed = True
            self.cond.notify_all()

    def wait(self, pattern: str, start: int = 0, timeout: float = TIMEOUT) -> int:
        """Index of the first line from `start` on that matches the regex `pattern`."""
        rx = re.compile(pattern)
        deadline = time.monotonic() + timeout
        with self.cond:
            i = start
            while True:
                while i < len(self.lines):
                    if rx.search(self.lines[i]):
                        return i
                    i += 1
                left = deadline - time.monotonic()
                if left <= 0 or self.closed:
                    raise AssertionError(f"no line matching {pattern!r}; got:\n" + "\n".join(self.lines[start:]))
                self.cond.wait(left)

    def find(self, pattern: str, start: int = 0) -> list[str]:
        rx = re.compile(pattern)
        with self.cond:
            return [line for line in self.lines[start:] if rx.search(line)]

    def __len__(self) -> int:
        with self.cond:
            return len(self.lines)

    def text(self) -> str:
        with self.cond:
            return "\n".join(self.lines)
