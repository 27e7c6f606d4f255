# SPDX-License-Identifier: Apache-2.0
"""Module methods against the fake module: the bytes each command sends, its result, each
error raised from the call that caused it, attribution, timeouts and timer results."""

from __future__ import annotations

import threading
import time

import pytest
from host_fake import wait_for

import brainstem_dio
from brainstem_dio import DigCfg, Packet
from brainstem_dio import protocol as P


def sent(fake, cmd: int) -> list[bytes]:
    """The host's packets with command `cmd` (the library's sync echoes left out)."""
    return [d for d in fake.packets_with(cmd) if not (cmd == P.CMD_DEBUG and d[1:2] == b"\xb5")]


# ---- commands and their bytes ----


@pytest.mark.parametrize(
    "kwargs, byte",
    [
        ({}, 0x01),
        ({"output": True}, 0x00),
        ({"latch": True, "latch_rising": True}, 0x07),
        ({"latch": True}, 0x03),
        ({"timer_high": True}, 0x09),
        ({"timer_width": True, "timer_high": True}, 0x19),
        ({"cfg": DigCfg(output=True, timer_width=True)}, 0x10),
        ({"cfg": 0xFF}, 0x1F),  # a raw byte; FIXED and bits 6:5 are not sent
        ({"cfg": DigCfg(latch=True), "latch_rising": True}, 0x07),  # named fields override
    ],
)
def test_configure_sends_the_digcfg_byte(rig, kwargs, byte):
    m, fake = rig()
    assert m.configure(2, **kwargs) is None
    assert sent(fake, P.CMD_DIG_CFG) == [bytes([26, 2, byte])]
    assert int(m.query(2)) == byte


def test_digcfg_round_trip():
    for b in range(256):
        cfg = DigCfg.from_byte(b)
        assert int(cfg) == b & 0x9F
        assert cfg.to_byte() == b & 0x1F
    assert str(DigCfg(latch=True, latch_rising=True, timer_width=True)) == "input, latch on 0->1, width timer of low"


def test_query_returns_the_configuration(rig):
    m, fake = rig(fixed={0: 0x00})
    assert m.query(3) == DigCfg()
    assert m.query(0) == DigCfg(output=True, fixed=True)
    assert sent(fake, P.CMD_DIG_CFG) == [bytes([26, 3]), bytes([26, 0])]


def test_update_config_changes_only_the_fields_named(rig):
    m, _fake = rig()
    m.configure(4, timer_width=True, timer_high=True)
    assert m.update_config(4, latch=True) == DigCfg(latch=True, timer_width=True, timer_high=True)
    assert int(m.query(4)) == 0x1B


def test_write_read_rearm_reflect(rig):
    m, fake = rig(levels=0b01001)
    m.configure(1, output=True)
    m.write(1, True)
    m.write(1, 0)
    assert m.read(0) == 1 and m.read(3) == 1 and m.read(2) == 0
    assert m.read(3, rflx=True) == 1
    m.rearm(2)
    m.reflect(4)
    assert sent(fake, P.CMD_DIG_IO) == [
        bytes([27, 1, 1]),
        bytes([27, 1, 0]),
        bytes([27, 0x80]),
        bytes([27, 0x83]),
        bytes([27, 0x82]),
        bytes([27, 0xC3]),
        bytes([27, 0x44]),
    ]
    assert sent(fake, P.CMD_DIG_RST) == [bytes([28, 2])]
    assert fake.out_latch[1] == 0


def test_echo_and_probe(rig):
    m, fake = rig()
    assert m.echo() == b""
    assert m.echo(b"\x01\x02\x03\x04\x05\x06\x07") == bytes(range(1, 8))
    assert sent(fake, P.CMD_DEBUG) == [bytes([23]), bytes([23, 1, 2, 3, 4, 5, 6, 7])]
    with pytest.raises(ValueError):
        m.echo(bytes(8))
    assert m.probe() < 0.5
    assert fake.probes == 1


def test_request_returns_every_answer(rig):
    m, _fake = rig()
    assert m.request([26, 3]) == [Packet.of(2, 26, 3, 1)]
    assert m.request([28, 1]) == []
    assert m.request([0x63], check=False) == [Packet.of(2, 0x80, 8)]


@pytest.mark.parametrize("bad", [-1, 256, 1.5, "1"])
def test_bad_arguments_are_refused_before_sending(rig, bad):
    m, fake = rig()
    with pytest.raises(ValueError):
        m.configure(bad)
    with pytest.raises(ValueError):
        m.read(bad if bad != 256 else 64)
    assert fake.received == []


