# SPDX-License-Identifier: Apache-2.0
"""The link against a fake module: resync after every kind of bad byte, the inter-byte
timeout, heartbeat answers, unsolicited packets, dead ports, URLs and threads."""

from __future__ import annotations

import os
import threading
import time
import tty

import pytest
from host_fake import FakeModule, FakeServer, FdEnd, serial_pair, wait_for

import brainstem_dio
from brainstem_dio import Packet
from brainstem_dio import protocol as P

BAD_BYTES = {
    "odd address": b"\x03",
    "zero address": b"\x00",
    "resync address from the module": b"\xad\x00",
    "length above 8": b"\x02\x09",
    "length 255": b"\x02\xff\x01\x02",
    "truncated packet": b"\x02\x03\x1a",  # then silence: the inter-byte timeout
}


def record(link: brainstem_dio.Link) -> list:
    events: list = []
    link.add_listener(events.append)
    return events


@pytest.mark.parametrize("bad", BAD_BYTES.values(), ids=BAD_BYTES.keys())
def test_resync_exchange_after_each_bad_byte_kind(rig, bad):
    m, fake = rig(link_inter_byte_timeout=0.03)
    assert m.receive(1.0) == Packet.of(2, 0x80, 4)
    events = record(m.link)
    fake.inject(bad)
    assert wait_for(lambda: m.link.stats.resyncs == 1)
    # The host flushed, sent exactly AD 00 AD 00, and accepted the two replies.
    assert fake.probes == 2
    tx = [e.raw for e in events if e.kind == "tx"]
    assert tx == [b"\xad\x00", b"\xad\x00"]
    kinds = [e.kind for e in events if e.kind != "tx"]
    assert kinds == ["framing", "resync"]
    assert m.link.stats.framing_errors == 1
    # The link goes on normally.
    assert m.query(3).output is False
    assert not m.link.resyncing
    assert m.drain() == []  # nothing of the garbage reached the queue


def test_truncated_packet_is_dropped_and_the_link_recovers(rig):
    m, fake = rig(link_inter_byte_timeout=0.03)
    m.receive(1.0)
    events = record(m.link)
    fake.inject(bytes([2, 3, 26, 3]))  # a DIG_CFG reply missing its last byte
    assert wait_for(lambda: m.link.stats.resyncs == 1)
    framing = [e for e in events if e.kind == "framing"]
    assert framing[0].note == "timeout" and framing[0].raw == bytes([2, 3, 26, 3])
    # The partial packet did not swallow the first byte of what came next.
    assert m.echo(b"\x07") == b"\x07"
    assert m.query(2) == brainstem_dio.DigCfg()


def test_without_inter_byte_timeout_a_slow_packet_completes(rig):
    m, fake = rig(link_inter_byte_timeout=None)
    m.receive(1.0)
    fake.inject(bytes([2, 3, 26]))
    time.sleep(0.15)
    fake.inject(bytes([3, 1]))
    assert m.receive(1.0) == Packet.of(2, 26, 3, 1)
    assert m.link.stats.framing_errors == 0


def test_answer_lost_in_a_framing_error_raises_resync_error(rig):
    m, fake = rig()

    def garble(addr: int, data: bytes) -> bool:
        if data[:1] == bytes([P.CMD_DIG_CFG]):
            fake.inject(b"\x01\x1a\x03\x01")  # the reply, its address byte corrupted
            return True
        return False

    fake.on_packet = garble
    start = time.monotonic()
    with pytest.raises(brainstem_dio.ResyncError):
        m.query(3, timeout=2.0)
    assert time.monotonic() - start < 1.0  # failed at the resync, not at the timeout
    fake.on_packet = None
    assert m.query(3) == brainstem_dio.DigCfg()


