# SPDX-License-Identifier: Apache-2.0
"""FrameParser: the host's packet framing and resync state machine, with made-up times."""

from __future__ import annotations

import pytest

from brainstem_dio.framing import FrameParser, FramingError, Packet, Resynced, ResyncTimeout, State

A = 2
SYNC = bytes([A, 0, A, 0])


def packets(events):
    return [e for e in events if isinstance(e, Packet)]


def feed_all(parser: FrameParser, chunks, t: float = 0.0):
    events = []
    for chunk in chunks:
        events += parser.feed(bytes(chunk), t)
    return events


GOOD = [
    Packet.of(2, 0x80, 4),
    Packet.of(2),  # N = 0: a probe reply
    Packet.of(2, 26, 3, 1),
    Packet.of(2, 4, 14, 1, 0xF4),
    Packet.of(254, 23, 1, 2, 3, 4, 5, 6, 7),  # N = 8, the longest
    Packet.of(4, 0, 1),
]


def test_good_packets_back_to_back():
    parser = FrameParser(A)
    wire = b"".join(p.to_bytes() for p in GOOD)
    events = parser.feed(wire, 1.0)
    assert events == GOOD
    assert all(e.time == 1.0 for e in events)
    assert parser.state is State.ADDRESS


@pytest.mark.parametrize("cut", range(1, sum(len(p.to_bytes()) for p in GOOD)))
def test_good_packets_split_anywhere(cut):
    parser = FrameParser(A)
    wire = b"".join(p.to_bytes() for p in GOOD)
    assert feed_all(parser, [wire[:cut], wire[cut:]]) == GOOD


def test_byte_by_byte():
    parser = FrameParser(A)
    wire = b"".join(p.to_bytes() for p in GOOD)
    assert feed_all(parser, [[b] for b in wire]) == GOOD


@pytest.mark.parametrize("bad", [0] + list(range(1, 256, 2)))
def test_first_byte_odd_or_zero_is_a_framing_error(bad):
    parser = FrameParser(A)
    events = parser.feed(bytes([bad, 2, 26, 3]), 5.0)
    assert events == [FramingError("address", bytes([bad]), 5.0)]
    assert parser.state is State.FLUSH  # the rest is discarded until the probes are sent


@pytest.mark.parametrize("n", range(9, 256))
def test_length_above_8_is_a_framing_error(n):
    parser = FrameParser(A)
    events = parser.feed(bytes([A, n, 1, 2]), 0.0)
    assert events == [FramingError("length", bytes([A, n]), 0.0)]


def test_framing_error_after_good_packets_keeps_them():
    parser = FrameParser(A)
    events = parser.feed(Packet.of(2, 26, 3, 1).to_bytes() + b"\x03", 0.0)
    assert events[0] == Packet.of(2, 26, 3, 1)
    assert isinstance(events[1], FramingError)


def hunt(parser: FrameParser, t: float = 0.0) -> None:
    parser.feed(b"\x01", t)  # a framing error
    assert parser.state is State.FLUSH
    parser.probes_sent(t)
    assert parser.state is State.HUNT


@pytest.mark.parametrize(
    "noise",
    [b"", b"\x02\x00\x02", b"\x02\x02\x00\x00", b"\x02\x00\x04\x00", b"\xff" * 40, b"\x02\x09\x01"],
)
def test_resync_accepts_only_the_two_probe_replies(noise):
    parser = FrameParser(A)
    hunt(parser)
    after = Packet.of(2, 26, 3, 1)
    events = parser.feed(noise + SYNC + after.to_bytes(), 0.1)
    assert isinstance(events[0], Resynced)
    assert events[0].discarded == len(noise)
    assert events[1:] == [after]


def test_resync_after_an_early_probe_reply_leaves_an_empty_packet():
    # `A 00` before the two replies (e.g. a user's own probe): the first four bytes match,
    # the last reply is then parsed as an ordinary N = 0 packet.
    parser = FrameParser(A)
    hunt(parser)
    events = parser.feed(bytes([A, 0]) + SYNC, 0.1)
    assert events == [Resynced(0.1, 0), Packet.of(A)]


