# SPDX-License-Identifier: Apache-2.0
"""The busy scenario of `sim/session --bench` under cocotb, through the TB's drivers and
monitors, for the `cycles` test argument (run by sim/bench.py, not by pytest)."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import cocotb

from bsd_model import Params
from bsd_tb import TB
from runner import test_args

# The same command mix as Session::bench in sim/session.cpp.
COMMANDS = [
    [2, 26, 3, 0x19], [2, 29, 0x83], [2, 27, 0x80], [2, 26, 4, 0x01],
    [2, 29, 0x84], [2, 28, 2], [2, 26, 1, 0x01], [2, 29, 0x81],
]


@cocotb.test()
async def busy(dut):
    p = Params.from_env()
    cycles = int(test_args().get("cycles", 200_000))
    tb = TB(dut, p)
    await tb.start()
    done = False

    async def traffic() -> None:
        k = 0
        while not done:
            c = COMMANDS[k % len(COMMANDS)]
            k += 1
            await tb.source.send(bytes([c[0], len(c) - 1, *c[1:]]))

    async def toggle() -> None:
        while not done:
            await tb.cycles(1024)
            tb.set_pins(tb.pins ^ 0x18)

    t0 = time.perf_counter()
    start = tb.now_s()
    cocotb.start_soon(traffic())
    cocotb.start_soon(toggle())
    await tb.cycles(cycles)
    done = True
    wall = time.perf_counter() - t0
    ran = round((tb.now_s() - start) * p.clk_hz)
    if out := os.environ.get("BSD_BENCH_OUT"):
        Path(out).write_text(json.dumps({"cycles": ran, "seconds": wall, "packets": len(tb.packets)}))
    tb.log.info("%d cycles in %.3f s: %.0f cycles/s", ran, wall, ran / wall)
