# SPDX-License-Identifier: Apache-2.0
"""Unit tests of the reference model (tb/lib/bsd_model.py) against the contract's own examples.

These are the only tests with hard-coded byte strings: they pin the model to PROTOCOL.md
§7 and §2, so the top-level tests can trust it.
"""

from __future__ import annotations

import pytest

import bsd_model
from bsd_model import (
    CMD_DEBUG,
    CMD_DIG_CFG,
    CMD_DIG_IO,
    CMD_DIG_RST,
    CMD_PTIME_RD,
    CMD_RESET,
    DEVCODE_HOST,
    DIGCFG_RESET,
    MSG_CMD_INDEX_ERR,
    MSG_CMD_INVALID,
    MSG_CMD_TOO_LONG,
    MSG_CMD_TOO_SHORT,
    MSG_CONFIG_ERR,
    MSG_POWER_RESET,
    MSG_SERIAL_ERROR,
    MSG_TMR_CONFLICT,
    TIMER_MAX_TICKS,
    Model,
    Output,
    Params,
    expected_ticks,
    message,
    packet,
    result_of,
    ticks_close,
    timer_interval,
    verilog_int,
)

H = bytes.fromhex


def pk(out: Output) -> list[bytes]:
    return out.packets


@pytest.fixture
def model() -> Model:
    # Pin 0 high (the §7 read), pin 4 high (edge timer towards 0 needs a falling edge).
    m = Model(Params(), pins=0b10001)
    return m


# ---------------------------------------------------------------- §7 worked examples

def test_table_reset(model: Model) -> None:
    assert pk(model.reset()) == [H("02028004")]


def test_table_query_pin3(model: Model) -> None:
    assert pk(model.feed(H("02021A03"))) == [H("02031A0301")]


def test_table_set_and_write(model: Model) -> None:
    assert not model.feed(H("02031A0100"))
    assert model.pin_oe() == 0b00010
    assert not model.feed(H("02031B0101"))
    assert model.pin_o() == 0b00010


def test_table_read_pin0(model: Model) -> None:
    out = model.feed(H("02021B80"))
    assert pk(out) == [H("0203040501")]
    assert out.rflx == []


def test_table_read_output_pin(model: Model) -> None:
    model.feed(H("02031A0100"))
    assert pk(model.feed(H("02021B81"))) == [H("0202800A")]


def test_table_pin7_out_of_range(model: Model) -> None:
    assert pk(model.feed(H("02031A0701"))) == [H("0202800A")]


def test_table_pin0_no_timer(model: Model) -> None:
    assert pk(model.feed(H("02021D80"))) == [H("0202800A")]


def test_table_ptime_pin4(model: Model) -> None:
    assert not model.feed(H("02021D84"))
    assert model.timer_busy(4)
    run = model.timer_run(4)
    # Default DIGCFG 0x01: edge mode, target 0 -> the 800 us high-to-low edge completes it.
    start = 1.0e-3
    wave = [(0.0, 1), (start + 800e-6, 0), (start + 900e-6, 1)]
    ticks = expected_ticks(start, wave, run.width, run.target)
    assert ticks == 500
    assert pk(model.timer_complete(4, result_of(ticks))) == [H("020404" "0E01F4")]
    assert not model.timer_busy(4)


def test_table_too_short(model: Model) -> None:
    assert pk(model.feed(H("02011A"))) == [H("0202801B")]


def test_table_too_long(model: Model) -> None:
    assert pk(model.feed(H("02041A0201FF"))) == [H("02028009")]
    assert model.digcfg(2) == 0x01


def test_table_unknown(model: Model) -> None:
    assert pk(model.feed(H("020163"))) == [H("02028008")]


def test_table_resync(model: Model) -> None:
    assert pk(model.feed(H("AD00"))) == [H("0200")]


def test_table_debug_echo(model: Model) -> None:
    assert pk(model.feed(H("0203170102"))) == [H("0203170102")]


