# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of brainstem_dio_uart with 24 pins (the iCEBreaker's three PMODs, a timer on
every pin, as `make bitstream BOARD=icebreaker24` builds it), over its serial pins, and their
pytest entry.

The board top's own test (tb/icebreaker24_top) runs that build at 9600 baud and touches only
two of its pins; these tests put every pin through each of its roles, so that pins 5-23 of
the wrapper's ports are exercised in every run, whatever the seed:
- every pin a DIG_CFG target (every stored bit set, queried, cleared), an output driven 1
  then 0, then an input again: pin_o, pin_oe and the configuration against the model;
- every pin an input with its transition latch armed (rising or falling edge, per pin from
  the seed): its pad moves to the trigger level (the latch fires on raw_trans, that pin
  only) and back (nothing fires), each level read back by DIG_IO with HOST and RFLX, then a
  timer result on RFLX (device ID 33) and reads whose IDs (5, 26, 5) set and clear every
  bit of rflx_id.

Build p24: the board's parameters (12 MHz, 24 pins, TIMER_MASK 24'hFFFFFF, the wrapper's
512-byte FIFO and 256 ms heartbeat) but 1 Mbaud, 12 clocks per bit, so a command costs tens of
microseconds rather than milliseconds: about 0.75 M clocks in all (Verilator only). The host, the model and
the strobe recorders are tb/brainstem_dio_uart/test_uart_link.py's. Random choices (the pin
order, the trigger edges, the input configurations) come from cocotb's seed, printed at the
start of each test.
"""

from __future__ import annotations

import cocotb
import pytest
import test_uart_link as link
from cocotb.triggers import ReadOnly, RisingEdge, Timer

import runner
from bsd_model import (
    CMD_DIG_CFG,
    CMD_DIG_IO,
    CMD_PTIME_RD,
    DEVCODE_HOST,
    DEVCODE_RFLX,
    DIGCFG_ENA,
    DIGCFG_IODIR,
    DIGCFG_STORED,
    DIGCFG_TRG,
    DIGCFG_TSTATE,
    Output,
    Params,
    packet,
    ticks_close,
)
from uart_line import now_ps

PINS = 24
BUILDS = {
    "p24": {**Params(clk_hz=12_000_000, num_pins=PINS, timer_mask=(1 << PINS) - 1, hb_rate=10).to_hdl(),
            "BAUD": 1_000_000, "FIFO_DEPTH": 512},
}

P, A = link.P, link.A
# Three polls of the transition latches: a level held this long is sampled (DESIGN.md).
HOLD_PS = int(3 * 1e12 / P.poll_hz) if P.poll_hz else 20 * link.PERIOD_PS


async def pins_match(dut, m, what: str) -> None:
    """pin_oe and pin_o as the model has them, read in this clock's read-only phase."""
    await ReadOnly()
    got = (int(dut.pin_oe.value), int(dut.pin_o.value))
    assert got == (m.pin_oe(), m.pin_o()), (f"after {what}: pin_oe/pin_o {got[0]:06x}/{got[1]:06x}, "
                                            f"model {m.pin_oe():06x}/{m.pin_o():06x}")
    await RisingEdge(dut.clk)


@cocotb.test()
async def test_every_pin_cfg_and_output(dut) -> None:
    """Each pin in turn (seeded order): DIG_CFG with every stored bit set, queried back, then
    an output (0x00) driven 1 then 0, then an input again with a seeded configuration:
    pin_oe and pin_o after every command, and each query's reply, as the model's."""
    host, m, strobes, rng = await link.setup(dut, 0)
    assert P.num_pins == PINS and not P.fixed_mask
    order = list(P.free_pins)
    rng.shuffle(order)
    dut._log.info("pin order %s", order)
    for p in order:
        await host.command(m, packet(A, CMD_DIG_CFG, p, DIGCFG_STORED))
        await host.command(m, packet(A, CMD_DIG_CFG, p))
        assert m.digcfg(p) == DIGCFG_STORED
        await host.command(m, packet(A, CMD_DIG_CFG, p, 0x00))
        await pins_match(dut, m, f"pin {p} an output")
        for v in (1, 0):
            await host.command(m, packet(A, CMD_DIG_IO, p, v))
            assert (m.pin_o() >> p & 1, m.pin_oe() >> p & 1) == (v, 1), f"the model's pin {p} is not driving {v}"
            await pins_match(dut, m, f"pin {p} <- {v}")
        cfg = DIGCFG_IODIR | rng.randrange(DIGCFG_STORED + 1)
        await host.command(m, packet(A, CMD_DIG_CFG, p, cfg))
        await host.command(m, packet(A, CMD_DIG_CFG, p))
        await pins_match(dut, m, f"pin {p} an input again (DIGCFG {cfg:#04x})")
    assert m.pin_oe() == 0
    assert not strobes.frame_err and not strobes.dropped()
    host.check_line()


