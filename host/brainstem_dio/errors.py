# SPDX-License-Identifier: Apache-2.0
"""Exceptions of the brainstem_dio host library.

    BrainStemError
    ├── LinkError            the serial link is unusable (closed, broken, answer lost)
    │   ├── PortError        the port could not be opened
    │   └── ResyncError      an answer was lost in a framing error and its resync
    ├── Timeout              no answer within the call's timeout (also a TimeoutError)
    ├── ProtocolError        an answer that does not fit the request
    ├── ModuleReset          the module reset (Module.reset() or a power-up) before it answered
    └── ModuleError          a message packet `A, 2, 0x80, code` the module sent
        ├── CmdInvalid (8) · CmdTooLong (9) · CmdIndexErr (10) · TmrConflict (15)
        ├── CmdTooShort (27) · SerialError (28) · ConfigErr (29)
        └── StatePowerReset (4) · CmdQOverflow (12)   (unsolicited; never raised by a call)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

from . import protocol as P

if TYPE_CHECKING:
    from .framing import Packet


class BrainStemError(Exception):
    """Base class of every exception this library raises on purpose."""


class LinkError(BrainStemError):
    """The link cannot carry the call: closed, the port failed, or the answer was lost."""


class PortError(LinkError):
    """The serial port (device, pty or URL) could not be opened."""


class ResyncError(LinkError):
    """A framing error on the link made the host resynchronize; the answer to this call was
    in the bytes that had to be discarded."""


class Timeout(BrainStemError, TimeoutError):
    """No answer within the call's timeout. Distinct from a timer result of 0 (a
    measurement that timed out on the module), which is a `TimerResult`."""


class ProtocolError(BrainStemError):
    """The module's answer does not fit the request (a wrong echo, a lost reply)."""


class ModuleReset(BrainStemError):
    """The module reset before it answered: `Module.reset()` fails every call to the module
    written before its cmdRESET (the module drops what it has not sent), and a power-up
    message that nobody asked for fails the measurements whose start the module had
    confirmed."""


class ModuleError(BrainStemError):
    """A message from the module (`A, 2, 0x80, code`), raised from the call that caused it.

    Attributes: `code` (the message code), `name` (the contract's name, e.g. `cmdIndexErr`),
    `addr` (the module), `packet` (the message as received), `command` (the data bytes of
    the packet that caused it, when known) and `packets` (everything else the call received
    before it finished, e.g. the reply of a command that also got cmdTooLong)."""

    code: int = -1

    def __init__(
        self,
        code: int | None = None,
        *,
        addr: int | None = None,
        packet: Packet | None = None,
        command: bytes | None = None,
        packets: Sequence[Packet] = (),
    ) -> None:
        if code is not None:
            self.code = code
        self.name = P.message_name(self.code)
        self.addr = addr
        self.packet = packet
        self.command = command
        self.packets = list(packets)
        text = f"{self.name} ({self.code})"
        if addr is not None:
            text = f"module {addr}: {text}"
        if command is not None:
            text += f" after {P.format_packet(addr if addr is not None else 0, command)}"
            desc = P.describe(addr or 0, command, from_host=True)
            if desc:
                text += f" ({desc})"
        super().__init__(text)


class StatePowerReset(ModuleError):
    """statePowerReset: the module's first packet after a reset."""

    code = P.MSG_STATE_POWER_RESET


class CmdInvalid(ModuleError):
    """cmdInvalid: unknown command code."""

    code = P.MSG_CMD_INVALID


class CmdTooLong(ModuleError):
    """cmdTooLong: more parameter bytes than the command takes. The command was executed
    with the bytes it needs; its reply, if any, is in `packets`."""

    code = P.MSG_CMD_TOO_LONG


class CmdIndexErr(ModuleError):
    """cmdIndexErr: pin out of range, no timer on the pin, reading an output, or writing an
    input."""

    code = P.MSG_CMD_INDEX_ERR


class CmdQOverflow(ModuleError):
    """cmdQOverflow: the serial wrapper's receive FIFO overflowed and dropped bytes."""

    code = P.MSG_CMD_Q_OVERFLOW


class TmrConflict(ModuleError):
    """tmrConflict: the pin's timer is still busy with an earlier measurement."""

    code = P.MSG_TMR_CONFLICT


class CmdTooShort(ModuleError):
    """cmdTooShort: fewer parameter bytes than the command needs."""

    code = P.MSG_CMD_TOO_SHORT


class SerialError(ModuleError):
    """serialError: the module received a packet with N > 8 (not a port failure: that is
    `LinkError`)."""

    code = P.MSG_SERIAL_ERROR


class ConfigErr(ModuleError):
    """configErr: DIG_CFG set on a pin whose configuration is fixed; nothing changed."""

    code = P.MSG_CONFIG_ERR


MODULE_ERRORS: dict[int, type[ModuleError]] = {
    cls.code: cls
    for cls in (
        StatePowerReset,
        CmdInvalid,
        CmdTooLong,
        CmdIndexErr,
        CmdQOverflow,
        TmrConflict,
        CmdTooShort,
        SerialError,
        ConfigErr,
    )
}


def error_class(code: int) -> type[ModuleError]:
    """The exception class of a message code (`ModuleError` for an unknown code)."""
    return MODULE_ERRORS.get(code, ModuleError)


def module_error(packet: Packet, command: bytes | None = None, packets: Sequence[Packet] = ()) -> ModuleError:
    """The exception for a received message packet."""
    code = packet.data[1]
    return error_class(code)(code, addr=packet.addr, packet=packet, command=command, packets=packets)
