# SPDX-License-Identifier: Apache-2.0
"""brainstem_dio.core through fusesoc (tb/fusesoc/check.py, also `make fusesoc-check`): its lint
targets (which fail when the .core lacks a file), the sim target and the synthesis targets' setup,
with no warning (the deprecated tool API warns), here as one pytest case beside the regression."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def test_fusesoc_lint_and_sim_targets() -> None:
    run = subprocess.run([sys.executable, str(HERE / "check.py")], capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, f"tb/fusesoc/check.py failed:\n{run.stdout}\n{run.stderr}"