def test_table_as_one_session() -> None:
    """The whole table in order, as one host session."""
    m = Model(Params(), pins=0b10001)
    rows = [
        ("", "02028004"),
        ("02021A03", "02031A0301"),
        ("02031A0100", ""),
        ("02031B0101", ""),
        ("02021B80", "0203040501"),
        ("02021B81", "0202800A"),
        ("02031A0701", "0202800A"),
        ("02021D80", "0202800A"),
        ("02021D84", ""),
        ("02011A", "0202801B"),
        ("02041A0201FF", "02028009"),
        ("020163", "02028008"),
        ("AD00", "0200"),
        ("0203170102", "0203170102"),
    ]
    for sent, reply in rows:
        out = m.reset() if not sent else m.feed(H(sent))
        assert b"".join(out.packets) == H(reply), sent
    assert b"".join(m.timer_complete(4, 500).packets) == H("020404" "0E01F4")


# ---------------------------------------------------------------- §2 messages, precedence

@pytest.mark.parametrize("code", [c for c in range(256) if c not in (0, 23, 24, 26, 27, 28, 29)])
@pytest.mark.parametrize("n", [1, 2, 8])
def test_invalid_any_length(code: int, n: int) -> None:
    """cmdInvalid comes first, whatever N (codes 4 and 0x80 included)."""
    m = Model()
    data = [code] + [0] * (n - 1)
    assert pk(m.feed(packet(2, *data))) == [message(2, MSG_CMD_INVALID)]


@pytest.mark.parametrize("n", range(1, 9))
def test_reset_any_length(n: int) -> None:
    """cmdRESET: the power-up state and only the power-up message, for any N from 1 to 8
    (never cmdTooLong); a timer stops, and the next packet is served after it."""
    m = Model(pins=0b11110)
    m.feed(packet(2, CMD_DIG_CFG, 1, 0x00))
    m.feed(packet(2, CMD_DIG_IO, 1, 1))
    m.feed(packet(2, CMD_DIG_CFG, 2, 0x1F))
    m.feed(packet(2, CMD_PTIME_RD, DEVCODE_HOST | 3))
    out = m.feed(packet(2, CMD_RESET, *range(n - 1)) + packet(2, CMD_DIG_CFG, 1))
    assert pk(out) == [message(2, MSG_POWER_RESET), packet(2, CMD_DIG_CFG, 1, DIGCFG_RESET)]
    assert not m.timer_busy(3) and m.pin_oe() == 0 and m.pin_o() == 0
    assert m.digcfg(2) == DIGCFG_RESET


@pytest.mark.parametrize("n", range(1, 9))
def test_debug_echo_any_length(n: int) -> None:
    """cmdDEBUG: the packet back unchanged for any N from 1 to 8 (never cmdTooShort/TooLong)."""
    m = Model()
    sent = packet(2, CMD_DEBUG, *range(0xF1, 0xF0 + n))
    assert pk(m.feed(sent)) == [sent]
    assert pk(m.feed(H("020117"))) == [H("020117")]


def test_debug_other_address_and_serial_error() -> None:
    m = Model()
    assert pk(m.feed(packet(4, CMD_DEBUG, 1, 2))) == []
    assert pk(m.feed(H("020917"))) == [message(2, MSG_SERIAL_ERROR)]


@pytest.mark.parametrize("cmd", [CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST, CMD_PTIME_RD])
def test_too_short_before_index(cmd: int) -> None:
    assert pk(Model().feed(packet(2, cmd))) == [message(2, MSG_CMD_TOO_SHORT)]


@pytest.mark.parametrize(
    "data",
    [
        [CMD_DIG_CFG, 5],  # query out of range
        [CMD_DIG_CFG, 0xFF, 0x01],  # set out of range
        [CMD_DIG_CFG, 0x80, 0x01, 0, 0],  # out of range, extra bytes: no cmdTooLong
        [CMD_DIG_IO, 0x85],  # read out of range (pin bits 5)
        [CMD_DIG_IO, 0xC0 | 0x3F],
        [CMD_DIG_IO, 0x80, 1],  # write: pin byte 0x80 is the pin number itself
        [CMD_DIG_IO, 0, 1],  # write to an input
        [CMD_DIG_IO, 0, 1, 9, 9],  # write to an input, extra bytes
        [CMD_DIG_RST, 5],
        [CMD_DIG_RST, 5, 0],
        [CMD_PTIME_RD, 0x80],  # pin 0: no timer
        [CMD_PTIME_RD, 0x85],  # out of range
        [CMD_PTIME_RD, 0xC0 | 0x3F, 1],
    ],
)
def test_index_errors(data: list[int]) -> None:
    m = Model()
    out = m.feed(packet(2, *data))
    assert pk(out) == [message(2, MSG_CMD_INDEX_ERR)]
    assert out.rflx == [] and m.timers == {}


