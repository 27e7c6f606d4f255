# SPDX-License-Identifier: Apache-2.0
"""cmdRESET from the host: Module.reset() waits for the power-up message and fails every call
still waiting on the module with ModuleReset; the fake module's cmdRESET."""

from __future__ import annotations

import threading
import time

import pytest

import brainstem_dio
from brainstem_dio import DigCfg, Packet
from brainstem_dio import protocol as P
from host_fake import wait_for


@pytest.fixture
def mod(rig):
    """(module, fake) once the fake's own power-up message is in: a power-up message that
    arrives while a reset is awaited is that reset's answer."""
    m, fake = rig()
    assert m.receive(1.0) == Packet.of(2, 0x80, 4)
    return m, fake


def test_reset_returns_the_module_to_its_power_up_state(mod):
    m, fake = mod
    m.configure(1, output=True)
    m.write(1, 1)
    m.configure(2, latch=True)
    m.reset()
    assert fake.resets == 1 and fake.packets_with(P.CMD_RESET) == [bytes([24])]
    assert [m.query(p) for p in range(5)] == [DigCfg()] * 5
    assert fake.out_latch == [0] * 5
    assert m.drain() == []  # the power-up message was the call's answer, not unsolicited


def test_reset_fails_a_running_measurement(mod):
    m, fake = mod
    fake.timer_timeout_s = 2.0  # no result before the reset
    handle = m.start_timer(3)
    m.reset()
    with pytest.raises(brainstem_dio.ModuleReset):
        handle.result(timeout=0.1)
    assert not fake.busy and m.link._timers == {}
    fake.timer_results[3] = 5
    assert m.time_pin(3).ticks == 5  # the timer is free again


def test_reset_fails_a_reply_still_awaited_in_another_thread(mod):
    m, fake = mod
    fake.on_packet = lambda addr, data: data[:1] == bytes([P.CMD_DIG_CFG])  # never answered
    outcome: list[BaseException] = []

    def query() -> None:
        try:
            m.query(3, timeout=5.0)
        except brainstem_dio.BrainStemError as exc:
            outcome.append(exc)

    thread = threading.Thread(target=query)
    thread.start()
    assert wait_for(lambda: fake.packets_with(P.CMD_DIG_CFG))
    start = time.monotonic()
    m.reset()
    thread.join(2.0)
    assert len(outcome) == 1 and isinstance(outcome[0], brainstem_dio.ModuleReset), outcome
    assert "query pin 3" in str(outcome[0])
    assert time.monotonic() - start < 1.0


def test_reset_fails_pending_commands_once(mod):
    m, fake = mod
    swallow = [True]

    def hook(addr: int, data: bytes) -> bool:
        if data[:2] == bytes([P.CMD_DEBUG, 0xB5]) and swallow:
            swallow.clear()
            return True  # the rearm's echo never comes
        return False

    fake.on_packet = hook
    pend = m.rearm(1, wait=False)
    assert pend is not None
    m.reset()
    assert pend.done()
    with pytest.raises(brainstem_dio.ModuleReset):
        pend.result()
    m.sync()  # not raised again


def test_reset_of_a_module_without_cmd_reset(mod):
    m, fake = mod
    fake.knows_reset = False
    with pytest.raises(brainstem_dio.CmdInvalid):
        m.reset()
    assert m.echo(b"\x01") == b"\x01"


def test_reset_needs_no_sync_after_a_timeout(mod):
    """A module that answers nothing but cmdRESET (and sends a stray late message) can still
    be reset after a call timed out."""
    m, fake = mod

    def hook(addr: int, data: bytes) -> bool:
        if data[:1] == bytes([P.CMD_RESET]):
            fake.inject(bytes([2, 2, 0x80, P.MSG_TMR_CONFLICT]))  # a late answer, then the reset
            return False
        return True  # nothing else is answered

    fake.on_packet = hook
    with pytest.raises(brainstem_dio.Timeout):
        m.query(3, timeout=0.02)
    m.reset(timeout=1.0)
    assert fake.resets == 1
    assert m.receive(1.0) == Packet.of(2, 0x80, P.MSG_TMR_CONFLICT)
    fake.on_packet = None
    echoes = len(fake.packets_with(P.CMD_DEBUG))
    assert m.query(3) == DigCfg()
    assert len(fake.packets_with(P.CMD_DEBUG)) == echoes  # no sync first: nothing late can come


def test_reset_without_an_answer_is_a_timeout(mod):
    m, fake = mod
    fake.mute = True
    with pytest.raises(brainstem_dio.Timeout, match="reset"):
        m.reset(timeout=0.05)


def test_reset_is_taken_with_any_n(mod):
    """cmdRESET ignores the bytes after the code (N 1..8), and is never cmdTooLong."""
    m, fake = mod
    for n in range(1, 9):
        m.send(bytes([P.CMD_RESET]) + bytes(range(1, n)))
        assert m.receive(1.0) == Packet.of(2, 0x80, 4)
    m.sync()
    assert fake.resets == 8 and m.drain() == []


def test_a_power_up_message_nobody_asked_for_still_goes_to_the_queue(mod):
    m, fake = mod
    fake.inject(bytes([2, 2, 0x80, 4]))
    assert m.receive(1.0) == Packet.of(2, 0x80, 4)
    assert m.query(3) == DigCfg()

