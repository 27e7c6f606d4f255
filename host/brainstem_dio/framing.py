# SPDX-License-Identifier: Apache-2.0
"""Host-side packet framing with the original host library's resync, as a pure state machine.

`FrameParser` is fed the bytes that arrive from the module with the time they arrived and
returns events; it never touches a port and never reads a clock, so it can be tested with
made-up times. The link (`brainstem_dio.link`) carries out what the events ask for.

Rules (the vendor's 2008 host receiver, plus an inter-byte timeout):

* A packet is `address, N, d0 .. d(N-1)`. The address must be even and non-zero and N at
  most 8; otherwise the packet is a framing error.
* A packet left incomplete for `inter_byte_timeout` seconds is a framing error too (the
  original has no such timeout, so a lost byte there hangs the link).
* After a framing error the parser discards every byte until the link has flushed its input
  and sent the probes `AD 00 AD 00` (`probes_sent`); then it accepts only the exact bytes
  `A 00 A 00` (the module's two probe replies), discarding all before them, and goes back to
  normal framing after them. If they do not come within `resync_timeout` seconds it reports
  `ResyncTimeout` and waits for the link to try again.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Union

from . import protocol as P


@dataclass(frozen=True)
class Packet:
    """One packet: `addr, N, data` (N = len(data)). `time` is when its last byte arrived
    (`time.monotonic()`), or when it was sent; it takes no part in comparisons."""

    addr: int
    data: bytes
    time: float = field(default=0.0, compare=False)

    @classmethod
    def of(cls, addr: int, *data: int, time: float = 0.0) -> Packet:
        """`Packet.of(2, 26, 3)`."""
        return cls(addr, bytes(data), time)

    @property
    def n(self) -> int:
        """The length byte N."""
        return len(self.data)

    @property
    def cmd(self) -> int | None:
        """The command code d0 (None for an N = 0 packet)."""
        return self.data[0] if self.data else None

    @property
    def is_message(self) -> bool:
        """A module message `A, 2, 0x80, code`."""
        return self.n == P.MSG_N and self.data[0] == P.CMD_MSG

    @property
    def message_code(self) -> int | None:
        return self.data[1] if self.is_message else None

    @property
    def is_heartbeat(self) -> bool:
        """The module's heartbeat `A, 2, 0, 0` (UP) or `A, 2, 0, 1` (DOWN)."""
        return self.n == 2 and self.data[0] == P.CMD_HB and self.data[1] in (P.HB_UP, P.HB_DOWN)

    def to_bytes(self) -> bytes:
        """The packet on the wire."""
        return bytes([self.addr, len(self.data)]) + self.data

    def __str__(self) -> str:
        return P.format_packet(self.addr, self.data)


@dataclass(frozen=True)
class FramingError:
    """A framing error. `reason`: `address` (the first byte is odd or zero), `length`
    (N > 8) or `timeout` (a partial packet, no byte for `inter_byte_timeout`). `dropped` are
    the bytes thrown away (the partial packet and the bad byte)."""

    reason: str
    dropped: bytes
    time: float


@dataclass(frozen=True)
class Resynced:
    """The probe replies `A 00 A 00` arrived; normal framing goes on after them.
    `discarded` counts the bytes thrown away after the framing error's own `dropped`."""

    time: float
    discarded: int


@dataclass(frozen=True)
class ResyncTimeout:
    """The probe replies did not arrive in time; the link should flush and probe again."""

    time: float


Event = Union[Packet, FramingError, Resynced, ResyncTimeout]


class State(enum.Enum):
    ADDRESS = "address"  # waiting for a packet's first byte
    LENGTH = "length"
    DATA = "data"
    FLUSH = "flush"  # after a framing error, until the probes are sent
    HUNT = "hunt"  # waiting for A 00 A 00