def test_index_error_reading_output_and_timing_output() -> None:
    m = Model()
    m.feed(packet(2, CMD_DIG_CFG, 1, 0x00))
    for data in ([CMD_DIG_IO, 0xC1], [CMD_PTIME_RD, 0xC1], [CMD_PTIME_RD, 0x81, 0]):
        assert pk(m.feed(packet(2, *data))) == [message(2, MSG_CMD_INDEX_ERR)]
    assert m.timers == {}


def test_failing_command_changes_nothing() -> None:
    m = Model(Params(fixed_mask=0b01000, fixed_cfg=0x07 << 24))
    before = (list(m.cfg), list(m.out_latch))
    m.feed(packet(2, CMD_DIG_CFG, 3, 0x00))
    m.feed(packet(2, CMD_DIG_IO, 2, 1))
    m.feed(packet(2, CMD_DIG_CFG, 9, 0x00))
    assert (m.cfg, m.out_latch) == before


def test_config_err_fixed() -> None:
    p = Params(fixed_mask=0b01001, fixed_cfg=(0x07 << 24) | 0x00)
    m = Model(p)
    assert pk(m.feed(packet(2, CMD_DIG_CFG, 3))) == [packet(2, CMD_DIG_CFG, 3, 0x87)]
    assert pk(m.feed(packet(2, CMD_DIG_CFG, 0))) == [packet(2, CMD_DIG_CFG, 0, 0x80)]
    assert m.pin_oe() == 0b00001
    for data in ([CMD_DIG_CFG, 3, 0x01], [CMD_DIG_CFG, 0, 0x01, 0xFF]):
        assert pk(m.feed(packet(2, *data))) == [message(2, MSG_CONFIG_ERR)]
    assert m.digcfg(3) == 0x87 and m.digcfg(0) == 0x80
    # A fixed output can still be written; a fixed input can be read.
    assert not m.feed(packet(2, CMD_DIG_IO, 0, 1))
    assert m.pin_o() == 1


def test_tmr_conflict_and_precedence_over_too_long() -> None:
    m = Model(pins=0b11110)
    assert not m.feed(packet(2, CMD_PTIME_RD, 0x82))
    assert pk(m.feed(packet(2, CMD_PTIME_RD, 0x82))) == [message(2, MSG_TMR_CONFLICT)]
    assert pk(m.feed(packet(2, CMD_PTIME_RD, 0x42, 0, 0))) == [message(2, MSG_TMR_CONFLICT)]
    # The running measurement goes on with its original flags.
    assert m.timer_run(2).host and not m.timer_run(2).rflx


def test_index_err_before_tmr_conflict() -> None:
    """A pin turned output while its timer runs (DESIGN.md 7): cmdIndexErr is the first of
    the command's own errors."""
    m = Model()
    m.feed(packet(2, CMD_PTIME_RD, 0x81))
    m.feed(packet(2, CMD_DIG_CFG, 1, 0x00))
    assert pk(m.feed(packet(2, CMD_PTIME_RD, 0x81))) == [message(2, MSG_CMD_INDEX_ERR)]


def test_too_long_after_executing() -> None:
    m = Model(pins=0b00001)
    # DIG_CFG set + extra
    assert pk(m.feed(packet(2, CMD_DIG_CFG, 1, 0xE0, 7))) == [message(2, MSG_CMD_TOO_LONG)]
    assert m.digcfg(1) == 0x00
    # DIG_IO write + extra (N=8)
    assert pk(m.feed(packet(2, CMD_DIG_IO, 1, 2, 3, 4, 5, 6, 7))) == [message(2, MSG_CMD_TOO_LONG)]
    assert m.pin_o() == 0b10
    # DIG_RST + extra
    assert pk(m.feed(packet(2, CMD_DIG_RST, 1, 0))) == [message(2, MSG_CMD_TOO_LONG)]
    # PTIME_RD + extra: timer started, then the message
    assert pk(m.feed(packet(2, CMD_PTIME_RD, 0xC2, 0))) == [message(2, MSG_CMD_TOO_LONG)]
    assert m.timer_busy(2)
    # DIG_IO N=3 is the write form, even with a DEVCODE-looking byte
    assert pk(m.feed(packet(2, CMD_DIG_IO, 0x80, 1))) == [message(2, MSG_CMD_INDEX_ERR)]