@cocotb.test()
async def test_every_pin_input_latch_rflx(dut) -> None:
    """Every pin an input with its transition latch armed for a seeded edge, its pad first
    at the other level. Each pin in turn (seeded order): the pad moves to the trigger level
    (raw_trans pulses for that pin alone), is read back (DIG_IO, HOST and RFLX: the reply
    packet and the RFLX strobe as the model's), moves back (nothing fires) and is read again.
    Then pin 23's timer (ID 33) reports a 1 ms edge on RFLX, and pins 0, 21, 0 are read on
    RFLX (IDs 5 = 000101, 26 = 011010, 5): every rflx_id bit rises and falls."""
    host, m, strobes, rng = await link.setup(dut, 0)
    seen = link.Pulses(dut)
    mask = (1 << PINS) - 1
    trg = rng.getrandbits(PINS)         # bit p set: pin p's latch fires on a rising edge
    idle = ~trg & mask
    dut._log.info("rising-edge latches %06x", trg)
    assert not m.set_pins(idle)         # no latch armed yet
    dut.pin_i.value = idle
    await Timer(HOLD_PS, unit="ps")
    for p in P.pins:
        await host.command(m, packet(A, CMD_DIG_CFG, p, DIGCFG_IODIR | DIGCFG_ENA | (DIGCFG_TRG if trg >> p & 1 else 0)))
    await pins_match(dut, m, "every pin an input")
    exp = Output()

    async def read(p: int, what: str) -> None:
        pkt = packet(A, CMD_DIG_IO, DEVCODE_HOST | DEVCODE_RFLX | p)
        out = m.feed(pkt)
        assert len(out.packets) == 1 and out.rflx == [(P.pin_id(p), m.level(p))], out
        exp.extend(out)
        await host.send(pkt)
        await host.expect(out.packets, f"{what}: DIG_IO read of pin {p}")
        assert seen.rflx == exp.rflx, f"{what}: RFLX strobes {seen.rflx[-3:]}, model {exp.rflx[-3:]}"

    async def move(p: int, level: int, fires: bool) -> None:
        out = m.set_pin(p, level)
        assert out.trans == ([p] if fires else []), out
        exp.extend(out)
        dut.pin_i.value = m.levels
        await Timer(HOLD_PS, unit="ps")
        assert seen.trans == exp.trans, f"pin {p} -> {level}: raw_trans pulses {seen.trans[-3:]}, model {exp.trans[-3:]}"

    order = list(P.pins)
    rng.shuffle(order)
    dut._log.info("pin order %s", order)
    for p in order:
        await move(p, trg >> p & 1, fires=True)
        await read(p, "at the trigger level")
        await move(p, idle >> p & 1, fires=False)
        await read(p, "back at the idle level")
    assert sorted(seen.trans) == list(P.pins)

    # Pin 23's timer to RFLX (ID 33 = 100001): edge mode towards 1 from 0, an edge 1 ms on.
    pin = PINS - 1
    assert P.timer_id(pin) == 33
    await host.command(m, packet(A, CMD_DIG_CFG, pin, DIGCFG_IODIR | DIGCFG_TSTATE))
    exp.extend(m.set_pin(pin, 0))
    dut.pin_i.value = m.levels
    await Timer(HOLD_PS, unit="ps")
    pkt = packet(A, CMD_PTIME_RD, DEVCODE_RFLX | pin)
    assert not m.feed(pkt)
    n_rflx = len(seen.rflx)
    await host.send(pkt)
    t_sent = now_ps()
    await Timer(1_000_000_000, unit="ps")
    interval = (now_ps() - t_sent) / 1e12
    exp.extend(m.set_pin(pin, 1))
    dut.pin_i.value = m.levels
    await Timer(HOLD_PS, unit="ps")
    new = seen.rflx[n_rflx:]
    assert len(new) == 1 and new[0][0] == P.timer_id(pin), f"RFLX strobes after the timer: {new}"
    ticks = new[0][1]
    # The core starts timing half a bit before the host's stop bit ends: a bit of slack.
    assert ticks_close(ticks, interval, P.clk_hz, latency_clocks=link.DIV + 4), f"{ticks} ticks for 1 ms"
    done = m.timer_complete(pin, ticks)
    assert done.rflx == new and not done.packets, (done, new)
    exp.extend(done)
    for p in (0, 21, 0):
        await read(p, "the rflx_id walk")
    assert [i for i, _ in seen.rflx[-4:]] == [33, 5, 26, 5]
    assert seen.trans == exp.trans and seen.rflx == exp.rflx
    assert not strobes.frame_err and not strobes.dropped()
    host.check_line()


# Verilator only: about 0.75 M clocks of the whole wrapper, minutes on Icarus, which runs the
# same ports at 5 pins in test_uart_link.py.
@pytest.mark.parametrize("sim, build", runner.cases(BUILDS, only=lambda sim, build: sim == "verilator"))
def test_uart_pins24(sim: str, build: str) -> None:
    runner.run(sim, "brainstem_dio_uart", __file__, BUILDS[build], build)