def test_resync_retries_when_the_probe_replies_do_not_come(rig):
    m, fake = rig(link_resync_timeout=0.05)
    events = record(m.link)
    fake.mute = True
    fake.inject(b"\x01")
    assert wait_for(lambda: m.link.stats.resync_timeouts >= 1)
    assert m.link.resyncing
    fake.mute = False
    assert wait_for(lambda: m.link.stats.resyncs == 1)
    assert "resync-timeout" in [e.kind for e in events]
    assert m.query(3) == brainstem_dio.DigCfg()


def test_garbage_for_ever_gives_a_timeout_that_says_why(rig):
    m, fake = rig(link_resync_timeout=0.05, mod_timeout=0.15)
    fake.mute = True
    stop = threading.Event()

    def noise() -> None:
        while not stop.is_set():
            fake.inject(b"\x55\x13")  # what a wrong baud rate looks like
            time.sleep(0.002)

    t = threading.Thread(target=noise, daemon=True)
    t.start()
    try:
        wait_for(lambda: m.link.resyncing)
        # Either the call waits in vain during a resync, or a new resync fails it at once.
        with pytest.raises((brainstem_dio.Timeout, brainstem_dio.ResyncError), match="framing error"):
            m.query(3)
    finally:
        stop.set()
        t.join()


# ---- heartbeats ----


def test_heartbeats_are_answered_while_the_user_sleeps(rig):
    m, fake = rig()
    stop = threading.Event()
    sent: list[tuple[int, float]] = []

    def beat() -> None:
        while not stop.wait(0.02):
            sent.append((fake.heartbeat(), time.monotonic()))

    t = threading.Thread(target=beat, daemon=True)
    t.start()
    time.sleep(0.25)  # the user's program does nothing
    stop.set()
    t.join()
    assert wait_for(lambda: len(fake.hb_answers) == len(sent))
    assert len(sent) >= 5
    assert fake.hb_answers == [kind + 2 for kind, _ in sent]
    assert fake.hb_answers[:4] == [2, 3, 2, 3]
    assert m.link.stats.heartbeats == m.link.stats.heartbeat_answers == len(sent)
    assert m.drain() == [Packet.of(2, 0x80, 4)]  # heartbeats never reach the queue


def test_heartbeat_answers_are_sent_promptly(rig):
    _m, fake = rig()
    times: list[float] = []
    fake.on_packet = lambda a, d: bool(d[:1] == b"\x00" and times.append(time.monotonic()))
    for _ in range(5):
        start = time.monotonic()
        n = len(times)
        fake.heartbeat()
        assert wait_for(lambda n=n: len(times) > n, 1.0)
        assert times[-1] - start < 0.2


def test_heartbeat_answers_can_be_switched_off(rig):
    m, fake = rig(link_answer_heartbeats=False)
    fake.heartbeat()
    assert wait_for(lambda: m.link.stats.heartbeats == 1)
    time.sleep(0.03)
    assert fake.hb_answers == []


def test_heartbeat_between_a_command_and_its_error(rig):
    m, fake = rig()

    def hb_first(addr: int, data: bytes) -> bool:
        if data == bytes([P.CMD_DIG_CFG, 9]):
            fake.heartbeat()
            fake.inject(bytes([2, 4, 4, 14, 0, 5]))  # and a timer result nobody waits for
        return False

    fake.on_packet = hb_first
    m.receive(1.0)
    with pytest.raises(brainstem_dio.CmdIndexErr):
        m.query(9)
    assert wait_for(lambda: fake.hb_answers == [2])
    assert m.receive(1.0) == Packet.of(2, 4, 14, 0, 5)


# ---- unsolicited packets ----


def test_unsolicited_packets_reach_the_queue(rig):
    m, fake = rig()
    assert m.receive(1.0) == Packet.of(2, 0x80, P.MSG_STATE_POWER_RESET)
    fake.inject(bytes([2, 2, 0x80, P.MSG_CMD_Q_OVERFLOW]))
    fake.inject(bytes([2, 4, 4, 12, 0x01, 0xF4]))  # a timer result nobody waits for
    fake.inject(bytes([4, 2, 0x80, 8]))  # another module's message
    got = [m.receive(1.0) for _ in range(3)]
    assert got == [
        Packet.of(2, 0x80, 12),
        Packet.of(2, 4, 12, 0x01, 0xF4),
        Packet.of(4, 0x80, 8),
    ]
    with pytest.raises(brainstem_dio.Timeout):
        m.receive(0.02)


