# SPDX-License-Identifier: Apache-2.0
"""The SymbiYosys tasks of formal/, one case each, through make (formal/<job>_<task>/PASS, so a
proof already passed on the same files is not run again): make test runs the Makefile's
FORMAL_QUICK (make formal-quick), make test-full every task and every mutant of
formal/mutants.py, each caught with its expected result."""

from __future__ import annotations

import importlib.util
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
STAMP = ROOT / ".venv" / ".formal-installed"
MAKE = ["make", "-s", "--no-print-directory", "-C", str(ROOT), "-o", ".venv/.formal-installed"]

_lists = subprocess.run([*MAKE, "formal-list"], capture_output=True, text=True, check=True).stdout
LISTS = {k: v.split() for k, v in (line.split(":", 1) for line in _lists.splitlines())}
_spec = importlib.util.spec_from_file_location("mutants", ROOT / "formal" / "mutants.py")
mutants = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mutants)


def _need_sby() -> None:
    if not STAMP.exists():
        pytest.skip("formal/requirements.txt is not installed (make test and make formal install it)")


@pytest.mark.parametrize("name", [pytest.param(n, marks=[] if n in LISTS["quick"] else [pytest.mark.deep])
                                  for n in LISTS["all"]])
def test_formal(name: str) -> None:
    _need_sby()
    run = subprocess.run([*MAKE, f"formal/{name}/PASS"], capture_output=True, text=True)
    assert run.returncode == 0, f"{name}:\n{run.stdout}{run.stderr}"


@pytest.mark.deep
@pytest.mark.parametrize("mutant", mutants.MUTANTS, ids=[f"{m[0]}-{m[1]}-{i}" for i, m in enumerate(mutants.MUTANTS)])
def test_mutant_caught(mutant: tuple[str, ...]) -> None:
    _need_sby()
    job, task, fname, what, old, new, *exp = mutant
    result, failed = mutants.run(job, task, fname, old, new)
    assert result == (exp[0] if exp else "FAIL"), f"{job} {task}, {what}: {result} {failed}"
