# SPDX-License-Identifier: Apache-2.0
"""synth/synth.py tells a design nextpnr could not place (too big for the device, or stopped at
the time limit) from a failure of the flow: the first is a result for the report
(`flow.Unplaced`, the logic cells it needs), the second stops the run (`flow.FlowError`). The
tools are not run: nextpnr's exit and log are stood in for, as nextpnr-ice40 0.11 writes them.

    .venv/bin/python -m pytest synth/tests/test_flow.py
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import synth as flow  # noqa: E402

# The utilization nextpnr-ice40 prints before it gives up on a design too big for the UP5K.
TOO_BIG = """Info: Device utilisation:
Info: 	         ICESTORM_LC:   19607/   5280   371%
Info: 	        ICESTORM_RAM:       1/     30     3%
ERROR: Unable to place cell 'u_dio.x', no BELs remaining to implement cell type 'ICESTORM_LC'
"""
FITS_BUT_FAILS = """Info: Device utilisation:
Info: 	         ICESTORM_LC:    1402/   5280    26%
ERROR: Failed to route net 'x'
"""


def _fake_nextpnr(monkeypatch, tmp_path: Path, log: str | None, late: bool = False) -> flow.Design:
    """A design whose nextpnr run fails (writing `log`) or runs past its time limit."""
    monkeypatch.setattr(flow, "tool", lambda name: name)

    def run(cmd, cwd, stdout=None, stderr=None, text=None, timeout=None):
        if late:
            raise subprocess.TimeoutExpired(cmd, timeout)
        (cwd / cmd[cmd.index("-l") + 1]).write_text(log)
        return subprocess.CompletedProcess(cmd, 1)

    monkeypatch.setattr(flow.subprocess, "run", run)
    monkeypatch.setattr(flow, "ROOT", tmp_path)
    return flow.design("uart64t")


def test_a_design_too_big_is_unplaced_with_the_cells_it_needs(monkeypatch, tmp_path) -> None:
    d = _fake_nextpnr(monkeypatch, tmp_path, TOO_BIG)
    with pytest.raises(flow.Unplaced, match=r"does not fit: 19607 ICESTORM_LC of the 5280 available \(371 %\)"):
        flow._nextpnr(tmp_path, d, 1)


def test_any_other_nextpnr_failure_stops_the_flow(monkeypatch, tmp_path) -> None:
    d = _fake_nextpnr(monkeypatch, tmp_path, FITS_BUT_FAILS)
    with pytest.raises(flow.FlowError) as e:
        flow._nextpnr(tmp_path, d, 1)
    assert not isinstance(e.value, flow.Unplaced), e.value


def test_a_seed_past_the_time_limit_is_unplaced(monkeypatch, tmp_path) -> None:
    d = _fake_nextpnr(monkeypatch, tmp_path, None, late=True)
    with pytest.raises(flow.Unplaced, match=rf"seed 1\): stopped after {d.timeout} s"):
        flow._nextpnr(tmp_path, d, 1)
