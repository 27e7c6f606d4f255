# SPDX-License-Identifier: Apache-2.0
"""Timer-result attribution (brainstem_dio.link): a result goes only to a wait whose start the
module confirmed, and a confirmed start leaves no stale wait ahead of it on its timer. The
fake module is scripted through `on_packet` to stage each order of events on the line."""

from __future__ import annotations

import threading
import time

import pytest

import brainstem_dio
from brainstem_dio import Packet
from brainstem_dio import protocol as P


def result(pin: int, ticks: int) -> bytes:
    return bytes([2, 4, P.CMD_DEV_VAL, 10 + pin, ticks >> 8, ticks & 0xFF])


def script(fake, on_ptime):
    """Hand the fake's n-th PTIME_RD (n from 1) to `on_ptime(n)`; it returns True if it dealt
    with it. A PTIME_RD it swallows takes its sync echo along (a packet that never arrived)."""
    state = {"n": 0, "swallow_echo": False}

    def hook(addr: int, data: bytes) -> bool:
        if data[:1] == bytes([P.CMD_PTIME_RD]):
            state["n"] += 1
            handled = on_ptime(state["n"])
            if handled == "lost":
                state["swallow_echo"] = True
            return bool(handled)
        if data[:2] == bytes([P.CMD_DEBUG, 0xB5]) and state["swallow_echo"]:
            state["swallow_echo"] = False
            return True
        return False

    fake.on_packet = hook


def lose_first_start(m) -> None:
    with pytest.raises(brainstem_dio.Timeout):
        m.start_timer(3, timeout=0.1)


def test_a_held_result_of_an_unconfirmed_start_is_not_the_next_ones(rig):
    """The first PTIME_RD did run (only its echo was lost); its result A leaves after the second
    PTIME_RD was written, before that one's echo; the second measurement's result B comes
    after the echo. B is the second's; A goes to the queue."""
    m, fake = rig()
    m.receive(1.0)

    def on_ptime(n: int):
        if n == 1:
            return "lost"
        fake.inject(result(3, 0xA))
        threading.Timer(0.03, fake.inject, (result(3, 0xB),)).start()
        return True

    script(fake, on_ptime)
    lose_first_start(m)
    handle = m.start_timer(3)
    assert handle.result().ticks == 0xB
    assert m.drain() == [Packet.of(2, 4, 13, 0, 0xA)]
    assert m.link._timers == {}


def test_a_held_result_is_the_new_starts_when_nothing_follows(rig):
    """As above, but the first PTIME_RD never ran: A is the second measurement's. The library
    can know that only once no other result has come within the timer timeout."""
    m, fake = rig()
    m.receive(1.0)

    def on_ptime(n: int):
        if n == 1:
            return "lost"
        fake.inject(result(3, 0xA))
        return True

    script(fake, on_ptime)
    lose_first_start(m)
    handle = m.start_timer(3)
    confirmed = time.monotonic()
    assert not handle.done()
    assert handle.result().ticks == 0xA
    assert time.monotonic() - confirmed >= P.TIMER_TIMEOUT_S
    assert m.drain() == []
    assert m.link._timers == {}


def test_a_held_result_without_an_unconfirmed_start_ahead_is_given_at_once(rig):
    m, fake = rig()
    fake.timer_results[3] = 0x42
    fake.instant_timers = True
    start = time.monotonic()
    assert m.time_pin(3).ticks == 0x42
    assert time.monotonic() - start < P.TIMER_TIMEOUT_S


def test_a_confirmed_wait_whose_result_was_lost_fails_at_the_next_confirmed_start(rig):
    m, fake = rig()
    script(fake, lambda n: n == 1)  # the first runs, but its result is lost on the line
    first = m.start_timer(3)
    fake.timer_results[3] = 9
    second = m.start_timer(3)
    with pytest.raises(brainstem_dio.ProtocolError, match="was lost"):
        first.result(timeout=1.0)
    assert second.result().ticks == 9


def test_a_result_held_for_a_start_refused_with_tmr_conflict_goes_to_the_queue(rig):
    m, fake = rig()
    m.receive(1.0)

    def on_ptime(n: int):
        if n == 1:
            return "lost"
        fake.inject(result(3, 0xA))
        fake.inject(bytes([2, 2, 0x80, P.MSG_TMR_CONFLICT]))
        return True

    script(fake, on_ptime)
    lose_first_start(m)
    with pytest.raises(brainstem_dio.TmrConflict):
        m.start_timer(3)
    assert m.receive(1.0) == Packet.of(2, 4, 13, 0, 0xA)


def test_a_result_lost_on_the_line_does_not_break_the_pin(rig):
    """A confirmed measurement whose result never arrives (a corrupted packet) times out; the
    next measurements' results, each before its start is confirmed, are theirs."""
    m, fake = rig(mod_timeout=0.2)
    fake.instant_timers = True
    script(fake, lambda n: n == 1)  # the first runs, its result is lost on the line
    with pytest.raises(brainstem_dio.Timeout, match="timer result"):
        m.time_pin(3)
    ticks = []
    for i in range(3):
        fake.timer_results[3] = 20 + i
        ticks.append(m.time_pin(3).ticks)
    assert ticks == [20, 21, 22]
    assert m.link._timers == {}


def test_a_late_result_of_a_given_up_wait_is_not_the_next_ones(rig):
    """The first result comes after its wait gave up, while the next start is unconfirmed;
    the next measurement's result follows its confirmation."""
    m, fake = rig()
    m.receive(1.0)

    def on_ptime(n: int):
        if n == 2:
            fake.inject(result(3, 0xA))  # the first's, late
            threading.Timer(0.03, fake.inject, (result(3, 0xB),)).start()
        return True

    script(fake, on_ptime)
    first = m.start_timer(3)
    with pytest.raises(brainstem_dio.Timeout):
        first.result(timeout=0.01)
    second = m.start_timer(3)
    assert second.result().ticks == 0xB
    assert m.drain() == [Packet.of(2, 4, 13, 0, 0xA)]
