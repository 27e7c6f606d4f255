# SPDX-License-Identifier: Apache-2.0
"""Every reply is checked against the contract (PROTOCOL.md §2, §3) before it is decoded: a
reply that does not fit raises ProtocolError naming its bytes, and the next call syncs first."""

from __future__ import annotations

import pytest

import brainstem_dio
from brainstem_dio import DigCfg
from brainstem_dio import protocol as P


def answer_once(fake, cmd: int, raw: bytes) -> None:
    """The module's next packet with command `cmd` is answered with `raw` instead."""
    used: list[bool] = []

    def hook(addr: int, data: bytes) -> bool:
        if addr == fake.addr and data[:1] == bytes([cmd]) and not used:
            used.append(True)
            fake.inject(raw)
            return True
        return False

    fake.on_packet = hook


BAD_REPLIES = [
    # (call, the reply sent instead, the bytes named, the reason)
    ("read level 17", lambda m: m.read(0), P.CMD_DIG_IO, bytes([2, 3, 4, 5, 17]), "02 03 04 05 11", "level 17"),
    ("read level 128", lambda m: m.read(0), P.CMD_DIG_IO, bytes([2, 3, 4, 5, 128]), "02 03 04 05 80", "level 128"),
    ("read another pin", lambda m: m.read(0), P.CMD_DIG_IO, bytes([2, 3, 4, 6, 1]), "02 03 04 06 01", "device ID 6"),
    ("query bit 5", lambda m: m.query(3), P.CMD_DIG_CFG, bytes([2, 3, 26, 3, 0x21]), "02 03 1A 03 21", "reserved bits"),
    ("query bit 6", lambda m: m.query(3), P.CMD_DIG_CFG, bytes([2, 3, 26, 3, 0x41]), "02 03 1A 03 41", "reserved bits"),
    ("query another pin", lambda m: m.query(3), P.CMD_DIG_CFG, bytes([2, 3, 26, 4, 0x01]), "02 03 1A 04 01", "pin 4"),
    ("unknown message", lambda m: m.query(3), P.CMD_DIG_CFG, bytes([2, 2, 0x80, 77]), "02 02 80 4D", "code 77"),
    ("write gets message 0", lambda m: m.write(1, 1), P.CMD_DIG_IO, bytes([2, 2, 0x80, 0]), "02 02 80 00", "code 0"),
]


@pytest.mark.parametrize("call, cmd, raw, named, why", [b[1:] for b in BAD_REPLIES], ids=[b[0] for b in BAD_REPLIES])
def test_a_reply_that_breaks_the_contract_is_a_protocol_error(rig, call, cmd, raw, named, why):
    m, fake = rig()
    answer_once(fake, cmd, raw)
    with pytest.raises(brainstem_dio.ProtocolError, match=why) as info:
        call(m)
    assert named in str(info.value)
    # The next call syncs first and gets its own answer.
    echoes = len(fake.packets_with(P.CMD_DEBUG))
    assert m.query(2) == DigCfg()
    assert len(fake.packets_with(P.CMD_DEBUG)) == echoes + 1


@pytest.mark.parametrize("level", [0, 1])
def test_levels_0_and_1_pass(rig, level):
    m, fake = rig(levels=level)
    assert m.read(0) == level


def test_fixed_may_not_appear_on_a_pin_seen_without_it(rig):
    m, fake = rig()
    assert m.query(3) == DigCfg()
    answer_once(fake, P.CMD_DIG_CFG, bytes([2, 3, 26, 3, 0x81]))
    with pytest.raises(brainstem_dio.ProtocolError, match="FIXED is 1, but it was 0") as info:
        m.query(3)
    assert "02 03 1A 03 81" in str(info.value)
    assert m.query(3) == DigCfg()


def test_fixed_may_not_vanish_from_a_fixed_pin(rig):
    m, fake = rig(fixed={0: 0x01})
    assert m.query(0) == DigCfg(fixed=True)
    assert m.query(0) == DigCfg(fixed=True)  # stable: fine
    answer_once(fake, P.CMD_DIG_CFG, bytes([2, 3, 26, 0, 0x01]))
    with pytest.raises(brainstem_dio.ProtocolError, match="FIXED is 0, but it was 1"):
        m.query(0)
    assert m.query(0) == DigCfg(fixed=True)


def test_fixed_is_remembered_per_pin(rig):
    m, fake = rig(fixed={0: 0x01})
    assert m.query(0).fixed and not m.query(1).fixed


def test_a_message_a_command_cannot_cause_is_raised_by_request(rig):
    m, fake = rig()
    answer_once(fake, P.CMD_DIG_RST, bytes([2, 2, 0x80, 3]))
    with pytest.raises(brainstem_dio.ProtocolError, match="02 02 80 03"):
        m.request([P.CMD_DIG_RST, 1])
    m.request([P.CMD_DIG_RST, 1])
