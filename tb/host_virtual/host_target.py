# SPDX-License-Identifier: Apache-2.0
"""What tb/host_virtual talks to (conftest.py picks it): the virtual module (`make virtual`'s
binary, started and stopped here) or a board on a serial port."""

from __future__ import annotations

import subprocess
from pathlib import Path
from typing import Optional

import pytest

from harness import TIMEOUT, Lines, make_built
from host_import import import_host_library  # noqa: F401  (re-exported for the tests)

ROOT = Path(__file__).resolve().parents[2]


def virtual_build(make_vars: list[str]) -> Path:
    return make_built("virtual-build", "virtual-path", make_vars)

# The build of tb/virtual/test_virtual.py (one build for both): the core's lowest clock and a
# fast line, so a loaded machine keeps real time; the 256 ms heartbeat.
MAKE_VARS = ["CLK_HZ=2000000", "BAUD=115200", "HB_RATE=10", "VIRTUAL_PGO=0"]


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