def test_unsolicited_callback_instead_of_the_queue():
    host, dev = serial_pair()
    got: list[Packet] = []
    m = brainstem_dio.open(host, on_unsolicited=got.append)
    fake = FakeModule(dev).start()
    try:
        fake.inject(bytes([2, 2, 0x80, 12]))
        assert wait_for(lambda: len(got) == 2)
        assert got == [Packet.of(2, 0x80, 4), Packet.of(2, 0x80, 12)]
        assert m.drain() == []
    finally:
        m.close()
        fake.stop()


def test_queue_is_bounded_and_counts_what_it_dropped(rig):
    m, fake = rig(link_unsolicited_maxlen=3)
    for i in range(6):
        fake.inject(bytes([2, 2, 0x80, 12]))
    assert wait_for(lambda: m.link.stats.unsolicited == 7)
    assert len(m.drain()) == 3
    assert m.link.stats.unsolicited_dropped == 4


def test_late_timer_result_goes_to_the_queue(rig):
    m, fake = rig()
    m.receive(1.0)
    fake.timer_results[4] = 500
    fake.timer_delay = 0.15
    handle = m.start_timer(4)
    with pytest.raises(brainstem_dio.Timeout):
        handle.result(timeout=0.02)
    assert m.receive(1.0) == Packet.of(2, 4, 14, 0x01, 0xF4)
    # The pin's next measurement gets its own result.
    fake.timer_delay = 0.001
    fake.timer_results[4] = 7
    assert m.time_pin(4).ticks == 7


# ---- dead ports, URLs ----


def test_no_hang_when_the_port_goes_away(rig):
    m, fake = rig(mod_timeout=5.0)
    fake.mute = True
    result: list[BaseException] = []

    def call() -> None:
        try:
            m.query(3)
        except BaseException as exc:  # noqa: BLE001 - the thread hands whatever it raised to the test
            result.append(exc)

    t = threading.Thread(target=call)
    t.start()
    time.sleep(0.05)
    start = time.monotonic()
    fake.port.close()
    t.join(2.0)
    assert not t.is_alive()
    assert time.monotonic() - start < 1.0
    assert isinstance(result[0], brainstem_dio.LinkError)
    assert not m.link.is_open
    with pytest.raises(brainstem_dio.LinkError, match="port failed"):
        m.query(3)


def test_no_answer_at_all_is_a_timeout_that_says_so():
    host, dev = serial_pair()
    dev.timeout = 0.01
    with brainstem_dio.open(host, timeout=0.05) as m:
        start = time.monotonic()
        with pytest.raises(brainstem_dio.Timeout, match="nothing at all was received") as info:
            m.echo()
        assert isinstance(info.value, TimeoutError)
        assert time.monotonic() - start < 0.5
        with pytest.raises(brainstem_dio.Timeout):
            m.configure(1, output=True)


def test_a_port_that_does_not_exist():
    with pytest.raises(brainstem_dio.PortError, match="No such file"):
        brainstem_dio.open("/dev/brainstem-dio-does-not-exist")


def test_closed_link_refuses_calls(rig):
    m, _fake = rig()
    m.close()
    with pytest.raises(brainstem_dio.LinkError, match="closed"):
        m.query(1)


def test_loop_url():
    # loop:// sends the host's bytes back: a cmdDEBUG echo is its own answer.
    with brainstem_dio.open("loop://", timeout=0.5) as m:
        assert m.echo(b"\x01\x02") == b"\x01\x02"
        # A request collects what comes back before its sync echo: here the packet itself.
        assert m.request([26, 1, 0]) == [Packet.of(2, 26, 1, 0)]


