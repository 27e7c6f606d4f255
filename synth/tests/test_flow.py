# SPDX-License-Identifier: Apache-2.0
"""synth/synth.py tells a design nextpnr could not place (too big, or stopped at the time limit:
`flow.Unplaced`, a result for the report) from a failure of the flow (`flow.FlowError`), with
nextpnr's exit and log stood in for as nextpnr-ice40 0.11 writes them; and its report's sums.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import synth as flow

# The utilization nextpnr-ice40 prints before it gives up on a design too big for the UP5K.
TOO_BIG = """Info: Device utilisation:
Info: 	         ICESTORM_LC:   19607/   5280   371%
Info: 	        ICESTORM_RAM:       1/     30     3%
ERROR: Unable to place cell 'u_dio.x', no BELs remaining to implement cell type 'ICESTORM_LC'
"""
# At the limit it packs the design, then its placer finds no legal placement.
AT_THE_LIMIT = """Info: Packing LUT-FFs..
Info:     2694 LCs used as LUT4 only
Info:      934 LCs used as LUT4 and DFF
Info: Packing non-LUT FFs..
Info:     1577 LCs used as DFF only
Info: Device utilisation:
Info: 	         ICESTORM_LC:    5249/   5280    99%
Info: Running main analytical placer, max placement attempts per cell = 3490082.
ERROR: Unable to find legal placement for all cells, design is probably at utilisation limit.
"""
FITS_BUT_FAILS = """Info: Device utilisation:
Info: 	         ICESTORM_LC:    1402/   5280    26%
ERROR: Failed to route net 'x'
"""


def _fake_nextpnr(monkeypatch, tmp_path: Path, log: str | None, late: bool = False) -> flow.Design:
    """A design whose nextpnr run fails (writing `log`) or runs past its time limit."""
    monkeypatch.setattr(flow, "tool", lambda name: name)

    def run(cmd, cwd, stdout=None, stderr=None, text=None, timeout=None, check=None):
        if late:
            raise subprocess.TimeoutExpired(cmd, timeout)
        (cwd / cmd[cmd.index("-l") + 1]).write_text(log)
        return subprocess.CompletedProcess(cmd, 1)

    monkeypatch.setattr(flow.subprocess, "run", run)
    monkeypatch.setattr(flow, "ROOT", tmp_path)
    return flow.DESIGN["uart64t"]


def test_a_design_too_big_is_unplaced_with_the_cells_it_needs(monkeypatch, tmp_path) -> None:
    d = _fake_nextpnr(monkeypatch, tmp_path, TOO_BIG)
    with pytest.raises(flow.Unplaced, match=r"does not fit: 19607 ICESTORM_LC of the 5280 available \(371 %\)"):
        flow._nextpnr(tmp_path, d, 1)


def test_a_design_at_the_limit_is_unplaced_with_the_cells_it_packed(monkeypatch, tmp_path) -> None:
    d = _fake_nextpnr(monkeypatch, tmp_path, AT_THE_LIMIT)
    with pytest.raises(flow.Unplaced, match=r"no legal placement: 5249 ICESTORM_LC of the 5280 available \(99 %\), "
                                                   r"1577 of them a flop without a LUT$"):
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


def test_nextpnr_places_each_design_for_its_own_target(monkeypatch, tmp_path) -> None:
    """The iCEBreaker top is placed and routed for its 60 MHz goal; every other design for the
    family's 4x board clock that it must close at."""
    monkeypatch.setattr(flow, "tool", lambda name: name)
    freq = {}

    def run(cmd, cwd, stdout=None, stderr=None, text=None, timeout=None, check=None):
        freq[cmd[0]] = cmd[cmd.index("--freq") + 1]
        raise subprocess.TimeoutExpired(cmd, timeout)

    monkeypatch.setattr(flow.subprocess, "run", run)
    got = {}
    for name in ("icebreaker", "icebreaker24", "uart64t", "core5", "ulx3s", "tangnano9k"):
        with pytest.raises(flow.Unplaced):
            flow._nextpnr(tmp_path, flow.DESIGN[name], 1)
        got[name] = freq.pop(flow.DESIGN[name].fam.nextpnr)
    assert got == {"icebreaker": "60", "icebreaker24": "48", "uart64t": "48", "core5": "48", "ulx3s": "100",
                   "tangnano9k": "108"}


def _result(name: str, lut4: int, ff: int, fmax: list[float] = (), lcs: int = 0, unplaced: str | None = None) -> dict:
    d = flow.DESIGN[name]
    return {"design": name, "pins": d.pins, "timers": d.timers, "cells": {"lut4": lut4, "ff": ff, "carry": 0, "ram": 2,
                                                                          "spram": int(d.pins > 16)},
            "seeds": [{"seed": i + 1, "fmax": f, "lcs": lcs, "lcs_available": 5280} for i, f in enumerate(fmax)],
            "unplaced": unplaced, "date": "2026-12-02 13:07 UTC"}


def test_the_report_computes_slopes_targets_and_the_fit() -> None:
    r = {n: _result(n, lut, ff) for n, lut, ff in (("core5", 600, 500), ("core16", 820, 610), ("core64", 1780, 1100),
                                                    ("core16t", 1180, 800), ("core64t", 3280, 2300))}
    r["icebreaker"] = _result("icebreaker", 900, 700, [61.0, 58.0, 65.0], 1500)
    r["uart64t"] = _result("uart64t", 4700, 2500, unplaced="does not fit: 6280 ICESTORM_LC of the 5280 available (119 %)")
    text = flow.report(r)
    assert "| core5 → core16 | 20.0 | 10.0 |" in text          # (820 - 600) / (16 - 5) pins
    assert "| core16 → core16t | 30.0 | 15.8 |" in text         # (1180 - 820) / (16 - 4) timers
    assert "| LUT4 per step core5 → core16 | ≤ 14 | 20.0 | **missed** |" in text
    assert "| LUT4 per step core64 → core64t | ≤ 30 | 25.0 | met |" in text
    assert "| core5 LUT4 | ≤ 700 | 600 | met |" in text
    assert "| icebreaker median Fmax (MHz) | ≥ 60 | 61.0 | met |" in text
    assert "| icebreaker worst Fmax (MHz) | ≥ 55 | 58.0 | met |" in text
    assert "| icebreaker | ice40 | 900 | 700 | 0 | 2 | 0 | 1500 | 61.0 / 58.0 / 65.0 | 61.0 / 58.0 |" in text
    assert "| core64t | ice40 | 3280 | 2300 | 0 | 2 | 1 |" in text      # its SPRAM
    assert "| uart64t placed, % of logic cells | ≤ 75 | does not fit: 6280 ICESTORM_LC" in text
    assert text.count("**missed**") == 3 and "| LUT4 per step core16 → core64 | ≤ 14 | 20.0 | **missed** |" in text
    assert "| core64 | ice40 |" in text and "| ulx3s | ecp5 | — |" in text


def test_the_rtl_list_is_the_core_files() -> None:
    files = flow.rtl_files()
    assert "rtl/brainstem_dio.v" in files and "rtl/brainstem_dio_uart.v" in files and "rtl/bsd_protocol.vh" in files
    assert all((flow.ROOT / f).is_file() for f in files)