def test_hb_from_host_is_silent() -> None:
    m = Model()
    for data in ([0], [0, 2], [0, 3], [0, 1, 2, 3, 4, 5, 6, 7]):
        assert not m.feed(packet(2, *data))


# ---------------------------------------------------------------- framing

def test_serial_error_and_resync_after() -> None:
    m = Model()
    assert pk(m.feed(H("0209"))) == [message(2, MSG_SERIAL_ERROR)]
    # The next byte is an address again.
    assert pk(m.feed(H("02021A00"))) == [packet(2, CMD_DIG_CFG, 0, 1)]
    assert not m.feed(H("05FF"))  # other address, N > 8: silent
    assert not m.feed(H("AD09"))
    assert pk(m.feed(H("AD00"))) == [packet(2)]


def test_other_addresses_ignored() -> None:
    m = Model()
    # Data bytes that look like a packet to us are consumed as data.
    assert not m.feed(H("0406" "02021A03" "0200"))
    assert not m.feed(H("AD04" "02021A03"))  # 0xAD with N > 0
    assert not m.feed(H("0200"))  # N = 0 to us
    assert not m.feed(H("0300"))
    assert pk(m.feed(H("02021A03"))) == [packet(2, CMD_DIG_CFG, 3, 1)]


def test_rx_timeout_drops_partial() -> None:
    m = Model(Params(rx_timeout_us=200))
    m.feed(H("02021A"))
    assert m.mid_packet
    assert pk(m.feed(H("02021A03"), idle_before_s=210e-6)) == [packet(2, CMD_DIG_CFG, 3, 1)]
    m.feed(H("0202"))
    assert pk(m.feed(H("1A03"), idle_before_s=190e-6)) == [packet(2, CMD_DIG_CFG, 3, 1)]
    # RX_TIMEOUT_US = 0: never.
    m = Model(Params(rx_timeout_us=0))
    m.feed(H("02"))
    assert pk(m.feed(H("021A03"), idle_before_s=10.0)) == [packet(2, CMD_DIG_CFG, 3, 1)]


def test_gp2_build() -> None:
    p = Params(num_pins=7, module_addr=4, timer_id_base=11, trans_id_base=20, timer_mask=0b0011110)
    m = Model(p, pins=0b1000000)
    assert pk(m.reset()) == [H("04028004")]
    assert pk(m.feed(H("04021B86"))) == [H("0403040B01")]
    assert pk(m.feed(H("04021B87"))) == [H("0402800A")]
    assert not m.feed(H("04021DC4"))
    out = m.timer_complete(4, 0x1234)
    assert pk(out) == [H("0404040F1234")] and out.rflx == [(15, 0x1234)]


def test_to_hdl_names_and_widths() -> None:
    hdl = Params(num_pins=5, fixed_mask=0b01001, fixed_cfg=0x07_00_00_00_00).to_hdl()
    assert list(hdl) == [
        "CLK_HZ", "MODULE_ADDR", "NUM_PINS", "TIMER_MASK", "FIXED_MASK", "FIXED_CFG",
        "PIN_ID_BASE", "TIMER_ID_BASE", "TRANS_ID_BASE", "POLL_HZ", "RX_TIMEOUT_US", "HB_RATE",
    ]
    assert hdl["FIXED_CFG"] == "40'h700000000" and hdl["TIMER_MASK"] == "5'h1e"
    # The cocotb side reads the HDL dict back (tb/lib/runner.py: one way to pass parameters).
    odd = Params(num_pins=7, fixed_mask=0b1000001, fixed_cfg=0x03 << 48 | 0x07, hb_rate=3)
    assert Params.from_hdl(odd.to_hdl()) == odd
    assert Params.from_hdl({**odd.to_hdl(), "BAUD": 9600}) == odd


@pytest.mark.parametrize("text, value", [
    (12, 12), ("25600", 25600), ("5'h1e", 0x1E), ("5'H1E", 0x1E), ("7'b1001010", 0b1001010),
    ("56'h1d_0000", 0x1D0000), ("8'd200", 200), ("6'o17", 0o17),
])
def test_verilog_int(text: object, value: int) -> None:
    """The block tests read their builds' parameters (ints, or literals as the runner passes
    them) with one parser."""
    assert verilog_int(text) == value