def test_socket_url():
    server = FakeServer(levels=0b1)
    try:
        with brainstem_dio.open(server.url) as m:
            assert m.read(0) == 1
            assert m.query(3) == brainstem_dio.DigCfg()
    finally:
        server.close()


def test_pty_device_path():
    master, slave = os.openpty()
    tty.setraw(slave)
    path = os.ttyname(slave)
    fake = FakeModule(FdEnd(master), levels=0b10000)
    try:
        with brainstem_dio.open(path) as m:
            fake.start()
            assert m.read(4) == 1
            fake.heartbeat()
            assert wait_for(lambda: fake.hb_answers == [2])
    finally:
        fake.stop()
        os.close(slave)
        fake.port.close()


# ---- threads ----


def test_calls_from_several_threads_are_attributed(rig):
    m, _fake = rig(levels=0b00101)
    m.configure(1, output=True)
    errors: list[str] = []

    def worker(k: int) -> None:
        for i in range(15):
            try:
                pin = (k + i) % 7
                if pin >= 5:
                    with pytest.raises(brainstem_dio.CmdIndexErr) as info:
                        m.query(pin)
                    assert info.value.command == bytes([26, pin])
                elif pin == 1:
                    with pytest.raises(brainstem_dio.CmdIndexErr) as info:
                        m.read(1)  # an output
                    assert info.value.command == bytes([27, 0x81])
                    m.write(1, i & 1)
                else:
                    assert m.read(pin) == (0b00101 >> pin) & 1
                    with pytest.raises(brainstem_dio.CmdIndexErr):
                        m.write(pin, 1)  # an input
            except BaseException as exc:  # noqa: BLE001 - the thread hands whatever it raised to the test
                errors.append(f"thread {k} step {i}: {exc!r}")

    threads = [threading.Thread(target=worker, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(10)
    assert errors == []


def test_blocking_call_from_a_callback_is_refused(rig):
    m, fake = rig()
    seen: list[BaseException] = []

    def listener(ev: brainstem_dio.LinkEvent) -> None:
        if ev.kind == "rx" and ev.note == "heartbeat":
            try:
                m.query(3)
            except RuntimeError as exc:
                seen.append(exc)

    m.link.add_listener(listener)
    fake.heartbeat()
    assert wait_for(lambda: seen)
    m.link.remove_listener(listener)
    assert m.query(3) == brainstem_dio.DigCfg()


def test_listener_sees_both_directions_and_marks_the_sync_echo(rig):
    m, _fake = rig()
    m.receive(1.0)
    events = record(m.link)
    m.configure(2, output=True)
    assert wait_for(lambda: len([e for e in events if e.kind == "rx"]) == 1)
    tx = [(str(e.packet), e.internal) for e in events if e.kind == "tx"]
    assert tx[0] == ("02:1A,02,00", False)
    assert tx[1][1] is True and tx[1][0].startswith("02:17,B5,")
    rx = [e for e in events if e.kind == "rx"]
    assert rx[0].internal and rx[0].packet.data[:2] == bytes([23, 0xB5])


def test_input_waiting_at_open_is_flushed():
    host, dev = serial_pair()
    fake = FakeModule(dev).start()  # its power-up message waits on the line
    assert wait_for(lambda: host.in_waiting == 4)
    try:
        with brainstem_dio.open(host) as m:
            assert m.query(1) == brainstem_dio.DigCfg()
            assert m.drain() == []
    finally:
        fake.stop()


def test_writes_pause_after_cmd_q_overflow(rig):
    # The module lost bytes: let its parser drop any partial packet (RX_TIMEOUT, 25.6 ms)
    # before the next command goes out.
    m, fake = rig()
    fake.inject(bytes([2, 2, 0x80, P.MSG_CMD_Q_OVERFLOW]))
    m.receive(1.0)
    assert m.receive(1.0) == Packet.of(2, 0x80, 12)
    start = time.monotonic()
    m.query(1)
    assert time.monotonic() - start >= P.DEFAULT_RX_TIMEOUT_US * 1e-6
