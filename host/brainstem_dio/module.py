# SPDX-License-Identifier: Apache-2.0
"""One BrainStem module on a link: every digital I/O command as a method.

How long a call waits, and for what:

* Commands with a reply (`query`, `read`, `echo`, `probe`) wait for the reply or for the
  message the command caused, whichever comes first (a failing command sends exactly one
  message and no reply).
* Commands without a reply (`configure`, `write`, `rearm`, and `start_timer` for the start
  itself) are sent together with a cmdDEBUG echo in one write, and wait for that echo. The
  module executes packets in order, so a message before the echo is the command's (raised as
  its `ModuleError` subclass) and the echo proves that it succeeded. This costs one round trip
  (9 bytes out, 4 back at 9600 baud: about 15 ms). With `wait=False` they return a `Pending`
  at once; its error is raised by `Pending.result()`, or else by the next `sync()`.
* `time_pin` waits past the module's own 104.9 ms timer timeout: a result of 0 ticks (the
  module's timeout) is a `TimerResult` with `timed_out` True, never an exception.
* A call that gets no answer in time raises `Timeout`. The next call to that module first
  sends an echo and waits for it, so that a late answer to the call that timed out is not
  taken for the new call's (it goes to the unsolicited queue instead).
* Every reply is checked against the contract before it is decoded (`_check_*` below): the
  pin and device ID the call asked for, a level of 0 or 1, DIGCFG bits 6:5 zero, FIXED the
  same as the first time the pin was seen, a message code a command can cause. A reply that
  does not fit raises ProtocolError naming its bytes, and the next call syncs first.
"""

from __future__ import annotations

import dataclasses
import threading
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Union

from . import protocol as P
from .errors import ModuleReset, ProtocolError, module_error
from .framing import Packet
from .link import Link, TimerWaiter, Transaction, exact_match

if TYPE_CHECKING:
    from typing_extensions import Self  # typing.Self from Python 3.11 on

DEFAULT_TIMEOUT = 0.5  # s for a reply (the original waits 250 ms)


@dataclass(frozen=True)
class DigCfg:
    """A pin's DIGCFG byte as named fields (PROTOCOL.md §3).

    `output`: drive the pin (IODIR = 0); an input otherwise. `latch`: arm the one-shot
    transition latch (ENA); `latch_rising`: it fires on 0->1, else on 1->0 (TRG).
    `timer_high`: the event timer's target level is high (TSTATE); `timer_width`: width
    timer, else edge timer (TMODE). `fixed` is read-only: 1 on a pin whose configuration
    the hardware fixes (ignored when configuring).

    The defaults are the power-up configuration: an input, nothing armed."""

    output: bool = False
    latch: bool = False
    latch_rising: bool = False
    timer_high: bool = False
    timer_width: bool = False
    fixed: bool = False

    def to_byte(self) -> int:
        """The DIGCFG byte (bit 7, FIXED, is never set: the module ignores it)."""
        return (
            (0 if self.output else P.DIGCFG_IODIR)
            | (P.DIGCFG_ENA if self.latch else 0)
            | (P.DIGCFG_TRG if self.latch_rising else 0)
            | (P.DIGCFG_TSTATE if self.timer_high else 0)
            | (P.DIGCFG_TMODE if self.timer_width else 0)
        )

    @classmethod
    def from_byte(cls, value: int) -> DigCfg:
        return cls(
            output=not value & P.DIGCFG_IODIR,
            latch=bool(value & P.DIGCFG_ENA),
            latch_rising=bool(value & P.DIGCFG_TRG),
            timer_high=bool(value & P.DIGCFG_TSTATE),
            timer_width=bool(value & P.DIGCFG_TMODE),
            fixed=bool(value & P.DIGCFG_FIXED),
        )

    def __int__(self) -> int:
        return self.to_byte() | (P.DIGCFG_FIXED if self.fixed else 0)

    def __str__(self) -> str:
        return P.describe_digcfg(int(self))


