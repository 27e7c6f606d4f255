# SPDX-License-Identifier: Apache-2.0
"""The fast SymbiYosys jobs of formal/ (formal/run.py's JOBS marked for make test), one
pytest case per job and task. Each runs in its own temporary work folder, so pytest-xdist
workers never share one. `make formal` runs every job, the slow ones too."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

_RUN = Path(__file__).resolve().parents[2] / "formal" / "run.py"
_spec = importlib.util.spec_from_file_location("formal_run", _RUN)
formal_run = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(formal_run)

FAST = [(job, task) for job, task, fast in formal_run.JOBS if fast]


@pytest.mark.parametrize("job,task", FAST, ids=[f"{j}-{t}" for j, t in FAST])
def test_formal(job: str, task: str, tmp_path: Path) -> None:
    if not formal_run.have_sby():
        pytest.skip("yowasp-sby is not installed (make test and make formal install "
                    "formal/requirements.txt)")
    result, depth, seconds, tail = formal_run.run_task(job, task, tmp_path / f"{job}_{task}")
    assert result == "PASS", f"{job} {task} (depth {depth}): {result} after {seconds:.1f} s\n{tail}"
