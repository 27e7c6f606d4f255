# SPDX-License-Identifier: Apache-2.0
"""bsd_fifo's pointer order: its tap table, read from rtl/bsd_fifo.v, checked for every pointer
width the FIFO allows (a plain pytest: no simulation, as a 16-bit pointer's 65 536 steps would
take a cocotb build minutes)."""

from __future__ import annotations

import re
from pathlib import Path


def lfsr_order_length(width: int, taps: int) -> int:
    """Steps of bsd_fifo's pointer (rtl/bsd_fifo.v, step()) from address 0 back to 0: the new
    low bit is the XOR of the tapped bits, flipped when the bits below the top are all 0."""
    mask, low, p, n = (1 << width) - 1, ((1 << width) - 1) >> 1, 0, 0
    while True:
        new = (bin(p & taps).count("1") & 1) ^ ((p & low) == 0)
        p, n = ((p << 1) | new) & mask, n + 1
        if p == 0 or n > mask + 1:
            return n


def test_pointer_order_visits_every_address() -> None:
    """Every pointer width the FIFO allows (1-16 bits: DEPTH 2 to 65536) steps through all its
    DEPTH addresses before it repeats, with the taps as rtl/bsd_fifo.v's table gives them. The
    cocotb builds reach widths 1, 4 and 9 (and the top's queues 3, 4, 7, 8); this covers the rest,
    where a wrong tap would make a queue fill early and overwrite words."""
    text = (Path(__file__).resolve().parents[2] / "rtl" / "bsd_fifo.v").read_text()
    table = re.search(r"function \[15:0\] taps.*?endfunction", text, re.S).group(0)
    taps = {int(w): int(t, 16) for w, t in re.findall(r"^\s*(\d+):\s*taps = 16'h([0-9A-Fa-f]+);", table, re.M)}
    default = re.search(r"default:\s*taps = 16'h([0-9A-Fa-f]+);", table)
    for w in range(1, 17):
        taps.setdefault(w, int(default.group(1), 16))
    assert sorted(taps) == list(range(1, 17))
    steps = {w: lfsr_order_length(w, t) for w, t in taps.items()}
    short = {w: n for w, n in steps.items() if n != 1 << w}
    assert not short, f"pointer orders shorter than DEPTH (width: steps back to 0): {short}"
