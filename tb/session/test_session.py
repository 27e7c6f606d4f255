# SPDX-License-Identifier: Apache-2.0
"""The standalone session runner (sim/session.cpp): the demo script holds, and
every kind of bad script line stops the run with file:line and a clear message."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from harness import make_built

# One worker runs this file: its binary builds once there, and its module fixtures start once.
pytestmark = pytest.mark.xdist_group("session")

ROOT = Path(__file__).resolve().parents[2]
MAKE_VARS = ["CLK_HZ=48000000"]  # and the other GP 1.0 defaults


@pytest.fixture(scope="session")
def session_bin() -> Path:
    return make_built("sim-build", "sim-path", MAKE_VARS)


def play(session_bin: Path, script: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [str(session_bin), "--no-wave", str(script)],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )


def test_demo_expectations_hold(session_bin: Path) -> None:
    run = play(session_bin, ROOT / "sim" / "demo.txt")
    assert run.returncode == 0, run.stderr
    out = run.stdout
    # The demo's own `expect` lines are the functional check; the transcript
    # must also show what has no `expect`: raw inputs and RFLX strobes.
    assert out.count("* raw input 17") == 2, out  # fired, spent, re-armed, fired
    assert "* RFLX id 5 = 1" in out
    assert "* RFLX id 13 = 1000" in out
    assert "pin 4 timer: 500 ticks = 800.0 us" in out
    assert "pin 4 timer: timeout" in out
    assert "< 2:cmd index error" in out


BAD_LINES = [
    ("fly 3", "unknown keyword 'fly'"),
    ("2 26 x", "bad byte 'x'"),
    ("2 26 256", "bad byte '256'"),
    ("pin 9 high", "bad pin number '9'"),
    ("pin 1 sideways", "expected 'pin N high'"),
    ("pin 1 pulse 3 parsecs", "expected 'pin N high'"),
    ("pin 1 pulse 3parsecs", "bad time '3parsecs'"),
    ("wait", "expected 'wait TIME'"),
    ("wait 5", "expected 'wait TIME'"),
    ("expect 2 3 26 3", "expect: N is 3 but 2 data bytes follow"),
    ("expect 2 2 128 0x1G", "bad byte '0x1G'"),
]


@pytest.mark.parametrize("line,message", BAD_LINES)
def test_bad_line_is_reported(session_bin: Path, tmp_path: Path, line: str, message: str) -> None:
    script = tmp_path / "bad.txt"
    script.write_text(f"# a comment\nexpect 2 2 128 4\n{line}\n")
    run = play(session_bin, script)
    assert run.returncode == 1
    assert f"{script}:3: {message}" in run.stderr, run.stderr


def test_failed_expect_is_reported(session_bin: Path, tmp_path: Path) -> None:
    script = tmp_path / "expect.txt"
    script.write_text("expect 2 2 128 4\n2 26 3\nexpect 2 3 26 3 0\n")
    run = play(session_bin, script)
    assert run.returncode == 1
    assert f"{script}:3: expected 02:03,1A,03,00 but the core sent 02:03,1A,03,01" in run.stderr


def test_missing_reply_is_reported_not_hung(session_bin: Path, tmp_path: Path) -> None:
    script = tmp_path / "silent.txt"
    script.write_text("expect 2 2 128 4\n2 26 3 1\nexpect 2 2 128 4\n")
    run = play(session_bin, script)
    assert run.returncode == 1
    assert f"{script}:3: no packet from the core within 200 ms" in run.stderr


def test_missing_script_is_reported(session_bin: Path, tmp_path: Path) -> None:
    run = play(session_bin, tmp_path / "nothing.txt")
    assert run.returncode == 1
    assert "cannot open the script" in run.stderr
