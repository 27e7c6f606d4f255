# SPDX-License-Identifier: Apache-2.0
"""Serial-line helpers for the UART tests (tb/bsd_uart_rx/, tb/bsd_uart_tx/, tb/brainstem_dio_uart/).

- `LineMonitor`: a strict 8N1 receiver for a DUT's TX line. cocotbext-uart's UartSink does
  not check the stop bit, so this one does: it samples the start bit, the 8 data
  bits and the stop bit in their middles at a given baud rate, records every frame with its
  start time, and records an error for a start bit that is not low at its middle or a stop
  bit that is not high.
- `drive_frame` / `drive_low`: raw line drivers for malformed frames and glitches, which
  cocotbext-uart's UartSource cannot produce.
- `quiet_uart_logs`: cocotbext-uart logs every byte at INFO; keep test logs readable.

Times are simulation picoseconds (the testbenches run with a 1 ps precision).
"""

from __future__ import annotations

import logging

import cocotb
from cocotb.triggers import FallingEdge, Timer
from cocotb.utils import get_sim_time


def now_ps() -> int:
    return int(get_sim_time("ps"))


def bit_ps(baud: float) -> int:
    return round(1e12 / baud)


def quiet_uart_logs(*signals) -> None:
    for sig in signals:
        logging.getLogger(f"cocotb.{sig._path}").setLevel(logging.WARNING)


class LineMonitor:
    """Strict 8N1 receiver on `sig` at `baud`: frames [(t_start_ps, byte)], errors [str]."""

    def __init__(self, sig, baud: float) -> None:
        self.sig = sig
        self.bit = bit_ps(baud)
        self.frames: list[tuple[int, int]] = []
        self.errors: list[str] = []
        self._task = cocotb.start_soon(self._run())

    def _level(self) -> int:
        v = self.sig.value
        return int(v) if v.is_resolvable else -1

    async def _run(self) -> None:
        while True:
            await FallingEdge(self.sig)
            t0 = now_ps()
            await Timer(self.bit // 2, unit="ps")
            if self._level() != 0:
                self.errors.append(f"start bit at {t0} ps not low at its middle")
                continue
            byte = 0
            for k in range(8):
                await Timer(self.bit, unit="ps")
                lvl = self._level()
                if lvl < 0:
                    self.errors.append(f"X on the line in data bit {k} of the frame at {t0} ps")
                byte |= (lvl & 1) << k
            await Timer(self.bit, unit="ps")
            if self._level() != 1:
                self.errors.append(f"bad stop bit in the frame at {t0} ps (byte {byte:02X})")
                continue
            self.frames.append((t0, byte))

    @property
    def data(self) -> bytes:
        return bytes(b for _, b in self.frames)


async def drive_low(sig, low_ps: int) -> None:
    """A low pulse of `low_ps` on an idle-high line (a glitch or a break)."""
    sig.value = 0
    await Timer(low_ps, unit="ps")
    sig.value = 1


async def drive_frame(sig, byte: int, bit: int, stop: int = 1, idle_after: int = 0) -> None:
    """One 8N1 frame, LSB first, with the given stop-bit level; then `idle_after` ps high."""
    levels = [0] + [(byte >> k) & 1 for k in range(8)] + [stop]
    for lvl in levels:
        sig.value = lvl
        await Timer(bit, unit="ps")
    sig.value = 1
    if idle_after:
        await Timer(idle_after, unit="ps")
