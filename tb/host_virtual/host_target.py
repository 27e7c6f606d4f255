# SPDX-License-Identifier: Apache-2.0
"""What tb/host_virtual talks to (conftest.py picks it): the virtual module (`make virtual`'s
binary, started and stopped here) or a board on a serial port."""

from __future__ import annotations

import fcntl
import importlib
import re
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Optional

import pytest

ROOT = Path(__file__).resolve().parents[2]
# The build of tb/virtual/test_virtual.py (one build for both): the core's lowest clock and a
# fast line, so a loaded machine keeps real time; the 256 ms heartbeat.
MAKE_VARS = ["CLK_HZ=2000000", "BAUD=115200", "HB_RATE=10"]
TIMEOUT = 30.0  # wall seconds for anything to happen, however loaded the machine


def virtual_build(make_vars: list[str]) -> Path:
    # One build, whichever xdist worker gets here first (the lock of tb/virtual and tb/session).
    lock_path = ROOT / "sim" / "build" / ".lock"
    lock_path.parent.mkdir(parents=True, exist_ok=True)
    with open(lock_path, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        subprocess.run(["make", "-s", "virtual-build", *make_vars], cwd=ROOT, check=True)
    path = subprocess.run(["make", "-s", "--no-print-directory", "virtual-path", *make_vars], cwd=ROOT,
                          check=True, capture_output=True, text=True).stdout.strip()
    return ROOT / path


class Lines:
    """The lines of one of the process's output streams, collected by a thread."""

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


class Virtual:
    """A running virtual module: its stdin, its transcript (stdout), its pty."""

    def __init__(self, binary: Path, link: Path) -> None:
        self.proc = subprocess.Popen([str(binary), "--link", str(link)], cwd=ROOT, stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        self.out = Lines(self.proc.stdout)
        self.err = Lines(self.proc.stderr)
        self.port = self.out.lines[self.out.wait(r"^port: ")].split(": ", 1)[1]

    def send(self, *lines: str) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.write("".join(f"{line}\n" for line in lines).encode())
        self.proc.stdin.flush()

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.send("quit")
            try:
                self.proc.wait(TIMEOUT)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()


class Target:
    """What the tests talk to: a port, its baud rate, and the virtual module behind it (None on
    a board)."""

    def __init__(self, port: str, baud: int, virtual: Optional[Virtual]) -> None:
        self.port = port
        self.baud = baud
        self.virtual = virtual

    def need_virtual(self, why: str) -> Virtual:
        if self.virtual is None:
            pytest.skip(f"needs the virtual module's standard input or transcript ({why}); not on a board (--port)")
        return self.virtual


def import_host_library():
    """The host library `brainstem_dio` (host/, installed editable). tb/ is on sys.path (its
    conftest's folder), and tb/brainstem_dio/ (the top's tests) would be taken for a namespace
    package of that name: import it with tb/ out of the way."""
    tb = (ROOT / "tb").resolve()
    mod = sys.modules.get("brainstem_dio")
    if mod is not None and getattr(mod, "__file__", None) is None:
        del sys.modules["brainstem_dio"]
    saved = sys.path[:]
    sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != tb]
    try:
        return importlib.import_module("brainstem_dio")
    finally:
        sys.path[:] = saved
