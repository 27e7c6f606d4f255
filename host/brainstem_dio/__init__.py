# SPDX-License-Identifier: Apache-2.0
"""brainstem_dio: host library for the digital I/O subsystem of Acroname BrainStem 1.0
modules (and the brainstem_dio core), over any pyserial port or URL.

    import brainstem_dio
    with brainstem_dio.open("/dev/ttyUSB0") as m:      # or a pty, socket://host:port ...
        m.configure(1, output=True)
        m.write(1, 1)
        print(m.read(0), m.query(3), m.time_pin(4))

See host/README.md for the whole API.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from . import protocol
from .errors import (
    BrainStemError,
    CmdIndexErr,
    CmdInvalid,
    CmdQOverflow,
    CmdTooLong,
    CmdTooShort,
    ConfigErr,
    LinkError,
    ModuleError,
    ModuleReset,
    PortError,
    ProtocolError,
    ResyncError,
    SerialError,
    StatePowerReset,
    Timeout,
    TmrConflict,
    error_class,
)
from .framing import FrameParser, FramingError, Packet, Resynced, ResyncTimeout
from .link import DEFAULT_BAUDRATE, Link, LinkEvent, LinkStats, SerialLike
from .module import DEFAULT_TIMEOUT, DigCfg, Module, Pending, TimerHandle, TimerResult

__version__ = "0.1.0"


def open(
    port: str | SerialLike,
    addr: int = protocol.DEFAULT_MODULE_ADDR,
    *,
    baudrate: int = DEFAULT_BAUDRATE,
    timeout: float = DEFAULT_TIMEOUT,
    pin_id_base: int = protocol.DEFAULT_PIN_ID_BASE,
    timer_id_base: int = protocol.DEFAULT_TIMER_ID_BASE,
    on_unsolicited: Callable[[Packet], None] | None = None,
    **link_options: Any,
) -> Module:
    """Open `port` (a device, a pty path, `socket://host:port`, `loop://`, any pyserial URL,
    or a serial-like object) and return the `Module` at `addr`. Closing the module closes
    the port. `link_options` go to `Link` (inter_byte_timeout, answer_heartbeats, ...).
    Raises `PortError` if the port cannot be opened."""
    link = Link(port, baudrate=baudrate, resync_addr=addr, on_unsolicited=on_unsolicited, **link_options)
    return Module(
        link, addr, timeout=timeout, pin_id_base=pin_id_base, timer_id_base=timer_id_base, owns_link=True
    )


__all__ = [
    "DEFAULT_BAUDRATE",
    "DEFAULT_TIMEOUT",
    "BrainStemError",
    "CmdIndexErr",
    "CmdInvalid",
    "CmdQOverflow",
    "CmdTooLong",
    "CmdTooShort",
    "ConfigErr",
    "DigCfg",
    "FrameParser",
    "FramingError",
    "Link",
    "LinkError",
    "LinkEvent",
    "LinkStats",
    "Module",
    "ModuleError",
    "ModuleReset",
    "Packet",
    "Pending",
    "PortError",
    "ProtocolError",
    "ResyncError",
    "ResyncTimeout",
    "Resynced",
    "SerialError",
    "SerialLike",
    "StatePowerReset",
    "Timeout",
    "TimerHandle",
    "TimerResult",
    "TmrConflict",
    "error_class",
    "open",
    "protocol",
]