class FrameParser:
    """Byte-stream parser of the module's packets with the resync state machine.

    `resync_addr` is the module address A whose probe replies `A 00 A 00` end a resync.
    `inter_byte_timeout` (seconds, None = never) drops a partial packet. `resync_timeout`
    (seconds) bounds the wait for the probe replies."""

    def __init__(
        self,
        resync_addr: int = P.DEFAULT_MODULE_ADDR,
        inter_byte_timeout: float | None = 0.1,
        resync_timeout: float = 0.25,
    ) -> None:
        if not (0 < resync_addr < 256 and resync_addr % 2 == 0):
            raise ValueError("a module address is even, 2..254")
        if inter_byte_timeout is not None and inter_byte_timeout <= 0:
            raise ValueError("inter_byte_timeout must be > 0 (or None)")
        self.resync_addr = resync_addr
        self.inter_byte_timeout = inter_byte_timeout
        self.resync_timeout = resync_timeout
        self._pattern = bytes([resync_addr, 0, resync_addr, 0])
        self.reset()

    def reset(self) -> None:
        """Back to waiting for an address, nothing pending."""
        self.state = State.ADDRESS
        self._buf = bytearray()
        self._last = 0.0
        self._window = bytearray()
        self._discarded = 0
        self._hunt_deadline = 0.0

    @property
    def mid_packet(self) -> bool:
        return self.state in (State.LENGTH, State.DATA)

    @property
    def resyncing(self) -> bool:
        return self.state in (State.FLUSH, State.HUNT)

    def feed(self, data: bytes, now: float) -> list[Event]:
        """Bytes that arrived at `now`; returns the events they complete, in order."""
        events: list[Event] = self.poll(now)
        for b in data:
            self._byte(b, now, events)
        if data:
            self._last = now
        return events

    def poll(self, now: float) -> list[Event]:
        """The events due to time alone at `now` (inter-byte timeout, resync timeout)."""
        if (
            self.mid_packet
            and self.inter_byte_timeout is not None
            and now - self._last > self.inter_byte_timeout
        ):
            return [self._error("timeout", b"", now)]
        if self.state is State.HUNT and now >= self._hunt_deadline:
            self.state = State.FLUSH
            return [ResyncTimeout(now)]
        return []

    def probes_sent(self, now: float) -> None:
        """The link flushed its input and sent `AD 00 AD 00` at `now`: hunt for the replies."""
        self.state = State.HUNT
        self._window = bytearray()
        self._hunt_deadline = now + self.resync_timeout

    # ---- internals ----
    def _error(self, reason: str, bad: bytes, now: float) -> FramingError:
        dropped = bytes(self._buf) + bad
        self._buf = bytearray()
        self._window = bytearray()
        self._discarded = 0
        self.state = State.FLUSH
        return FramingError(reason, dropped, now)

    def _byte(self, b: int, now: float, events: list[Event]) -> None:
        st = self.state
        if st is State.ADDRESS:
            if b == 0 or b & 1:
                events.append(self._error("address", bytes([b]), now))
            else:
                self._buf = bytearray([b])
                self.state = State.LENGTH
        elif st is State.LENGTH:
            if b > P.MAX_N:
                events.append(self._error("length", bytes([b]), now))
            elif b == 0:
                events.append(Packet(self._buf[0], b"", now))
                self._buf = bytearray()
                self.state = State.ADDRESS
            else:
                self._buf.append(b)
                self.state = State.DATA
        elif st is State.DATA:
            self._buf.append(b)
            if len(self._buf) == self._buf[1] + 2:
                events.append(Packet(self._buf[0], bytes(self._buf[2:]), now))
                self._buf = bytearray()
                self.state = State.ADDRESS
        elif st is State.FLUSH:
            self._discarded += 1
        else:  # HUNT
            self._window.append(b)
            if len(self._window) > 4:
                del self._window[0]
                self._discarded += 1
            if bytes(self._window) == self._pattern:
                self.state = State.ADDRESS
                self._window = bytearray()
                events.append(Resynced(now, self._discarded))
                self._discarded = 0
