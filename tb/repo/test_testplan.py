# SPDX-License-Identifier: Apache-2.0
"""docs/testplan.md cannot go stale: the repository's table passes `tools/testplan.py`, and the
check catches each kind of mistake made in a copy of the table (a missing test, a section
without a row, an unknown proof or bin, a cocotb test in no row, an error path without a test).
No simulator: the tests are read with `ast`."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))

import testplan

PLAN = (ROOT / "docs" / "testplan.md").read_text(encoding="utf-8")


def row(rid: str) -> str:
    return next(ln for ln in PLAN.splitlines() if ln.startswith(f"| **{rid}**"))


def test_the_repository_plan_passes() -> None:
    proc = subprocess.run([sys.executable, str(ROOT / "tools" / "testplan.py")], check=False, capture_output=True, text=True)
    assert proc.returncode == 0 and "complete" in proc.stdout, proc.stdout + proc.stderr


def test_parse_reads_tests_proofs_and_bins() -> None:
    rows = {r[0]: r[1:] for r in testplan.parse(PLAN)}
    tests, proofs, bins = rows["PROTOCOL §2 framing"]
    assert "tb/bsd_parser/test_bsd_parser.py::test_own_packets" in tests
    assert "host/tests/test_host_framing.py" in tests and proofs == ["bsd_parser"] and bins == ["command:cmd=none"]


def test_the_documents_parts() -> None:
    parts = testplan.anchors(ROOT)
    assert parts["PROTOCOL §4.1"] and not parts["PROTOCOL §4"]   # §4 has no text of its own
    assert parts["DESIGN decision 1"] and parts["DESIGN Latencies"]
    assert not parts["FPGA Bit timing"]


@pytest.mark.parametrize("old, new, error", [
    ("`test_rearm_meets_edge`", "`test_rearm_meets_edgy`", r"unknown test .*test_rearm_meets_edgy"),
    ("`tb/bsd_parser/test_bsd_parser.py`", "`tb/bsd_parser/test_nothing.py`", r"no such test file"),
    ("`host/tests/test_host_framing.py`", "`tb/bsd_parser`", r"a folder with cocotb tests"),
    ("**PROTOCOL §2 framing**", "**PROTOCOL §42 framing**", r"names no section"),
    ("`bsd_parser`", "`bsd_parserx`", r"unknown proof 'bsd_parserx'"),
    ("`command:cmd=none`", "`command:cmd=nothing`", r"unknown or unreachable bin"),
])
def test_a_wrong_name_is_caught(old: str, new: str, error: str) -> None:
    line = row("PROTOCOL §2 framing") if old != "`test_rearm_meets_edge`" else row("DESIGN decision 5")
    assert old in line
    errors = testplan.check(PLAN.replace(line, line.replace(old, new, 1)))
    assert any(re.search(error, e) for e in errors), errors


def test_a_section_without_a_row_is_caught() -> None:
    errors = testplan.check(PLAN.replace(row("DESIGN Latencies") + "\n", ""))
    assert any("DESIGN Latencies has no row" in e for e in errors), errors


def test_a_cocotb_test_file_in_no_row_is_caught() -> None:
    text = re.sub(r"`tb/bsd_sync/test_bsd_sync.py`: [^|]*?(<br>|(?= \|))", "", PLAN)
    assert "tb/bsd_sync/test_bsd_sync.py" not in text
    errors = testplan.check(text)
    assert "tb/bsd_sync/test_bsd_sync.py: this cocotb test file is in no row of docs/testplan.md" in errors, errors


def test_a_row_without_test_or_proof_is_caught() -> None:
    line = row("PROTOCOL §3 cmdDIG_RST")
    cells = line.split(" | ")
    errors = testplan.check(PLAN.replace(line, " | ".join([*cells[:2], "—", "—", cells[4]])))
    assert any("'PROTOCOL §3 cmdDIG_RST': no test and no proof" in e for e in errors), errors


def test_an_error_path_without_a_test_is_caught(tmp_path: Path) -> None:
    # Every file the table names that uses tmrConflict is dropped from it.
    users = {p for p in re.findall(r"`((?:tb|host)/[^`]+\.py)`", PLAN)
             if re.search(r"tmrConflict|MSG_TMR_CONFLICT", (ROOT / p).read_text(encoding="utf-8"))}
    assert users
    text = "\n".join(ln for ln in PLAN.splitlines() if not any(f"`{u}`" in ln for u in users))
    errors = testplan.check(text)
    assert any("message tmrConflict (MSG_TMR_CONFLICT) is used by no test file" in e for e in errors), errors


def test_bad_arguments_exit_2() -> None:
    proc = subprocess.run([sys.executable, str(ROOT / "tools" / "testplan.py"), "--bogus"], check=False, capture_output=True, text=True)
    assert proc.returncode == 2 and "usage" in proc.stderr
