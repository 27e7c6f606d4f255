# SPDX-License-Identifier: Apache-2.0
"""Protocol constants of the BrainStem 1.0 packet link (docs/PROTOCOL.md) and their names.

Every protocol number the host library uses lives in this module, so that the constants
section can later be replaced by the module generated from the project's one protocol table
(`tools/protocol.toml`). The constant names follow that table's naming rule
(`cmdDIG_CFG` -> `CMD_DIG_CFG`, `statePowerReset` -> `MSG_STATE_POWER_RESET`), and DIGCFG /
DEVCODE bits are masks.

The second half decodes packets to text in the style of the project's session transcript.
"""

from __future__ import annotations

from typing import Sequence

# --- constants ------------------------------------------------------------------------------
# Generated from the project's one protocol table (tools/protocol.toml); see that file.
from ._protocol_table import (  # noqa: E402,F401  (re-exported: the library's constants)
    ADDR_RESYNC, CMD_DEBUG, CMD_DEV_VAL, CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST, CMD_HB, CMD_MSG,
    CMD_MAX_N, CMD_MIN_N, CMD_PTIME_RD, CMD_RESET, COMMANDS, DEFAULT_MODULE_ADDR, DEFAULT_NUM_PINS,
    DEFAULT_PIN_ID_BASE, DEFAULT_RX_TIMEOUT_US, DEFAULT_TIMER_ID_BASE, DEFAULT_TIMER_MASK,
    DEFAULT_TRANS_ID_BASE, DEV_ID_LIMIT, DEVCODE_HOST, DEVCODE_PIN, DEVCODE_RFLX, DIGCFG_ENA,
    DIGCFG_FIXED, DIGCFG_IODIR, DIGCFG_RESET, DIGCFG_STORED, DIGCFG_TMODE, DIGCFG_TRG,
    DIGCFG_TSTATE, HB_ANSWER_OFFSET, HB_DOWN, HB_UNIT_TICKS, HB_UP, MAX_N, MESSAGE_TEXT,
    MESSAGES, MSG_CMD_INDEX_ERR, MSG_CMD_INVALID, MSG_CMD_Q_OVERFLOW, MSG_CMD_TOO_LONG,
    MSG_CMD_TOO_SHORT, MSG_CONFIG_ERR, MSG_N, MSG_SERIAL_ERROR, MSG_STATE_POWER_RESET,
    MSG_TMR_CONFLICT, TICK_HZ, TIMER_MAX_TICKS,
)

# --- derived values --------------------------------------------------------------------------

TICK_S = 1.0 / TICK_HZ
TIMER_TIMEOUT_S = TIMER_MAX_TICKS * TICK_S  # 104.856 ms
HB_UNIT_S = HB_UNIT_TICKS * TICK_S  # 25.6 ms
# DIGCFG bits 6:5: always 0 in a reply (§3), every bit that is neither FIXED nor stored.
DIGCFG_RESERVED = 0xFF & ~(DIGCFG_FIXED | DIGCFG_STORED)


COMMAND_NAMES = COMMANDS

MESSAGE_NAMES = MESSAGES

# Messages a command can cause (PROTOCOL.md §2). The others arrive on their own.
COMMAND_MESSAGES = frozenset(
    {
        MSG_CMD_INVALID,
        MSG_CMD_TOO_LONG,
        MSG_CMD_INDEX_ERR,
        MSG_TMR_CONFLICT,
        MSG_CMD_TOO_SHORT,
        MSG_SERIAL_ERROR,
        MSG_CONFIG_ERR,
    }
)
UNSOLICITED_MESSAGES = frozenset({MSG_STATE_POWER_RESET, MSG_CMD_Q_OVERFLOW})


# --- names -----------------------------------------------------------------------------------


def message_name(code: int) -> str:
    """The contract's name of a message code (`cmdIndexErr`), or `message N`."""
    return MESSAGE_NAMES.get(code, f"message {code}")


def command_name(code: int) -> str:
    """The contract's name of a command code (`cmdDIG_CFG`), or `command N`."""
    return COMMAND_NAMES.get(code, f"command {code}")


def command_code(name: str) -> int | None:
    """A command code from its name, with or without `cmd`, any case: `DIG_CFG` -> 26."""
    key = name.strip().lower()
    for code, full in COMMAND_NAMES.items():
        if key in (full.lower(), full[3:].lower()):
            return code
    return None