@pytest.mark.parametrize("cut", range(1, 4))
def test_resync_pattern_split_across_reads(cut):
    parser = FrameParser(A)
    hunt(parser)
    assert parser.feed(b"\x55" + SYNC[:cut], 0.0) == []
    events = parser.feed(SYNC[cut:], 0.0)
    assert events == [Resynced(0.0, 1)]
    assert parser.state is State.ADDRESS


def test_resync_ignores_another_modules_replies():
    parser = FrameParser(A)
    hunt(parser)
    assert parser.feed(bytes([4, 0, 4, 0]), 0.0) == []
    assert parser.state is State.HUNT


def test_bytes_before_the_probes_are_discarded():
    parser = FrameParser(A)
    parser.feed(b"\x01", 0.0)
    assert parser.feed(SYNC, 0.0) == []  # the replies cannot be ours yet
    parser.probes_sent(0.1)
    events = parser.feed(SYNC, 0.2)
    assert isinstance(events[0], Resynced)


def test_resync_timeout_and_retry():
    parser = FrameParser(A, resync_timeout=0.25)
    hunt(parser, 10.0)
    assert parser.poll(10.2) == []
    assert parser.poll(10.25) == [ResyncTimeout(10.25)]
    assert parser.state is State.FLUSH
    parser.probes_sent(10.3)
    assert isinstance(parser.feed(SYNC, 10.31)[0], Resynced)


def test_inter_byte_timeout_drops_a_partial_packet():
    parser = FrameParser(A, inter_byte_timeout=0.1)
    assert parser.feed(bytes([A, 3, 26]), 1.0) == []
    assert parser.poll(1.099) == []
    assert parser.poll(1.101) == [FramingError("timeout", bytes([A, 3, 26]), 1.101)]
    assert parser.state is State.FLUSH


def test_inter_byte_timeout_counts_from_the_last_byte():
    parser = FrameParser(A, inter_byte_timeout=0.1)
    parser.feed(bytes([A]), 0.0)
    parser.feed(bytes([3]), 0.09)
    parser.feed(bytes([26]), 0.18)
    assert parser.poll(0.27) == []
    assert parser.feed(bytes([3, 1]), 0.27) == [Packet.of(A, 26, 3, 1)]


def test_a_late_byte_ends_the_partial_packet_first():
    parser = FrameParser(A, inter_byte_timeout=0.1)
    parser.feed(bytes([A, 3]), 0.0)
    events = parser.feed(bytes([26, 3, 1]), 0.5)  # the reader was late to look
    assert events == [FramingError("timeout", bytes([A, 3]), 0.5)]


def test_no_inter_byte_timeout_when_disabled():
    parser = FrameParser(A, inter_byte_timeout=None)
    parser.feed(bytes([A, 3, 26]), 0.0)
    assert parser.poll(1000.0) == []
    assert parser.feed(bytes([3, 1]), 1000.0) == [Packet.of(A, 26, 3, 1)]


def test_idle_parser_never_times_out():
    parser = FrameParser(A, inter_byte_timeout=0.1)
    assert parser.poll(1e6) == []


@pytest.mark.parametrize("addr", [0, 1, 0xAD, 256])
def test_resync_address_must_be_a_module_address(addr):
    with pytest.raises(ValueError):
        FrameParser(addr)


def test_packet_helpers():
    p = Packet.of(2, 0x80, 10, time=3.0)
    assert p.is_message and p.message_code == 10 and not p.is_heartbeat
    assert p == Packet.of(2, 0x80, 10)  # time takes no part in comparisons
    assert str(p) == "02:80,0A"
    assert p.to_bytes() == b"\x02\x02\x80\x0a"
    assert Packet.of(2, 0, 1).is_heartbeat and not Packet.of(2, 0, 3).is_heartbeat
    assert Packet.of(2).cmd is None and Packet.of(2).n == 0