@pytest.mark.parametrize(
    "kw",
    [dict(module_addr=3), dict(module_addr=0), dict(num_pins=0), dict(num_pins=65),
     dict(timer_mask=1 << 5), dict(clk_hz=1_000_000), dict(pin_id_base=60)],
)
def test_params_validation(kw: dict[str, int]) -> None:
    with pytest.raises(ValueError):
        Params(**kw)


# ---------------------------------------------------------------- transition latch

def test_latch_rising_one_shot_and_rearm() -> None:
    m = Model(pins=0)
    m.feed(packet(2, CMD_DIG_CFG, 2, 0x07))  # input, ENA, TRG rising
    assert m.set_pin(2, 1).trans == [2]
    assert m.set_pin(2, 0).trans == [] and m.set_pin(2, 1).trans == []
    m.feed(packet(2, CMD_DIG_RST, 2))  # arms with level 1 as previous
    assert m.set_pin(2, 0).trans == []
    assert m.set_pin(2, 1).trans == [2]


def test_latch_present_level_never_fires() -> None:
    m = Model(pins=0b100)
    m.feed(packet(2, CMD_DIG_CFG, 2, 0x07))
    assert m.set_pin(2, 1).trans == []  # no change: nothing
    assert m.set_pin(2, 0).trans == []
    assert m.set_pin(2, 1).trans == [2]


def test_latch_falling_and_disabled() -> None:
    m = Model(pins=0b11)
    m.feed(packet(2, CMD_DIG_CFG, 0, 0x03))  # falling
    m.feed(packet(2, CMD_DIG_CFG, 1, 0x05))  # ENA = 0
    assert m.set_pins(0).trans == [0]
    m.feed(packet(2, CMD_DIG_CFG, 1, 0x00))  # output: latch inactive
    m.feed(packet(2, CMD_DIG_RST, 1))  # silent (DESIGN.md 6)
    assert m.set_pins(0b11).trans == []


def test_latch_fixed_armed_at_reset() -> None:
    p = Params(fixed_mask=0b01000, fixed_cfg=0x07 << 24)
    m = Model(p, pins=0)
    assert m.set_pin(3, 1).trans == [3]
    m.reset(pins=0b01000)
    assert m.set_pin(3, 0).trans == [] and m.set_pin(3, 1).trans == [3]


def test_latch_simultaneous_ascending() -> None:
    m = Model(pins=0)
    for pin in (4, 1, 0):
        m.feed(packet(2, CMD_DIG_CFG, pin, 0x07))
    assert m.set_pins(0b10011).trans == [0, 1, 4]


# ---------------------------------------------------------------- timers

@pytest.mark.parametrize("target", [0, 1])
def test_edge_timer(target: int) -> None:
    nt = 1 - target
    # Already at target: must leave it first (the first edge to non-target does not count).
    wave = [(0.0, target), (1e-3, nt), (1.5e-3, target)]
    assert timer_interval(0.5e-3, wave, width=False, target=target) == pytest.approx(1e-3)
    assert expected_ticks(0.5e-3, wave, width=False, target=target) == 625
    # No edge: timeout.
    assert expected_ticks(0.0, [(0.0, nt)], width=False, target=target) is None
    # Edge after 104.856 ms: timeout too.
    assert expected_ticks(0.0, [(0.0, nt), (0.105, target)], False, target) is None
    assert expected_ticks(0.0, [(0.0, nt), (0.1048, target)], False, target) == 65500


@pytest.mark.parametrize("target", [0, 1])
def test_width_timer(target: int) -> None:
    nt = 1 - target
    wave = [(0.0, target), (1e-3, nt), (2e-3, target), (2.8e-3, nt)]
    # Started while at target: the pulse that begins at 2 ms is measured.
    assert expected_ticks(0.5e-3, wave, width=True, target=target) == 500
    # A pulse under one tick is still a completed measurement: 1, never 0.
    short = [(0.0, nt), (1e-3, target), (1e-3 + 0.3e-6, nt)]
    assert expected_ticks(0.0, short, width=True, target=target) == 1
    # The timeout counts from the start, not from the pulse's beginning.
    late = [(0.0, nt), (100e-3, target), (106e-3, nt)]
    assert expected_ticks(0.0, late, width=True, target=target) is None
    assert result_of(None) == 0