# --- decoding to text -------------------------------------------------------------------------


def format_packet(addr: int, data: Sequence[int], with_length: bool = False) -> str:
    """Console style: `02:1A,03,01` (address, then the data bytes; `with_length` adds N)."""
    body = ([len(data)] if with_length else []) + list(data)
    return f"{addr:02X}:" + ",".join(f"{b:02X}" for b in body)


def describe_digcfg(value: int) -> str:
    """A DIGCFG byte in words: `input, latch on 0->1, width timer of high`."""
    parts = ["input" if value & DIGCFG_IODIR else "output"]
    if value & DIGCFG_ENA:
        parts.append("latch on " + ("0->1" if value & DIGCFG_TRG else "1->0"))
    if value & DIGCFG_TMODE:
        parts.append("width timer of " + ("high" if value & DIGCFG_TSTATE else "low"))
    elif value & DIGCFG_TSTATE:
        parts.append("edge timer to high")
    if value & DIGCFG_FIXED:
        parts.append("fixed")
    return ", ".join(parts)


def ticks_text(ticks: int) -> str:
    """A timer result in words: `500 ticks = 800.0 us`, or `timeout` for 0."""
    if ticks == 0:
        return "timeout"
    return f"{ticks} ticks = {ticks * TICK_S * 1e6:.1f} us"


def describe(
    addr: int,
    data: Sequence[int],
    *,
    from_host: bool = False,
    pin_id_base: int = DEFAULT_PIN_ID_BASE,
    timer_id_base: int = DEFAULT_TIMER_ID_BASE,
) -> str:
    """What a packet means, in words ('' when there is nothing to add to its bytes).

    `from_host` selects the host -> module reading of the command codes."""
    n = len(data)
    if n == 0:
        return "resync probe" if addr == ADDR_RESYNC else ("" if from_host else "resync reply")
    cmd = data[0]
    if from_host:
        return _describe_host(data, pin_id_base)
    if cmd == CMD_MSG and n == MSG_N:
        return message_name(data[1]) + f" ({MESSAGE_TEXT.get(data[1], 'message')})"
    if cmd == CMD_HB and n == 2:
        return {HB_UP: "heartbeat UP", HB_DOWN: "heartbeat DOWN"}.get(data[1], f"heartbeat {data[1]}")
    if cmd == CMD_DIG_CFG and n == 3:
        return f"pin {data[1]} config 0x{data[2]:02X}: {describe_digcfg(data[2])}"
    if cmd == CMD_DEV_VAL and n == 3:
        return f"pin {data[1] - pin_id_base} level {data[2]}"
    if cmd == CMD_DEV_VAL and n == 4:
        return f"pin {data[1] - timer_id_base} timer: {ticks_text(data[2] << 8 | data[3])}"
    if cmd == CMD_DEBUG:
        return "echo"
    return ""


def _describe_host(data: Sequence[int], pin_id_base: int) -> str:
    n, cmd = len(data), data[0]
    if cmd == CMD_HB and n == 2:
        return f"heartbeat answer {data[1]}"
    if cmd == CMD_DEBUG:
        return "echo request"
    if cmd == CMD_DIG_CFG and n == 2:
        return f"query pin {data[1]}"
    if cmd == CMD_DIG_CFG and n == 3:
        return f"configure pin {data[1]}: {describe_digcfg(data[2])}"
    if cmd == CMD_DIG_IO and n == 2:
        return f"read pin {data[1] & DEVCODE_PIN}" + _devcode_flags(data[1])
    if cmd == CMD_DIG_IO and n == 3:
        return f"write pin {data[1]} = {int(data[2] != 0)}"
    if cmd == CMD_DIG_RST and n == 2:
        return f"re-arm pin {data[1]}"
    if cmd == CMD_PTIME_RD and n == 2:
        return f"time pin {data[1] & DEVCODE_PIN}" + _devcode_flags(data[1])
    return command_name(cmd) if cmd in COMMAND_NAMES else ""


def _devcode_flags(devcode: int) -> str:
    flags = [name for bit, name in ((DEVCODE_HOST, "HOST"), (DEVCODE_RFLX, "RFLX")) if devcode & bit]
    return f" ({'+'.join(flags)})" if flags else " (value discarded)"
