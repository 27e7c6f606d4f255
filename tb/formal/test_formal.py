# SPDX-License-Identifier: Apache-2.0
"""Every SymbiYosys task of formal/ (formal/run.py's JOBS), one pytest case per job and task:
make test runs the tasks marked for it (every block's proofs and one cover), make test-full
all of them, as `make formal` does. Each runs in its own temporary work folder, so
pytest-xdist workers never share one."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

_RUN = Path(__file__).resolve().parents[2] / "formal" / "run.py"
_spec = importlib.util.spec_from_file_location("formal_run", _RUN)
formal_run = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(formal_run)

# Every task; those not marked for make test in formal/run.py are deep (make test-full).
TASKS = [pytest.param(job, task, id=f"{job}-{task}", marks=[] if fast else [pytest.mark.deep])
         for job, task, fast in formal_run.JOBS]


@pytest.mark.parametrize("job,task", TASKS)
def test_formal(job: str, task: str, tmp_path: Path) -> None:
    if not formal_run.have_sby():
        pytest.skip("yowasp-sby is not installed (make test and make formal install "
                    "formal/requirements.txt)")
    result, depth, seconds, tail = formal_run.run_task(job, task, tmp_path / f"{job}_{task}")
    assert result == "PASS", f"{job} {task} (depth {depth}): {result} after {seconds:.1f} s\n{tail}"