def test_module_address_is_checked():
    host, _ = __import__("host_fake").serial_pair()
    link = brainstem_dio.Link(host)
    try:
        for addr in (0, 1, 3, 0xAD, 256):
            with pytest.raises(ValueError):
                brainstem_dio.Module(link, addr)
    finally:
        link.close()


# ---- errors, each from the call that caused it ----

ERRORS = [
    ("cmdInvalid", brainstem_dio.CmdInvalid, lambda m: m.request([0x63]), bytes([0x63])),
    ("cmdInvalid: DEV_VAL from the host", brainstem_dio.CmdInvalid, lambda m: m.request([4, 1, 1]), bytes([4, 1, 1])),
    ("cmdTooShort", brainstem_dio.CmdTooShort, lambda m: m.request([26]), bytes([26])),
    ("cmdTooShort PTIME_RD", brainstem_dio.CmdTooShort, lambda m: m.request([29]), bytes([29])),
    ("cmdTooLong", brainstem_dio.CmdTooLong, lambda m: m.request([28, 2, 0]), bytes([28, 2, 0])),
    ("cmdIndexErr query", brainstem_dio.CmdIndexErr, lambda m: m.query(5), bytes([26, 5])),
    ("cmdIndexErr configure", brainstem_dio.CmdIndexErr, lambda m: m.configure(200), bytes([26, 200, 1])),
    ("cmdIndexErr write an input", brainstem_dio.CmdIndexErr, lambda m: m.write(0, 1), bytes([27, 0, 1])),
    ("cmdIndexErr read an output", brainstem_dio.CmdIndexErr, lambda m: m.read(1), bytes([27, 0x81])),
    ("cmdIndexErr read out of range", brainstem_dio.CmdIndexErr, lambda m: m.read(63), bytes([27, 0xBF])),
    ("cmdIndexErr rearm", brainstem_dio.CmdIndexErr, lambda m: m.rearm(5), bytes([28, 5])),
    ("cmdIndexErr no timer", brainstem_dio.CmdIndexErr, lambda m: m.time_pin(0), bytes([29, 0x80])),
    ("cmdIndexErr time an output", brainstem_dio.CmdIndexErr, lambda m: m.time_pin(1), bytes([29, 0x81])),
    ("configErr", brainstem_dio.ConfigErr, lambda m: m.configure(4, output=True), bytes([26, 4, 0])),
    ("serialError", brainstem_dio.SerialError, lambda m: m.request(b"", n=9), None),
]


@pytest.mark.parametrize("name, exc_type, call, command", ERRORS, ids=[e[0] for e in ERRORS])
def test_each_error_is_raised_from_its_call(rig, name, exc_type, call, command):
    m, _fake = rig(fixed={4: 0x01})
    m.configure(1, output=True)
    with pytest.raises(exc_type) as info:
        call(m)
    err = info.value
    assert isinstance(err, brainstem_dio.ModuleError)
    assert err.code == exc_type.code and err.name == P.message_name(exc_type.code)
    assert err.addr == 2 and err.command == command
    assert err.name in str(err)
    # Nothing is left over for the next call, and nothing reached the queue.
    assert m.query(2) == DigCfg()
    assert [p for p in m.drain() if p != Packet.of(2, 0x80, 4)] == []


def test_tmr_conflict_from_the_second_start(rig):
    m, fake = rig()
    fake.timer_results[3] = 250
    fake.timer_delay = 0.1
    first = m.start_timer(3)
    with pytest.raises(brainstem_dio.TmrConflict) as info:
        m.start_timer(3)
    assert info.value.command == bytes([29, 0x83])
    assert first.result().ticks == 250  # the running measurement went on
    assert m.link._timers == {}  # the refused start left no waiter behind


def test_too_long_still_executes_the_command(rig):
    m, _fake = rig()
    with pytest.raises(brainstem_dio.CmdTooLong):
        m.request([26, 2, 0x00, 0xFF])
    assert m.query(2).output is True


def test_error_classes_by_code():
    for code, name in P.MESSAGE_NAMES.items():
        cls = brainstem_dio.error_class(code)
        assert cls.code == code and cls(code).name == name
    assert brainstem_dio.error_class(99) is brainstem_dio.ModuleError
    assert brainstem_dio.ModuleError(99).name == "message 99"


# ---- attribution of messages to calls ----


