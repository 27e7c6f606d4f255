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

# --- constants (PROTOCOL.md §1-§4, docs/fpga.md) ------------------------------------------

# Packets: `address, N, d0 .. d(N-1)`.
MAX_N = 8  # most data bytes in a packet (d0 counts)
ADDR_RESYNC = 0xAD  # the host's resync probe `0xAD, 0`, answered `A, 0`
MSG_N = 2  # a message is `A, MSG_N, CMD_MSG, code`

# Command codes.
CMD_HB = 0
CMD_DEV_VAL = 4
CMD_DEBUG = 23
CMD_DIG_CFG = 26
CMD_DIG_IO = 27
CMD_DIG_RST = 28
CMD_PTIME_RD = 29
CMD_MSG = 0x80

# Message codes (`A, 2, 0x80, code`).
MSG_STATE_POWER_RESET = 4
MSG_CMD_INVALID = 8
MSG_CMD_TOO_LONG = 9
MSG_CMD_INDEX_ERR = 10
MSG_CMD_Q_OVERFLOW = 12  # sent by the serial wrapper brainstem_dio_uart, not the core
MSG_TMR_CONFLICT = 15
MSG_CMD_TOO_SHORT = 27
MSG_SERIAL_ERROR = 28
MSG_CONFIG_ERR = 29  # assigned by the contract

# DIGCFG byte: [7] FIXED | [6:5] 0 | [4] TMODE | [3] TSTATE | [2] TRG | [1] ENA | [0] IODIR.
DIGCFG_FIXED = 0x80
DIGCFG_TMODE = 0x10
DIGCFG_TSTATE = 0x08
DIGCFG_TRG = 0x04
DIGCFG_ENA = 0x02
DIGCFG_IODIR = 0x01
DIGCFG_STORED = 0x1F  # the bits a DIG_CFG set stores
DIGCFG_RESET = 0x01  # power-up value of a pin that is not fixed

# DEVCODE byte: [7] HOST | [6] RFLX | [5:0] pin.
DEVCODE_HOST = 0x80
DEVCODE_RFLX = 0x40
DEVCODE_PIN = 0x3F

# cmdHB: the core sends `0, HB_UP` / `0, HB_DOWN`, the host answers type + HB_ANSWER_OFFSET.
HB_UP = 0
HB_DOWN = 1
HB_ANSWER_OFFSET = 2
HB_UNIT_TICKS = 16_000  # the HB_RATE unit, 25.6 ms

# Event timer.
TICK_HZ = 625_000  # a tick is 1.6 us
TIMER_MAX_TICKS = 65_535  # a result is 16 bits; the timeout comes after this many ticks

DEV_ID_LIMIT = 64

# The core's parameters as GP 1.0 has them (PROTOCOL.md §1); the host needs the address and
# the device ID bases to recognise replies.
DEFAULT_MODULE_ADDR = 2
DEFAULT_NUM_PINS = 5
DEFAULT_TIMER_MASK = 0b11110
DEFAULT_PIN_ID_BASE = 5
DEFAULT_TIMER_ID_BASE = 10
DEFAULT_TRANS_ID_BASE = 15
DEFAULT_RX_TIMEOUT_US = 25_600

# --- derived values --------------------------------------------------------------------------

TICK_S = 1.0 / TICK_HZ
TIMER_TIMEOUT_S = TIMER_MAX_TICKS * TICK_S  # 104.856 ms
HB_UNIT_S = HB_UNIT_TICKS * TICK_S  # 25.6 ms

# Longest form of each host command, counting the command byte; longer is cmdTooLong.
CMD_MAX_N = {CMD_DEBUG: 8, CMD_DIG_CFG: 3, CMD_DIG_IO: 3, CMD_DIG_RST: 2, CMD_PTIME_RD: 2}
# Shortest form; shorter is cmdTooShort.
CMD_MIN_N = {CMD_DEBUG: 1, CMD_DIG_CFG: 2, CMD_DIG_IO: 2, CMD_DIG_RST: 2, CMD_PTIME_RD: 2}

COMMAND_NAMES = {
    CMD_HB: "cmdHB",
    CMD_DEV_VAL: "cmdDEV_VAL",
    CMD_DEBUG: "cmdDEBUG",
    CMD_DIG_CFG: "cmdDIG_CFG",
    CMD_DIG_IO: "cmdDIG_IO",
    CMD_DIG_RST: "cmdDIG_RST",
    CMD_PTIME_RD: "cmdPTIME_RD",
    CMD_MSG: "cmdMSG",
}

MESSAGE_NAMES = {
    MSG_STATE_POWER_RESET: "statePowerReset",
    MSG_CMD_INVALID: "cmdInvalid",
    MSG_CMD_TOO_LONG: "cmdTooLong",
    MSG_CMD_INDEX_ERR: "cmdIndexErr",
    MSG_CMD_Q_OVERFLOW: "cmdQOverflow",
    MSG_TMR_CONFLICT: "tmrConflict",
    MSG_CMD_TOO_SHORT: "cmdTooShort",
    MSG_SERIAL_ERROR: "serialError",
    MSG_CONFIG_ERR: "configErr",
}

# The session transcript's wording of each message (sim/session.cpp).
MESSAGE_TEXT = {
    MSG_STATE_POWER_RESET: "power reset",
    MSG_CMD_INVALID: "cmd invalid",
    MSG_CMD_TOO_LONG: "cmd too long",
    MSG_CMD_INDEX_ERR: "cmd index error",
    MSG_CMD_Q_OVERFLOW: "queue overflow",
    MSG_TMR_CONFLICT: "timer conflict",
    MSG_CMD_TOO_SHORT: "cmd too short",
    MSG_SERIAL_ERROR: "serial error",
    MSG_CONFIG_ERR: "config error",
}

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