def test_timer_busy_lifecycle_and_flags() -> None:
    m = Model(pins=0b11110)
    for dev in (0x02, 0x43, 0x84, 0xC1):
        assert not m.feed(packet(2, CMD_PTIME_RD, dev))
    out = m.timers_complete({4: 7, 1: TIMER_MAX_TICKS, 3: 0})
    assert out.packets == [H("0204040B" "FFFF"), H("0204040E" "0007")]
    assert out.rflx == [(11, TIMER_MAX_TICKS), (13, 0)]
    m.timer_done(2)
    assert m.timers == {}
    # A DIG_CFG set during a measurement does not change the running mode.
    m.feed(packet(2, CMD_PTIME_RD, 0x81))
    m.feed(packet(2, CMD_DIG_CFG, 1, 0x19))
    assert not m.timer_run(1).width and m.timer_run(1).target == 0


def test_ticks_close() -> None:
    assert ticks_close(500, 800e-6, 48_000_000)
    assert ticks_close(501, 800e-6, 48_000_000)
    assert not ticks_close(502, 800e-6, 48_000_000)
    assert not ticks_close(0, 0.1e-6, 48_000_000)
    assert ticks_close(1, 0.1e-6, 48_000_000)


# ---------------------------------------------------------------- heartbeat

def test_heartbeat_link_up() -> None:
    m = Model(Params(hb_rate=1))
    assert not m.link_up
    assert pk(m.heartbeat_due()) == [H("02020000")]
    assert not m.feed(H("02020003"))  # wrong answer type: silent, ignored
    assert not m.link_up
    m.feed(H("02020002"))
    assert m.link_up
    assert pk(m.heartbeat_due()) == [H("02020001")]
    assert m.link_up  # previous one was answered
    assert pk(m.heartbeat_due()) == [H("02020000")]
    assert not m.link_up  # the DOWN one was never answered
    m.heartbeat_skipped()
    assert pk(m.heartbeat_due()) == [H("02020001")]


# ---- observers: what the model tells functional coverage and the host's fake module ----


def test_observers_hear_each_decision_in_order() -> None:
    """A PTIME_RD that starts a timer, one that conflicts with it, an out-of-range DIG_IO,
    a framing error, the timer's completion and a cmdRESET, each told as it is decided, with
    the very packet objects the model returns."""
    m = Model(pins=0b11110)
    heard: list[bsd_model.Event] = []
    m.observers.append(heard.append)

    def command_events() -> list[bsd_model.Event]:
        return [e for e in heard if not isinstance(e, bsd_model.ByteFed)]

    start = packet(2, CMD_PTIME_RD, DEVCODE_HOST | 4)
    assert not m.feed(start)
    assert [e.value for e in heard if isinstance(e, bsd_model.ByteFed)] == list(start)
    run = m.timer_run(4)
    assert command_events() == [bsd_model.TimerStarted(4, run),
                                bsd_model.CommandDone(tuple(start[2:]), 4, True, None, [])]
    heard.clear()
    out = m.feed(packet(2, CMD_PTIME_RD, DEVCODE_HOST | 4))
    done = command_events()
    assert done[0] == bsd_model.TimerConflict(4, run)
    assert done[1].error == MSG_TMR_CONFLICT and done[1].packets[0] is out.packets[0]
    heard.clear()
    m.feed(packet(2, CMD_DIG_IO, 9, 1))
    assert command_events() == [bsd_model.CommandDone((CMD_DIG_IO, 9, 1), 9, None, MSG_CMD_INDEX_ERR,
                                                      [message(2, MSG_CMD_INDEX_ERR)])]
    heard.clear()
    out = m.feed(bytes([2, 9]))
    assert command_events() == [bsd_model.Framing(2, 9, out.packets)]
    heard.clear()
    out = m.timer_complete(4, 77)
    assert heard == [bsd_model.TimerCompleted(4, run, 77, out)]
    heard.clear()
    out = m.feed(packet(2, CMD_RESET))
    assert command_events() == [bsd_model.Reset(), bsd_model.CommandDone((CMD_RESET,), None, None, None, out.packets)]