def test_pipelined_commands_each_get_their_own_error(rig):
    m, _fake = rig()
    m.configure(1, output=True)
    bad = m.write(0, 1, wait=False)  # pin 0 is an input
    good = m.write(1, 1, wait=False)
    bad2 = m.configure(9, wait=False)
    assert m.query(3) == DigCfg()  # the query in between is not disturbed
    good.result()
    with pytest.raises(brainstem_dio.CmdIndexErr) as info:
        bad.result()
    assert info.value.command == bytes([27, 0, 1])
    with pytest.raises(brainstem_dio.CmdIndexErr) as info:
        bad2.result()
    assert info.value.command == bytes([26, 9, 1])
    m.sync()  # everything was collected


def test_many_pipelined_commands(rig):
    # No inter-byte timeout in the fake: it reads the line 64 bytes at a time, and on a
    # loaded machine its thread can sleep past the 25.6 ms between two reads of one packet,
    # which drops the packet (an error, rightly kept) -- not what this test is about.
    m, fake = rig(rx_timeout=None)
    m.configure(1, output=True)
    pendings = [m.write(1, i & 1, wait=False) for i in range(200)]
    pendings[-1].result()
    assert all(p.done() for p in pendings)
    assert wait_for(lambda: m._unchecked == [])  # successes are not kept
    assert fake.dropped_partials == 0
    assert fake.out_latch[1] == 1
    m.sync()


def test_sync_raises_an_error_nobody_collected(rig):
    m, _fake = rig()
    m.write(0, 1, wait=False)
    m.write(3, 1, wait=False)
    with pytest.raises(brainstem_dio.CmdIndexErr) as info:
        m.sync()
    assert info.value.command == bytes([27, 0, 1])
    with pytest.raises(brainstem_dio.CmdIndexErr) as info:  # the next one is not lost either
        m.sync()
    assert info.value.command == bytes([27, 3, 1])
    m.sync()


def test_sync_attributes_an_error_of_a_raw_send(rig):
    m, _fake = rig()
    m.send([0x63])
    with pytest.raises(brainstem_dio.CmdInvalid):
        m.sync()
    m.send([26, 3])
    m.sync()
    assert Packet.of(2, 26, 3, 1) in m.drain()


def test_timer_result_and_heartbeat_between_command_and_error(rig):
    m, fake = rig()
    fake.timer_results[2] = 77
    fake.timer_delay = 0.0
    handle = m.start_timer(2)

    def interleave(addr: int, data: bytes) -> bool:
        if data[:1] == b"\x1b":
            fake.heartbeat()
        return False

    fake.on_packet = interleave
    with pytest.raises(brainstem_dio.CmdIndexErr):
        m.write(2, 1)
    assert handle.result().ticks == 77


def test_a_lost_sync_echo_fails_its_call_when_a_later_one_arrives(rig):
    m, fake = rig()
    dropped: list[bytes] = []

    def drop_first_sync(addr: int, data: bytes) -> bool:
        if data[:2] == bytes([23, 0xB5]) and not dropped:
            dropped.append(data)
            return True  # swallowed: the echo never comes
        return False

    fake.on_packet = drop_first_sync
    first = m.rearm(1, wait=False)
    m.rearm(2)
    with pytest.raises(brainstem_dio.ProtocolError, match="lost"):
        first.result()


# ---- timeouts ----


def test_per_call_timeout_and_recovery(rig):
    m, fake = rig()
    m.receive(1.0)
    fake.reply_delay = 0.2
    start = time.monotonic()
    with pytest.raises(brainstem_dio.Timeout, match="query pin 3") as info:
        m.query(3, timeout=0.05)
    assert isinstance(info.value, TimeoutError)
    assert 0.04 < time.monotonic() - start < 0.15
    fake.reply_delay = 0.0
    # The late reply is not taken for the next call's: it goes to the queue.
    assert m.query(2, timeout=1.0) == DigCfg()
    assert m.receive(1.0) == Packet.of(2, 26, 3, 1)


def test_timeout_of_a_command_without_reply(rig):
    m, fake = rig(mod_timeout=0.05)
    fake.mute = True
    with pytest.raises(brainstem_dio.Timeout, match="write pin 1"):
        m.write(1, 1)
    fake.mute = False
    m.configure(1, output=True)


def test_default_timeout_waits_past_the_module_timer_timeout(rig):
    m, fake = rig(mod_timeout=0.05)
    fake.timer_timeout_s = P.TIMER_TIMEOUT_S + 0.005  # a module at the edge of its timeout
    start = time.monotonic()
    result = m.time_pin(3)
    assert time.monotonic() - start >= P.TIMER_TIMEOUT_S
    assert result.timed_out and result.ticks == 0 and result.seconds is None
    assert str(result) == "timeout"


