# SPDX-License-Identifier: Apache-2.0
"""The protocol constants against the contract's tables, and the packets decoded to text."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from brainstem_dio import protocol as P

REPO = Path(__file__).resolve().parents[2]
CONTRACTS = [REPO / "docs" / "PROTOCOL.md", REPO.parent / "shared" / "spec" / "PROTOCOL.md"]


def contract() -> str:
    for path in CONTRACTS:
        if path.is_file():
            return path.read_text(encoding="utf-8")
    pytest.skip("PROTOCOL.md not found beside the repository")


def sections() -> tuple[str, str]:
    text = contract()
    packets = text.split("## 2. Packets", 1)[1].split("## 3. Commands", 1)
    return packets[0], packets[1].split("## 4.", 1)[0]


def test_message_codes_match_the_contract():
    rows = re.findall(r"^\| (\d+) \| (\w+)[^|]*\|", sections()[0], re.MULTILINE)
    core = {c: n for c, n in P.MESSAGE_NAMES.items() if c != P.MSG_CMD_Q_OVERFLOW}
    assert {int(c): n for c, n in rows} == core


def test_command_codes_match_the_contract():
    rows = re.findall(r"^\| (\d+|0x[0-9A-F]+)(?: \(0x[0-9A-F]+\))? \| (cmd\w+) \|", sections()[1], re.MULTILINE)
    assert {int(c, 0): n for c, n in rows} == P.COMMAND_NAMES


def test_uart_overflow_message_is_in_the_fpga_doc():
    doc = REPO / "docs" / "fpga.md"
    if not doc.is_file():
        pytest.skip("docs/fpga.md not found")
    assert f"A, 2, 0x80, {P.MSG_CMD_Q_OVERFLOW}" in doc.read_text(encoding="utf-8")


def test_timer_constants():
    assert P.TIMER_TIMEOUT_S == pytest.approx(0.104856)
    assert P.TICK_S == pytest.approx(1.6e-6)
    assert P.HB_UNIT_S == pytest.approx(0.0256)


@pytest.mark.parametrize(
    "addr, data, text",
    [
        (2, [0x80, 4], "statePowerReset (power reset)"),
        (2, [0x80, 12], "cmdQOverflow (queue overflow)"),
        (2, [0x80, 99], "message 99 (message)"),
        (2, [0, 0], "heartbeat UP"),
        (2, [0, 1], "heartbeat DOWN"),
        (2, [26, 3, 0x1B], "pin 3 config 0x1B: input, latch on 1->0, width timer of high"),
        (2, [26, 1, 0x80], "pin 1 config 0x80: output, fixed"),
        (2, [26, 2, 0x08], "pin 2 config 0x08: output, edge timer to high"),
        (2, [4, 5, 1], "pin 0 level 1"),
        (2, [4, 14, 1, 0xF4], "pin 4 timer: 500 ticks = 800.0 us"),
        (2, [4, 11, 0, 0], "pin 1 timer: timeout"),
        (2, [], "resync reply"),
        (2, [23, 1], "echo"),
        (2, [99], ""),
    ],
)
def test_describe_module_packets(addr, data, text):
    assert P.describe(addr, data) == text


@pytest.mark.parametrize(
    "data, text",
    [
        ([26, 3], "query pin 3"),
        ([26, 1, 0], "configure pin 1: output"),
        ([27, 0x83], "read pin 3 (HOST)"),
        ([27, 0xC3], "read pin 3 (HOST+RFLX)"),
        ([27, 0x03], "read pin 3 (value discarded)"),
        ([27, 1, 5], "write pin 1 = 1"),
        ([28, 2], "re-arm pin 2"),
        ([29, 0x84], "time pin 4 (HOST)"),
        ([0, 2], "heartbeat answer 2"),
        ([23, 0xB5, 1], "echo request"),
        ([0x63], ""),
    ],
)
def test_describe_host_packets(data, text):
    assert P.describe(2, data, from_host=True) == text


def test_names():
    assert P.format_packet(2, [0x1D, 0x84]) == "02:1D,84"
    assert P.format_packet(2, [0x1D, 0x84], with_length=True) == "02:02,1D,84"
    assert P.command_code("DIG_CFG") == P.command_code("cmdDIG_CFG") == P.command_code("dig_cfg") == 26
    assert P.command_code("nope") is None
    assert P.command_name(29) == "cmdPTIME_RD" and P.command_name(99) == "command 99"
    assert P.message_name(10) == "cmdIndexErr"