@dataclass(frozen=True)
class TimerResult:
    """A PTIME_RD result: `ticks` of 1.6 us. `ticks` 0 means the module's timer timed out
    (no completion within 65 535 ticks = 104.856 ms): `timed_out` is then True and `seconds`
    None. `time` is when it arrived (time.monotonic())."""

    pin: int
    ticks: int
    time: float = dataclasses.field(default=0.0, compare=False)

    @property
    def timed_out(self) -> bool:
        return self.ticks == 0

    @property
    def seconds(self) -> float | None:
        # (a division by the tick rate: the nearest float to the exact time, so that 500
        # ticks print as 0.0008, where 500 * 1.6e-6 rounds twice to 0.0007999999999999999)
        return None if self.ticks == 0 else self.ticks / P.TICK_HZ

    def __str__(self) -> str:
        return P.ticks_text(self.ticks)


class Pending:
    """A command without a reply sent with `wait=False`."""

    def __init__(self, module: Module, t: Transaction) -> None:
        self._module = module
        self._t = t

    def done(self) -> bool:
        """True once the module's answer (error or sync echo) is in."""
        return self._t.done()

    def result(self, timeout: float | None = None) -> None:
        """Wait for the outcome; raise the command's `ModuleError` (or a link error, or
        `Timeout` after `timeout` s, default the module's)."""
        self._module._forget(self)
        self._module._finish(self._t, timeout)

    def _exception(self) -> BaseException | None:
        """The outcome of a finished command as an exception (None: it succeeded)."""
        t = self._t
        if t.exc is not None:
            return t.exc
        if t.error is not None:
            return self._module._message_error(t)
        return None


class TimerHandle:
    """A started measurement (`Module.start_timer`); `result()` waits for its result."""

    def __init__(self, module: Module, pin: int, waiter: TimerWaiter, deadline: float) -> None:
        self._module = module
        self.pin = pin
        self._waiter = waiter
        self._deadline = deadline

    @property
    def dev_id(self) -> int:
        return self._waiter.dev_id

    def done(self) -> bool:
        return self._waiter.event.is_set()

    def result(self, timeout: float | None = None) -> TimerResult:
        """The measurement's result. `timeout` (s) defaults to what is left of the module's
        timeout plus 104.9 ms from the start. A module timeout is a `TimerResult` with
        `timed_out`; `Timeout` means the result itself did not arrive."""
        if timeout is None:
            timeout = max(0.0, self._deadline - time.monotonic())
        p = self._module.link.wait_timer(self._waiter, timeout)
        return TimerResult(self.pin, p.data[2] << 8 | p.data[3], p.time)


CfgArg = Union[DigCfg, int, None]


