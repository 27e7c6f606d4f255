# SPDX-License-Identifier: Apache-2.0
"""The board tops' shared cocotb test: one power-up, a few packets over the board's own UART
pins at the board's real clock, every reply checked against the reference model, the header
pads and the LEDs checked too. tb/<board top>/test_<board top>.py describes its board (a
`Board`) and registers the test; the vendor pad primitives are simulated by the small models
in tb/lib/pads/ (`pad_model`), which keep the input path independent of the simulator's
tristate resolution.

The sequence (about 30 frames: ~31 ms of simulated time at 9600 baud, 2.6 ms at 115 200):
1. power-up: the board top's own reset (no `rst` port), then the core's power-up message;
2. DIG_IO read of pin 3: the pull-up reads 1 (nothing drives the header);
3. DIG_CFG pin 0 to output, DIG_IO write pin 0 = 0, then = 1: the pad follows;
4. LEDs: activity lit after the traffic (where the board top has one), link_up dark (no heartbeat answered yet).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, Timer
from cocotbext.uart import UartSink, UartSource

from bsd_model import CMD_DIG_CFG, CMD_DIG_IO, Model, Params, packet
from runner import ROOT, hdl_params, rtl_sources
from uart_line import LineMonitor, now_ps, quiet_uart_logs

SYNTH = ROOT / "synth"
PADS = Path(__file__).resolve().parent / "pads"


@dataclass(frozen=True)
class Board:
    top: str            # the board top's module, synth/<top>.v
    clk_hz: int         # the board's oscillator: the top's CLK_HZ default
    clk: str            # port names
    rx: str             # host -> FPGA
    tx: str             # FPGA -> host
    btn: str            # active-low reset button
    pads: str           # the header bus, digital pin p on bit p
    pad_model: str      # tb/lib/pads/<pad_model>.v
    led_link: tuple[str, int]   # (port, bit) of the link_up LED
    led_act: tuple[str, int] | None   # (port, bit) of the activity LED (the iCEBreaker has none)
    led_active_low: bool
    extra_sources: tuple[str, ...] = ("board_status.v",)

    def sources(self) -> list[Path]:
        return [*rtl_sources(), *(SYNTH / s for s in self.extra_sources), SYNTH / f"{self.top}.v",
                PADS / f"{self.pad_model}.v"]


def builds(board: Board) -> dict[str, dict[str, object]]:
    """The board top at its board's clock (CLK_HZ = its default), 5 pins: `b9600` is exactly
    the bitstream's build (9600 baud, the default), for Verilator; `b115200` the same at
    115 200 baud, 12x fewer clocks per byte, for Icarus (a 9600-baud session is ~800 k clocks
    at 25 MHz: minutes on Icarus). The parameters are given explicitly so the test knows them."""
    return {"b9600": {"CLK_HZ": board.clk_hz, "BAUD": 9600, "NUM_PINS": 5},
            "b115200": {"CLK_HZ": board.clk_hz, "BAUD": 115_200, "NUM_PINS": 5}}


def one_build_per_sim(sim: str, build: str) -> bool:
    """Verilator runs the bitstream's build (9600 baud), Icarus the 115 200-baud one: one
    build of each top per simulator keeps the regression's build time down."""
    return (sim, build) in (("verilator", "b9600"), ("icarus", "b115200"))


def _bit(dut, port_bit: tuple[str, int]) -> int:
    port, bit = port_bit
    v = getattr(dut, port).value
    return int(str(v)[::-1][bit] == "1")


def _led(dut, board: Board, which: tuple[str, int]) -> bool:
    return bool(_bit(dut, which) ^ board.led_active_low)


