# SPDX-License-Identifier: Apache-2.0
"""The FuseSoC core file (brainstem_dio.core) cannot go stale: its lint and sim targets run
through fusesoc (tb/fusesoc/check.py, also `make fusesoc-check`), here as one pytest case so
that it runs beside the rest of the regression."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def test_fusesoc_lint_and_sim_targets() -> None:
    run = subprocess.run([sys.executable, str(HERE / "check.py")], capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, f"tb/fusesoc/check.py failed:\n{run.stdout}\n{run.stderr}"