class Module:
    """The module at address `addr` (even, 2..254) on `link`.

    `timeout`: default seconds a call waits for its answer (0.5). `pin_id_base`,
    `timer_id_base`: the module's device ID bases (GP 1.0: 5 and 10), used to recognise
    DIG_IO read replies and timer results. Make one with `brainstem_dio.open()` or
    `Module(link, addr)`. Thread-safe (see `brainstem_dio.link`)."""

    def __init__(
        self,
        link: Link,
        addr: int = P.DEFAULT_MODULE_ADDR,
        *,
        timeout: float = DEFAULT_TIMEOUT,
        pin_id_base: int = P.DEFAULT_PIN_ID_BASE,
        timer_id_base: int = P.DEFAULT_TIMER_ID_BASE,
        owns_link: bool = False,
    ) -> None:
        if not (isinstance(addr, int) and 2 <= addr <= 254 and addr % 2 == 0):
            raise ValueError(f"a module address is even, 2..254 (got {addr!r})")
        self.link = link
        self.addr = addr
        self.timeout = timeout
        self.pin_id_base = pin_id_base
        self.timer_id_base = timer_id_base
        self._owns_link = owns_link
        self._unchecked: list[Pending] = []
        self._lock = threading.Lock()
        self._fixed: dict[int, bool] = {}  # FIXED of each pin, as first seen in a query reply

    def __repr__(self) -> str:
        return f"<Module {self.addr} on {self.link.port_name}>"

    # ---- configuration ---------------------------------------------------------------------------
    def configure(
        self,
        pin: int,
        cfg: CfgArg = None,
        *,
        output: bool | None = None,
        latch: bool | None = None,
        latch_rising: bool | None = None,
        timer_high: bool | None = None,
        timer_width: bool | None = None,
        wait: bool = True,
        timeout: float | None = None,
    ) -> Pending | None:
        """cmdDIG_CFG set: `26, pin, DIGCFG`. `cfg` is a `DigCfg` or a raw byte; the named
        arguments override its fields. Fields given neither way take `DigCfg`'s defaults
        (an input, nothing armed), not the pin's current values: use `update_config` to
        change some fields only. Also re-arms the pin's transition latch.

        Raises CmdIndexErr (no such pin) or ConfigErr (a fixed pin)."""
        base = DigCfg.from_byte(cfg) if isinstance(cfg, int) else (cfg or DigCfg())
        changes = {
            k: v
            for k, v in {
                "output": output, "latch": latch, "latch_rising": latch_rising, "timer_high": timer_high, "timer_width": timer_width
            }.items()
            if v is not None
        }
        value = dataclasses.replace(base, **changes).to_byte()
        pin = _byte(pin, "pin")
        return self._no_reply(bytes([P.CMD_DIG_CFG, pin, value]), f"configure pin {pin}", wait, timeout)

    def query(self, pin: int, *, timeout: float | None = None) -> DigCfg:
        """cmdDIG_CFG query `26, pin`: the pin's configuration (reply `26, pin, DIGCFG`).
        Raises CmdIndexErr for a pin out of range."""
        pin = _byte(pin, "pin")
        data = bytes([P.CMD_DIG_CFG, pin])

        def expect(p: Packet) -> bool:
            return p.n == 3 and p.data[0] == P.CMD_DIG_CFG

        reply = self._reply(data, expect, f"query pin {pin}", timeout)
        if reply.data[1] != pin:
            self._bad_reply(reply, f"a query of pin {pin}", f"it names pin {reply.data[1]}")
        value = reply.data[2]
        if value & P.DIGCFG_RESERVED:
            self._bad_reply(reply, f"a query of pin {pin}", f"DIGCFG 0x{value:02X} has reserved bits 6:5 set")
        fixed = bool(value & P.DIGCFG_FIXED)
        with self._lock:
            seen = self._fixed.setdefault(pin, fixed)
        if seen != fixed:
            self._bad_reply(
                reply, f"a query of pin {pin}", f"FIXED is {int(fixed)}, but it was {int(seen)} before (it never changes)"
            )
        return DigCfg.from_byte(value)

    def update_config(self, pin: int, *, timeout: float | None = None, **changes: bool) -> DigCfg:
        """Query the pin, change the named `DigCfg` fields, configure it; returns the new
        configuration."""
        cfg = dataclasses.replace(self.query(pin, timeout=timeout), fixed=False, **changes)
        self.configure(pin, cfg, timeout=timeout)
        return cfg

    # ---- digital I/O -------------------------------------------------------------------------------
    def write(self, pin: int, value: bool | int, *, wait: bool = True, timeout: float | None = None) -> Pending | None:
        """cmdDIG_IO write `27, pin, value`: drive an output pin high (value true) or low.
        Raises CmdIndexErr if the pin is out of range or an input."""
        pin = _byte(pin, "pin")
        return self._no_reply(bytes([P.CMD_DIG_IO, pin, 1 if value else 0]), f"write pin {pin}", wait, timeout)

    def read(self, pin: int, *, rflx: bool = False, timeout: float | None = None) -> int:
        """cmdDIG_IO read `27, DEVCODE` (HOST set, RFLX if `rflx`): the input pin's level,
        0 or 1. Raises CmdIndexErr if the pin is out of range or an output."""
        devcode = P.DEVCODE_HOST | (P.DEVCODE_RFLX if rflx else 0) | _pin6(pin)
        dev_id = self.pin_id_base + pin

        def expect(p: Packet) -> bool:
            return p.n == 3 and p.data[0] == P.CMD_DEV_VAL

        reply = self._reply(bytes([P.CMD_DIG_IO, devcode]), expect, f"read pin {pin}", timeout)
        if reply.data[1] != dev_id:
            self._bad_reply(
                reply,
                f"a read of pin {pin}",
                f"device ID {reply.data[1]}, not {dev_id} (is pin_id_base {self.pin_id_base} right?)",
            )
        if reply.data[2] not in (0, 1):
            self._bad_reply(reply, f"a read of pin {pin}", f"level {reply.data[2]} (a level is 0 or 1)")
        return reply.data[2]

    def rearm(self, pin: int, *, wait: bool = True, timeout: float | None = None) -> Pending | None:
        """cmdDIG_RST `28, pin`: re-arm the pin's transition latch (no effect while its ENA
        is 0). Raises CmdIndexErr for a pin out of range."""
        pin = _byte(pin, "pin")
        return self._no_reply(bytes([P.CMD_DIG_RST, pin]), f"re-arm pin {pin}", wait, timeout)

    def reflect(self, pin: int, *, wait: bool = True, timeout: float | None = None) -> Pending | None:
        """cmdDIG_IO read with RFLX only: the level goes to the module's `rflx_*` outputs,
        nothing to the host."""
        data = bytes([P.CMD_DIG_IO, P.DEVCODE_RFLX | _pin6(pin)])
        return self._no_reply(data, f"reflect pin {pin}", wait, timeout)

    # ---- event timer ---------------------------------------------------------------------------------
    def start_timer(
        self, pin: int, *, rflx: bool = False, host: bool = True, timeout: float | None = None
    ) -> TimerHandle | None:
        """cmdPTIME_RD `29, DEVCODE`: start the pin's measurement (in the mode its DIGCFG
        sets) and return once the module has accepted it. Raises CmdIndexErr (no timer on
        the pin, out of range, an output) or TmrConflict (its timer is busy). Returns a
        `TimerHandle` for the result, or None when `host` is False (the result then goes
        only to the module's RFLX outputs)."""
        devcode = (P.DEVCODE_HOST if host else 0) | (P.DEVCODE_RFLX if rflx else 0) | _pin6(pin)
        data = bytes([P.CMD_PTIME_RD, devcode])
        waiter = TimerWaiter(self.addr, self.timer_id_base + pin) if host else None
        on_done = None if waiter is None else (lambda t: self.link.timer_started(waiter, t))
        t = self._submit(data, None, f"time pin {pin}", timer=waiter, on_done=on_done)
        self._finish(t, timeout)
        if waiter is None:
            return None
        return TimerHandle(self, pin, waiter, time.monotonic() + self._timeout(None) + P.TIMER_TIMEOUT_S)

    def time_pin(self, pin: int, *, rflx: bool = False, timeout: float | None = None) -> TimerResult:
        """Start the pin's measurement and wait for its result (`start_timer` + `result`).
        `timeout` bounds the whole call; the default is the module's timeout plus the
        module's 104.9 ms timer timeout."""
        total = self._timeout(None) + P.TIMER_TIMEOUT_S if timeout is None else timeout
        deadline = time.monotonic() + total
        handle = self.start_timer(pin, rflx=rflx, timeout=total)
        assert handle is not None
        return handle.result(max(0.0, deadline - time.monotonic()))

    # ---- link checks ---------------------------------------------------------------------------------
    def echo(self, data: bytes | Iterable[int] = b"", *, timeout: float | None = None) -> bytes:
        """cmdDEBUG `23, data...` (at most 7 bytes): returns the bytes the module echoed."""
        data = bytes(data)
        if len(data) > P.MAX_N - 1:
            raise ValueError("cmdDEBUG carries at most 7 data bytes")
        body = bytes([P.CMD_DEBUG]) + data
        reply = self._reply(body, exact_match(bytes([self.addr, len(body)]) + body), "echo", timeout)
        return reply.data[1:]

    def probe(self, *, timeout: float | None = None) -> float:
        """The resync probe `AD 00`; waits for the module's `A 00` and returns the round trip
        in seconds."""
        start = time.monotonic()
        self._auto_sync()
        t = self.link.submit(
            self.addr, bytes([P.ADDR_RESYNC, 0]), command=b"", expect=lambda p: p.n == 0, label="resync probe"
        )
        self._finish(t, timeout)
        return time.monotonic() - start

    def reset(self, *, timeout: float | None = None) -> None:
        """cmdRESET `24`: the module returns to its power-up state (every pin an input,
        nothing armed, output latches 0, timers stopped, heartbeat restarting) and answers
        with the power-up message `A, 2, 0x80, 4`, for which this waits. The module drops
        everything it had not yet sent, so every call to it still waiting (from any thread:
        replies, `wait=False` commands, timer results) fails with `ModuleReset`; the errors of
        `wait=False` commands are not raised again by `sync()`. Raises CmdInvalid from a
        module without cmdRESET, and `Timeout` if the power-up message does not come. It
        does not sync first, even after a Timeout: a module that stopped answering echoes
        can still be reset, and what it had not sent is dropped anyway."""
        data = bytes([P.CMD_RESET])
        t = self.link.submit(self.addr, self._packet(data), command=data, label="reset", reset=True)
        self._finish(t, timeout)
        with self._lock:
            self._unchecked = [
                pend for pend in self._unchecked if not (pend.done() and isinstance(pend._t.exc, ModuleReset))
            ]

    def sync(self, *, timeout: float | None = None) -> None:
        """Send an echo and wait for it: everything sent before has then been executed.
        Raises the first error no call has reported yet: the error of a `wait=False`
        command whose `result()` nobody took, or a message caused by a raw `send` that
        arrived while a call was in flight (errors left over are raised by the next
        `sync()`; one that arrived with no call in flight is in the unsolicited queue).
        Other packets that arrived before the echo go to the unsolicited queue."""
        self.link.take_needs_sync(self.addr)
        t = self.link.submit(self.addr, b"", label="sync")
        t.wait(self._timeout(timeout))
        if t.exc is not None:
            raise t.exc
        errors = [p for p in t.packets if p.is_message]
        self.link.put_unsolicited([p for p in t.packets if not p.is_message] + errors[1:])
        failures: list[BaseException] = [self._message_exception(errors[0], None, [])] if errors else []
        with self._lock:
            keep: list[Pending] = []
            for pend in self._unchecked:
                if not pend.done():
                    keep.append(pend)
                    continue
                exc = pend._exception()
                if exc is not None:
                    if failures:
                        keep.append(pend)  # for the next sync()
                    else:
                        failures.append(exc)
            self._unchecked = keep
        if failures:
            raise failures[0]

    # ---- raw packets --------------------------------------------------------------------------------------
    def request(
        self,
        data: bytes | Iterable[int],
        *,
        n: int | None = None,
        timeout: float | None = None,
        check: bool = True,
    ) -> list[Packet]:
        """Send any packet `addr, N, data` (`n` overrides N) followed by a sync echo, and
        return every packet the module sent in answer (timer results excepted: they go to
        the unsolicited queue). With `check`, a message among them is raised as its
        `ModuleError`; the others are in its `packets`. For N > 8 send no data bytes: the
        module drops the address and length and reads the next byte as an address."""
        data = bytes(data)
        wire = bytes([self.addr, (len(data) if n is None else n) & 0xFF]) + data
        self._auto_sync()
        command = data if n is None else None  # with another N it is not `data` as sent
        t = self.link.submit(self.addr, wire, command=command, label="request")
        t.wait(self._timeout(timeout))
        if t.exc is not None:
            raise t.exc
        if check and t.error is not None:
            raise self._message_error(t)
        return list(t.packets)

    def send(self, data: bytes | Iterable[int], *, n: int | None = None) -> None:
        """Send a packet to this module and return at once. Nothing waits for its answers:
        with no call in flight they go to the unsolicited queue; a message it causes while a
        call is in flight is raised by the next `sync()` if that call does not take it
        first. Prefer `request`."""
        self.link.send_packet(self.addr, data, n)

    def receive(self, timeout: float | None = None) -> Packet:
        """The next unsolicited packet of the link (see `Link.receive`)."""
        return self.link.receive(timeout)

    def drain(self) -> list[Packet]:
        """Every unsolicited packet waiting (see `Link.drain`)."""
        return self.link.drain()

    def close(self) -> None:
        """Close the link if this module opened it (`brainstem_dio.open`)."""
        if self._owns_link:
            self.link.close()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ---- internals ------------------------------------------------------------------------------------------
    def _timeout(self, timeout: float | None) -> float:
        return self.timeout if timeout is None else timeout

    def _packet(self, data: bytes) -> bytes:
        return bytes([self.addr, len(data)]) + data

    def _auto_sync(self) -> None:
        """After a Timeout: drain the answers still on their way, to the unsolicited queue."""
        if self.link.take_needs_sync(self.addr):
            t = self.link.submit(self.addr, b"", label="sync after a timeout", detached=True)
            t.wait(self.timeout)
            if t.exc is not None:
                raise t.exc

    def _submit(
        self,
        data: bytes,
        expect: Callable[[Packet], bool] | None,
        label: str,
        timer: TimerWaiter | None = None,
        on_done: Callable[[Transaction], None] | None = None,
    ) -> Transaction:
        self._auto_sync()
        return self.link.submit(
            self.addr, self._packet(data), command=data, expect=expect, label=label, timer=timer, on_done=on_done
        )

    def _finish(self, t: Transaction, timeout: float | None) -> Packet | None:
        t.wait(self._timeout(timeout))
        if t.exc is not None:
            raise t.exc
        if t.error is not None:
            raise self._message_error(t)
        return t.reply

    def _message_error(self, t: Transaction) -> BaseException:
        assert t.error is not None
        return self._message_exception(t.error, t.command, [p for p in t.packets if p is not t.error])

    def _message_exception(self, msg: Packet, command: bytes | None, others: list[Packet]) -> BaseException:
        """The exception for a message a call received: its ModuleError, or ProtocolError for
        a code no command causes (PROTOCOL.md §2)."""
        if msg.message_code not in P.COMMAND_MESSAGES:
            self.link.mark_needs_sync(self.addr)
            what = "a call" if command is None else P.format_packet(self.addr, command)
            return ProtocolError(
                f"module {self.addr} answered {what} with {_hex(msg)}: message code {msg.message_code}"
                " is not one a command can cause"
            )
        return module_error(msg, command, others)

    def _bad_reply(self, reply: Packet, call: str, why: str) -> None:
        """Raise ProtocolError for a reply that breaks the contract; the next call syncs
        first, since a reply that does not fit may be a sign of a garbled stream."""
        self.link.mark_needs_sync(self.addr)
        raise ProtocolError(f"module {self.addr} answered {call} with {_hex(reply)}: {why}")

    def _reply(self, data: bytes, expect: Callable[[Packet], bool], label: str, timeout: float | None) -> Packet:
        reply = self._finish(self._submit(data, expect, label), timeout)
        assert reply is not None
        return reply

    def _no_reply(self, data: bytes, label: str, wait: bool, timeout: float | None) -> Pending | None:
        if wait:
            self._finish(self._submit(data, None, label), timeout)
            return None
        box: list[Pending] = []

        def settled(t: Transaction) -> None:
            # A command that succeeded needs no reporting: forget it (an error stays for
            # result() or the next sync()).
            if t.exc is None and t.error is None and box:
                self._forget(box[0])

        t = self._submit(data, None, label, on_done=settled)
        pend = Pending(self, t)
        with self._lock:
            self._unchecked.append(pend)
            box.append(pend)
        if t.done():
            settled(t)
        return pend

    def _forget(self, pend: Pending) -> None:
        with self._lock:
            if pend in self._unchecked:
                self._unchecked.remove(pend)


def _hex(p: Packet) -> str:
    """A packet's bytes as on the wire: `02 03 04 05 11`."""
    return " ".join(f"{b:02X}" for b in p.to_bytes())


def _byte(value: int, what: str) -> int:
    if not isinstance(value, int) or not 0 <= value <= 255:
        raise ValueError(f"{what} must be 0..255 (got {value!r})")
    return value


def _pin6(pin: int) -> int:
    if not isinstance(pin, int) or not 0 <= pin <= P.DEVCODE_PIN:
        raise ValueError(f"a DEVCODE pin is 0..63 (got {pin!r})")
    return pin


__all__: Sequence[str] = ["DigCfg", "Module", "Pending", "TimerHandle", "TimerResult"]