class BoardLink:
    """A board top's serial port as the host sees it: the clock started, the reset button up,
    cocotbext-uart on RX/TX, a strict line monitor, and the model the replies are checked
    against."""

    def __init__(self, dut, board: Board, p: Params, baud: int, pins: int) -> None:
        period_ps = round(1e12 / p.clk_hz)
        self.frame_ps = 10 * ((p.clk_hz + baud // 2) // baud) * period_ps
        rx, tx = getattr(dut, board.rx), getattr(dut, board.tx)
        getattr(dut, board.btn).value = 1
        self.src, self.sink, self.mon = UartSource(rx, baud=baud), UartSink(tx, baud=baud), LineMonitor(tx, baud)
        quiet_uart_logs(rx, tx)
        cocotb.start_soon(Clock(getattr(dut, board.clk), period_ps, unit="ps", impl="gpi",
                                period_high=period_ps // 2).start())
        self.model = Model(p, pins)
        dut._log.info("%s at %.3f MHz (clock period %d ps), %d baud", board.top, p.clk_hz / 1e6, period_ps, baud)

    async def expect(self, exp: list[bytes], what: str, within_ps: int = 0) -> None:
        """Exactly these packets from the board, then 3 frame times of silence."""
        want = b"".join(exp)
        got = bytearray()
        deadline = now_ps() + within_ps + (len(want) + 6) * self.frame_ps
        while len(got) < len(want) and now_ps() < deadline:
            await Timer(self.frame_ps, unit="ps")
            got += self.sink.read_nowait(self.sink.count())
        await Timer(3 * self.frame_ps, unit="ps")     # nothing more may follow
        got += self.sink.read_nowait(self.sink.count())
        assert bytes(got) == want, f"after {what}: expected {want.hex(' ')}, got {bytes(got).hex(' ')}"
        assert not self.mon.errors, self.mon.errors[:3]

    async def command(self, pkt: bytes) -> None:
        exp = self.model.feed(pkt)
        self.src.write_nowait(pkt)
        await self.src.wait()
        await self.expect(exp.packets, pkt.hex(" "))


async def session(dut, board: Board) -> None:
    hdl = hdl_params()
    clk_hz, baud, n = int(hdl["CLK_HZ"]), int(hdl["BAUD"]), int(hdl["NUM_PINS"])
    assert clk_hz == board.clk_hz, f"CLK_HZ {clk_hz} is not {board.top}'s board clock {board.clk_hz}"
    # The wrapper's defaults apart from the board's clock (HB_RATE 10: a heartbeat per 256 ms).
    p = Params(clk_hz=clk_hz, num_pins=n, hb_rate=10)
    pull_ups = (1 << n) - 1
    link = BoardLink(dut, board, p, baud, pull_ups)
    model, expect, command = link.model, link.expect, link.command

    # 1. power-up: no rst port; the top's reset releases the core after 16 clocks.
    await ClockCycles(getattr(dut, board.clk), 2)
    assert not _led(dut, board, board.led_link)
    await expect(model.reset(pull_ups).packets, "power-up")
    # 2. pin 3 reads its pull-up.
    await command(packet(p.module_addr, CMD_DIG_IO, 3))
    # 3. pin 0 as an output: the header pad follows the output latch.
    await command(packet(p.module_addr, CMD_DIG_CFG, 0, 0x00))
    for level in (0, 1, 0):
        await command(packet(p.module_addr, CMD_DIG_IO, 0, level))
        await ClockCycles(getattr(dut, board.clk), 4)
        assert model.pin_oe() & 1 and (model.pin_o() & 1) == level
        assert _bit(dut, (board.pads, 0)) == level, f"pad 0 should be {level} after DIG_IO write {level}"
    # The pin reads back what it drives.
    await command(packet(p.module_addr, CMD_DIG_IO, 0))
    # 4. LEDs: traffic lit the activity LED; no heartbeat was answered, so no link.
    if board.led_act is not None:
        assert _led(dut, board, board.led_act), "activity LED dark after traffic"
    assert not _led(dut, board, board.led_link), "link_up LED lit without a heartbeat answer"
    dut._log.info("%d bytes from the board, all as the model says; %.1f ms simulated",
                  len(link.mon.data), now_ps() / 1e9)