def test_timer_timeout_result_is_not_an_exception(rig):
    m, fake = rig()
    fake.timer_timeout_s = 0.01
    result = m.time_pin(4)
    assert result == brainstem_dio.TimerResult(4, 0)
    assert result.timed_out


def test_missing_timer_result_is_a_timeout_exception(rig):
    m, fake = rig()
    fake.timer_timeout_s = 2.0
    with pytest.raises(brainstem_dio.Timeout, match="timer result"):
        m.time_pin(4, timeout=0.05)


# ---- timers ----


def test_time_pin_ticks_and_seconds(rig):
    m, fake = rig()
    fake.timer_results[4] = 500
    result = m.time_pin(4)
    assert result.pin == 4 and result.ticks == 500 and not result.timed_out
    assert result.seconds == pytest.approx(800e-6)
    assert str(result) == "500 ticks = 800.0 us"
    # the nearest float to the exact time, as the README's example prints it
    assert repr(result.seconds) == "0.0008"
    assert all(brainstem_dio.TimerResult(4, t).seconds == t * 16 / 10_000_000 for t in (1, 3, 500, 62_500, 65_535))
    assert sent(fake, P.CMD_PTIME_RD) == [bytes([29, 0x84])]


def test_timers_on_several_pins_at_once(rig):
    m, fake = rig()
    fake.timer_delay = 0.03
    for pin in (1, 2, 3, 4):
        fake.timer_results[pin] = 100 * pin
    handles = [m.start_timer(pin) for pin in (1, 2, 3, 4)]
    assert [h.result().ticks for h in reversed(handles)] == [400, 300, 200, 100]


def test_start_timer_rflx_only_returns_no_handle(rig):
    m, fake = rig()
    fake.timer_results[1] = 5
    assert m.start_timer(1, host=False, rflx=True) is None
    assert sent(fake, P.CMD_PTIME_RD) == [bytes([29, 0x41])]


def test_module_reset_during_a_measurement(rig):
    m, fake = rig()
    fake.timer_timeout_s = 1.0
    handle = m.start_timer(3)
    fake.inject(bytes([2, 2, 0x80, 4]))
    with pytest.raises(brainstem_dio.ModuleReset):
        handle.result(timeout=1.0)


def test_wrong_device_id_base_is_a_protocol_error(rig):
    m, _fake = rig(pin_id_base=20, levels=1)
    with pytest.raises(brainstem_dio.ProtocolError, match="pin_id_base"):
        m.read(0)


def test_results_of_a_wrong_timer_id_base_go_to_the_queue(rig):
    m, fake = rig(timer_id_base=30)
    fake.timer_results[2] = 9
    handle = m.start_timer(2)
    with pytest.raises(brainstem_dio.Timeout):
        handle.result(timeout=0.05)
    assert Packet.of(2, 4, 32, 0, 9) in m.drain()


def test_concurrent_timer_waits_from_threads(rig):
    m, fake = rig()
    fake.timer_delay = 0.02
    results: dict[int, int] = {}

    def run(pin: int) -> None:
        fake.timer_results[pin] = pin * 11
        results[pin] = m.time_pin(pin).ticks

    threads = [threading.Thread(target=run, args=(p,)) for p in (1, 2, 3, 4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(5)
    assert results == {1: 11, 2: 22, 3: 33, 4: 44}
    assert wait_for(lambda: not fake.busy)


def test_a_lost_timer_start_does_not_break_the_pin(rig):
    """A PTIME_RD the module never ran (a packet to module 4 whose 8 data bytes swallow it and
    its sync echo) must not take the next measurements' results: with a pulse shorter than
    the sync echo, each result arrives before its start is confirmed."""
    m, fake = rig(mod_timeout=0.2)
    assert m.receive(1.0) == Packet.of(2, 0x80, 4)
    fake.instant_timers = True
    m.link.send_bytes(bytes([4, 8]))
    outcomes: list[object] = []
    for i in range(5):
        fake.timer_results[4] = 100 + i  # each measurement its own value
        try:
            outcomes.append(m.time_pin(4).ticks)
        except brainstem_dio.Timeout:
            outcomes.append("Timeout")
    assert outcomes[0] in ("Timeout", 100)
    assert outcomes[1:] == [101, 102, 103, 104], outcomes
    strays = [p for p in m.drain() if p.cmd == P.CMD_DEV_VAL]
    assert strays == [], strays
    assert m.link._timers == {}
