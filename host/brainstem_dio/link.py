# SPDX-License-Identifier: Apache-2.0
"""The serial link to BrainStem modules: a background reader that frames and resynchronizes
the byte stream, answers heartbeats, and hands each packet to the call that caused it (or to
the unsolicited queue).

Attribution. The module executes packets in the order it receives them, and sends the
packets each one causes before those of the next (heartbeats, timer results and the serial
wrapper's cmdQOverflow excepted). The link keeps the calls in flight in the order their bytes
were written, per module address, and gives each arriving packet to the oldest of them:

* a *reply* call (query, read, echo, probe) ends at its reply or at a message;
* an *echo* call is a command (or nothing) followed in the same write by a tagged cmdDEBUG
  echo `A, 3, 23, 0xB5, tag`. It collects every packet up to that echo: a message that
  arrives before the echo is that command's, and the echo proves that the command succeeded.
  If the echo of a *later* echo call arrives first, the calls before it lost their answers
  and fail with ProtocolError.

* a *reset* call (`Module.reset`) ends at the power-up message (or cmdInvalid); every call
  of that module written before it, and every timer wait whose PTIME_RD was, fails with
  ModuleReset (the module drops what it has not yet sent).

Timer results (`cmdDEV_VAL` with N = 4) are attributed per timer (address, device ID). The
module runs one measurement per timer at a time, refuses a PTIME_RD while the timer is busy
(tmrConflict), and sends the results of one timer in the order of the measurements. A result
is given only to a wait whose start the module confirmed (the PTIME_RD's sync echo came back
clean): the oldest such wait still waiting (a wait given up after its start was confirmed
takes its late result, and sends it to the queue, only while no start is unconfirmed). A
result that arrives while the timer has no such wait, but a start is unconfirmed, is held: it
may be that start's own (a pulse shorter than the sync echo ends before the echo leaves).
When a start is confirmed, every wait ahead of it on that timer is stale (the module sent all
earlier results before it ran the PTIME_RD) and is dropped: a confirmed one still waiting
whose result never came fails with ProtocolError. Of the results held, those that arrived
before the PTIME_RD was written are not its own; the last one after it is, unless a wait
ahead of it that was given up or never confirmed (a PTIME_RD whose call timed out or was
lost in a resync) might have produced it: then it is the new measurement's only if no other
result follows within the timer timeout (104.9 ms) plus CANDIDATE_SLACK of the
confirmation. Heartbeats are answered and shown to listeners only. The power-up message,
cmdQOverflow and anything no call claims go to the unsolicited queue (or the `on_unsolicited`
callback).

Thread safety: every public method of `Link` and `Module` may be called from any thread;
calls from several threads are attributed correctly because a call is registered and written
under one lock. Listeners and the unsolicited callback run in the reader thread: keep them
short and do not make blocking calls from them (that raises RuntimeError, since the reader
is what would deliver the answer).
"""

from __future__ import annotations

import collections
import functools
import itertools
import logging
import os
import threading
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Deque, Iterable, Optional, Protocol

from . import protocol as P
from .errors import LinkError, ModuleReset, PortError, ProtocolError, ResyncError, Timeout, module_error
from .framing import FrameParser, FramingError, Packet, Resynced, ResyncTimeout

if TYPE_CHECKING:
    from .module import Module

log = logging.getLogger("brainstem_dio")

# The link's own cmdDEBUG echoes are `A, 3, 23, SYNC_MARK, tag`: a convention of this
# library, not of the protocol (the module echoes any cmdDEBUG).
SYNC_MARK = 0xB5

DEFAULT_BAUDRATE = 9600
DEFAULT_INTER_BYTE_TIMEOUT = 0.1  # s; USB serial adapters may hold bytes back ~16 ms
DEFAULT_RESYNC_TIMEOUT = 0.25  # s to wait for the probe replies; doubled per retry, 2 s at most
FLUSH_QUIET = 0.02  # s of silence that ends the flush before the probes
FLUSH_MAX = 0.25  # s: the longest flush (as the original)
OVERFLOW_HOLD = 1.5 * P.DEFAULT_RX_TIMEOUT_US * 1e-6  # s of silence after cmdQOverflow
# s past the timer timeout after a confirmed start before a held result that an unconfirmed
# earlier start might have produced is taken for the new measurement's (the module's output
# may be busy with other packets, the reader polls every poll_interval).
CANDIDATE_SLACK = 0.05


class SerialLike(Protocol):
    """The part of pyserial's `Serial` interface the link uses; any object with these
    members can be passed instead of a port name (the tests use an in-memory pair)."""

    timeout: Optional[float]

    def read(self, size: int = 1) -> bytes: ...

    def write(self, data: bytes) -> Optional[int]: ...

    @property
    def in_waiting(self) -> int: ...

    def reset_input_buffer(self) -> None: ...

    def close(self) -> None: ...


@dataclass(frozen=True)
class LinkEvent:
    """What a listener is told.

    `kind`: `rx` (a packet arrived), `tx` (a packet or raw bytes were written; `packet` is
    None for bytes that are not one well-formed packet), `framing` (a framing error: `raw`
    = the bytes dropped, `note` = the reason), `resync` (the probe replies came),
    `resync-timeout`, `error` (the port failed) or `closed`. `note` says what a packet was
    (`heartbeat`, `heartbeat answer`, `unsolicited`, the call it belongs to ...) and
    `internal` marks the link's own sync echoes."""

    kind: str
    time: float
    packet: Optional[Packet] = None
    raw: bytes = b""
    note: str = ""
    internal: bool = False


@dataclass
class LinkStats:
    """Counters of a link (read them any time)."""

    bytes_in: int = 0
    packets_in: int = 0
    packets_out: int = 0
    heartbeats: int = 0
    heartbeat_answers: int = 0
    framing_errors: int = 0
    resyncs: int = 0
    resync_timeouts: int = 0
    unsolicited: int = 0
    unsolicited_dropped: int = 0
    last_rx: Optional[float] = None
    last_heartbeat: Optional[float] = None
    last_framing_error: Optional[float] = None


Action = Callable[[], None]


class Transaction:
    """One call in flight, created by `Link.submit` (users meet it inside `Pending`).

    `kind` is `reply` (ends at the packet `match` accepts, or at a message) or `echo` (ends at
    its own sync echo and collects the messages and other packets before it). After the end:
    `reply` (the packet that ended it), `error` (the first message), `packets` (what an echo
    call collected, messages included), `exc` (a link failure or a Timeout)."""

    def __init__(
        self,
        link: Link,
        seq: int,
        addr: int,
        command: Optional[bytes],
        kind: str,
        match: Callable[[Packet], bool],
        label: str,
        internal: bool,
        detached: bool,
    ) -> None:
        self.link = link
        self.seq = seq
        self.addr = addr
        self.command = command
        self.kind = kind
        self.match = match
        self.label = label
        self.internal = internal
        self.detached = detached
        self.packets: list[Packet] = []
        self.error: Optional[Packet] = None
        self.reply: Optional[Packet] = None
        self.exc: Optional[BaseException] = None
        self.sent_at = 0.0
        self._finished = False  # decided (under the link's lock)
        self._event = threading.Event()  # set after the listeners were told
        self._callbacks: list[Callable[[Transaction], None]] = []

    def done(self) -> bool:
        return self._finished

    def add_done_callback(self, fn: Callable[[Transaction], None]) -> None:
        """Call `fn(self)` when the call ends (in the thread that ends it; at once if over)."""
        with self.link._lock:
            if not self._finished:
                self._callbacks.append(fn)
                return
        fn(self)

    def wait(self, timeout: Optional[float]) -> None:
        """Wait for the end. Raise `Timeout` if it does not come in time; the call is then
        given up (an answer that still comes goes to the next sync, see `Module`)."""
        self.link._check_not_reader()
        if self._event.wait(timeout):
            return
        if self.link._abandon(self):
            raise Timeout(
                f"no answer from module {self.addr} within {timeout:.3g} s to {self.label}"
                + self.link.diagnosis()
            )
        self._event.wait()  # it ended just now; the reader sets the event in a moment

    def _finish(self) -> list[Action]:
        """Mark the end (lock held); returns what to run once the lock is released."""
        self._finished = True
        callbacks, self._callbacks = self._callbacks, []
        actions: list[Action] = [self._event.set]
        actions += [functools.partial(fn, self) for fn in callbacks]
        return actions


class TimerWaiter:
    """A wait for one timer result (cmdDEV_VAL, N = 4, device ID `dev_id`) from `addr`.
    `state`: starting (PTIME_RD sent), running (its start confirmed), ghost (confirmed, then
    given up: its result, should it come, goes to the unsolicited queue), unconfirmed (the
    start call ended without an answer: the measurement may or may not run; it is never
    given a result), done. `candidate`: a result held for a running wait until it is clear
    that it is not an unconfirmed start's (see the module docstring)."""

    def __init__(self, addr: int, dev_id: int) -> None:
        self.addr = addr
        self.dev_id = dev_id
        self.state = "starting"
        self.result: Optional[Packet] = None
        self.exc: Optional[BaseException] = None
        self.event = threading.Event()
        self.seq = -1  # the call that carries the PTIME_RD
        self.mark = 0  # results of this timer received before the PTIME_RD was written
        self.candidate: Optional[Packet] = None
        self.candidate_until = 0.0


def open_serial(port: str, baudrate: int, timeout: float, write_timeout: Optional[float]) -> Any:
    """Open a pyserial port or URL raw: 8N1, no flow control (as the original library)."""
    import serial  # pyserial

    try:
        return serial.serial_for_url(
            port,
            baudrate=baudrate,
            bytesize=serial.EIGHTBITS,
            parity=serial.PARITY_NONE,
            stopbits=serial.STOPBITS_ONE,
            timeout=timeout,
            write_timeout=write_timeout,
            xonxoff=False,
            rtscts=False,
            dsrdtr=False,
        )
    except (serial.SerialException, OSError, ValueError) as exc:
        errno = getattr(exc, "errno", None)
        reason = os.strerror(errno) if isinstance(errno, int) else str(exc)
        raise PortError(f"cannot open port {port!r}: {reason}") from exc


class _Mailbox:
    """The unsolicited queue: bounded, and never blocks the reader (drops the oldest)."""

    def __init__(self, maxlen: int) -> None:
        self._items: Deque[Packet] = collections.deque()
        self._maxlen = maxlen
        self._cond = threading.Condition()
        self.dropped = 0

    def put(self, p: Packet) -> None:
        with self._cond:
            if len(self._items) >= self._maxlen:
                self._items.popleft()
                self.dropped += 1
            self._items.append(p)
            self._cond.notify_all()

    def get(self, timeout: Optional[float]) -> Optional[Packet]:
        with self._cond:
            if not self._cond.wait_for(lambda: bool(self._items), timeout):
                return None
            return self._items.popleft()

    def drain(self) -> list[Packet]:
        with self._cond:
            items = list(self._items)
            self._items.clear()
            return items


class Link:
    """A serial connection to BrainStem modules, with its background reader thread.

    `port`: a pyserial port name or URL (`/dev/ttyUSB0`, a pty path such as `/dev/pts/5`,
    `socket://host:port`, `loop://`, `spy://...`), or an open serial-like object.

    Options:
    `baudrate` (9600, the module's rate after reset);
    `resync_addr` (2: the module address A whose probe replies `A 00 A 00` end a resync);
    `inter_byte_timeout` (0.1 s: a partial packet is dropped, and the link resynchronized,
    after this long without a byte; None = never, as the original);
    `resync_timeout` (0.25 s to wait for the probe replies before probing again);
    `answer_heartbeats` (True: answer `0, t` with `0, t+2`);
    `on_unsolicited` (a callback given each unsolicited `Packet` in the reader thread, in
    place of the queue); `unsolicited_maxlen` (1024: beyond it the queue drops its oldest);
    `write_timeout` (2 s: a write that cannot complete raises LinkError);
    `flush_on_open` (True: discard what waits on the port, as the original does);
    `poll_interval` (0.01 s: how often the reader checks the timeouts)."""

    def __init__(
        self,
        port: str | SerialLike,
        *,
        baudrate: int = DEFAULT_BAUDRATE,
        resync_addr: int = P.DEFAULT_MODULE_ADDR,
        inter_byte_timeout: Optional[float] = DEFAULT_INTER_BYTE_TIMEOUT,
        resync_timeout: float = DEFAULT_RESYNC_TIMEOUT,
        answer_heartbeats: bool = True,
        on_unsolicited: Optional[Callable[[Packet], None]] = None,
        unsolicited_maxlen: int = 1024,
        write_timeout: Optional[float] = 2.0,
        flush_on_open: bool = True,
        poll_interval: float = 0.01,
    ) -> None:
        self._parser = FrameParser(resync_addr, inter_byte_timeout, resync_timeout)
        if isinstance(port, str):
            self.port_name = port
            self._ser: Any = open_serial(port, baudrate, poll_interval, write_timeout)
        else:
            self.port_name = str(getattr(port, "name", None) or getattr(port, "port", None) or port)
            self._ser = port
            try:
                self._ser.timeout = poll_interval
            except (AttributeError, ValueError):
                pass
        self.baudrate = baudrate
        self.answer_heartbeats = answer_heartbeats
        self.stats = LinkStats()
        self._resync_base = resync_timeout
        self._on_unsolicited = on_unsolicited
        self._mailbox = _Mailbox(unsolicited_maxlen)
        self._listeners: list[Callable[[LinkEvent], None]] = []
        self._lock = threading.RLock()  # calls in flight, timer waiters
        # Taken before _lock: registration + write. Re-entrant, so that a listener (called
        # after a write, in the writing thread) may itself send.
        self._send_lock = threading.RLock()
        self._pending: list[Transaction] = []
        self._timers: dict[tuple[int, int], Deque[TimerWaiter]] = {}
        # Results held until a start is confirmed, numbered as counted in _timer_rx.
        self._parked: dict[tuple[int, int], list[tuple[int, Packet]]] = {}
        self._timer_rx: dict[tuple[int, int], int] = {}
        self._needs_sync: set[int] = set()
        self._seq = itertools.count()
        self._tags = itertools.cycle(range(256))
        self._hold_until = 0.0
        self._closed = False
        self._broken: Optional[BaseException] = None
        self._stop = threading.Event()
        if flush_on_open:
            try:
                self._ser.reset_input_buffer()
            except Exception:  # noqa: BLE001 - a port that cannot flush still works
                pass
        self._reader = threading.Thread(target=self._run, name="brainstem_dio-reader", daemon=True)
        self._reader.start()

    # ---- public ------------------------------------------------------------------------------
    @property
    def resync_addr(self) -> int:
        return self._parser.resync_addr

    @property
    def inter_byte_timeout(self) -> Optional[float]:
        return self._parser.inter_byte_timeout

    @property
    def is_open(self) -> bool:
        """False once closed or once the port failed."""
        return not self._closed and self._broken is None

    @property
    def resyncing(self) -> bool:
        """True between a framing error and the probe replies that end its resync."""
        return self._parser.resyncing

    def module(self, addr: int = P.DEFAULT_MODULE_ADDR, **options: Any) -> Module:
        """A `Module` for the module at `addr` on this link (options as `Module`'s)."""
        from .module import Module

        return Module(self, addr, **options)

    def add_listener(self, fn: Callable[[LinkEvent], None]) -> None:
        """Call `fn(event)` for everything sent and received: in the reader thread for what
        arrives, in the writing thread for what is sent."""
        with self._lock:
            self._listeners.append(fn)

    def remove_listener(self, fn: Callable[[LinkEvent], None]) -> None:
        with self._lock:
            if fn in self._listeners:
                self._listeners.remove(fn)

    def receive(self, timeout: Optional[float] = None) -> Packet:
        """The next unsolicited packet: the power-up message, cmdQOverflow, a timer result
        nobody waits for, answers to raw `send_packet`s, anything no call claims. Raises
        `Timeout` if none comes within `timeout` seconds (None = wait for ever)."""
        self._check_not_reader()
        p = self._mailbox.get(timeout)
        if p is None:
            raise Timeout(f"no unsolicited packet within {timeout} s")
        return p

    def drain(self) -> list[Packet]:
        """Every unsolicited packet waiting, oldest first, without blocking."""
        return self._mailbox.drain()

    def send_bytes(self, raw: bytes) -> None:
        """Write bytes exactly as given (no framing, no attribution; for framing tests).
        The module's answers go to whichever call is in flight, else to the queue."""
        self._check_usable()
        with self._send_lock:
            self._write_locked(bytes(raw), [], note="raw")

    def send_packet(self, addr: int, data: bytes | Iterable[int] = b"", n: Optional[int] = None) -> None:
        """Write one packet `addr, N, data` and return (`n` overrides the length byte). Its
        answers are not attributed: with no call in flight they go to the unsolicited queue."""
        data = bytes(data)
        wire = bytes([addr & 0xFF, (len(data) if n is None else n) & 0xFF]) + data
        self._check_usable()
        with self._send_lock:
            self._write_locked(wire, [wire] if n is None else [], note="raw")

    def diagnosis(self) -> str:
        """A hint about the link's state for an error message ('' when it looks fine)."""
        s = self.stats
        if self._broken is not None:
            return f"; the port failed: {self._broken}"
        if self.resyncing:
            return (
                f"; the link is resynchronizing after {s.framing_errors} framing error(s)"
                f" (wrong baud rate? {self.baudrate} now)"
            )
        if s.bytes_in == 0:
            return (
                f"; nothing at all was received on {self.port_name} (module connected and"
                f" powered? baud rate {self.baudrate}? address right?)"
            )
        if s.last_framing_error is not None and time.monotonic() - s.last_framing_error < 5:
            return f"; {s.framing_errors} framing error(s) on the link so far"
        return ""

    def close(self) -> None:
        """Stop the reader, close the port, fail every call still waiting with LinkError."""
        if self._closed:
            return
        self._closed = True
        self._stop.set()
        me = threading.current_thread()
        if me is not self._reader:
            self._reader.join(timeout=0.5)  # a read returns within poll_interval
        try:
            self._ser.close()  # also ends a read that does not honour the timeout
        except Exception:  # noqa: BLE001
            pass
        if me is not self._reader:
            self._reader.join(timeout=1.0)
        self._fail_all(LinkError("the link was closed"))
        self._emit(LinkEvent("closed", time.monotonic()))

    def __enter__(self) -> Link:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ---- calls (used by Module) ------------------------------------------------------------------
    def submit(
        self,
        addr: int,
        wire: bytes,
        *,
        command: Optional[bytes] = None,
        expect: Optional[Callable[[Packet], bool]] = None,
        label: str = "",
        internal: bool = False,
        detached: bool = False,
        timer: Optional[TimerWaiter] = None,
        on_done: Optional[Callable[[Transaction], None]] = None,
        reset: bool = False,
    ) -> Transaction:
        """Register a call and write its bytes `wire` (may be empty).

        With `expect` the call is a reply call: it ends at the first packet from `addr` that
        `expect` accepts, or at a message. Without, the link appends a tagged sync echo and
        the call ends at that echo. `reset`: `wire` is a cmdRESET; the call ends at the
        power-up message (or a message) and fails every call to `addr` written before it
        with ModuleReset. `detached`: nobody waits; what the call collects goes to the
        unsolicited queue. `timer`: a TimerWaiter registered with the call.
        `on_done(call)`: run when the call ends (in the thread that ends it)."""
        self._check_usable()
        with self._send_lock:
            with self._lock:
                self._check_usable()
                packets = [wire] if wire else []
                if reset:
                    expect = _is_power_up
                    kind = "reset"
                elif expect is None:
                    echo = bytes([addr, 3, P.CMD_DEBUG, SYNC_MARK, next(self._tags)])
                    expect = exact_match(echo)
                    packets.append(echo)
                    kind = "echo"
                else:
                    kind = "reply"
                t = Transaction(self, next(self._seq), addr, command, kind, expect, label, internal, detached)
                if on_done is not None:
                    t._callbacks.append(on_done)
                self._pending.append(t)
                if timer is not None:
                    key = (addr, timer.dev_id)
                    timer.seq = t.seq
                    timer.mark = self._timer_rx.get(key, 0)
                    self._timers.setdefault(key, collections.deque()).append(timer)
            try:
                self._write_locked(b"".join(packets), packets, label, sync_last=kind == "echo")
            except LinkError:
                with self._lock:
                    if t in self._pending:
                        self._pending.remove(t)
                    self._drop_timer(timer)
                raise
            t.sent_at = time.monotonic()
        return t

    def timer_started(self, w: TimerWaiter, t: Transaction) -> None:
        """The PTIME_RD call that carries `w` ended: a confirmed start, an error message (the
        measurement never started), or no answer (it may have started: `w` becomes
        unconfirmed; it is never given a result, and the next confirmed start drops it)."""
        actions: list[Action] = []
        unsolicited: list[Packet] = []
        with self._lock:
            key = (w.addr, w.dev_id)
            dq = self._timers.get(key)
            if w.state != "starting" or dq is None or w not in dq:
                return  # ended meanwhile (a reset, the link closed)
            if t.exc is None and t.error is None:
                self._confirmed(key, dq, w, actions, unsolicited)
            elif t.exc is None:  # an error message: nothing started
                assert t.error is not None
                dq.remove(w)
                w.state = "done"
                w.exc = module_error(t.error, t.command)
                actions.append(w.event.set)
            else:
                w.state = "unconfirmed"
                w.exc = t.exc
                actions.append(w.event.set)
            self._tidy(key, unsolicited)
        for act in actions:
            act()
        self.put_unsolicited(unsolicited)

    def _confirmed(
        self, key: tuple[int, int], dq: Deque[TimerWaiter], w: TimerWaiter, actions: list[Action], unsolicited: list[Packet]
    ) -> None:
        """The module confirmed `w`'s start (lock held). It ran the PTIME_RD with the timer
        free, so every earlier result of this timer had left before: the waits ahead of `w`
        are stale, and of the results held, at most the last is `w`'s."""
        w.state = "running"
        unsure = 0  # waits ahead that may have sent a result after w's PTIME_RD was written
        for old in list(itertools.takewhile(lambda o: o is not w, dq)):
            dq.remove(old)
            if old.state in ("unconfirmed", "ghost"):
                unsure += 1
            if old.state == "running":
                if old.candidate is not None:  # nothing followed it: it was old's own
                    self._deliver(old, old.candidate, actions)
                else:
                    old.state = "done"
                    old.exc = ProtocolError(
                        f"the result of module {w.addr}'s timer (device ID {w.dev_id}) was lost: the module"
                        " has started the next measurement on that timer" + self.diagnosis()
                    )
                    actions.append(old.event.set)
            elif old.candidate is not None:  # a ghost's
                unsolicited.append(old.candidate)
        held = self._parked.pop(key, [])
        unsolicited.extend(p for n, p in held if n <= w.mark)  # before the PTIME_RD was written
        after = [p for n, p in held if n > w.mark]
        if not after:
            return
        unsolicited.extend(after[:-1])
        if len(after) > unsure:
            dq.remove(w)
            self._deliver(w, after[-1], actions)
        else:
            w.candidate = after[-1]
            w.candidate_until = time.monotonic() + P.TIMER_TIMEOUT_S + CANDIDATE_SLACK

    def _deliver(self, w: TimerWaiter, p: Packet, actions: list[Action]) -> None:
        w.state = "done"
        w.result = p
        w.candidate = None
        actions.append(w.event.set)

    def _tidy(self, key: tuple[int, int], unsolicited: list[Packet]) -> None:
        """Forget an empty wait list; release held results once no start is unconfirmed
        (each taking a given-up wait at the head along: results come in order)."""
        dq = self._timers.get(key)
        if not any(o.state == "starting" for o in dq or ()):
            for _, p in self._parked.pop(key, []):
                if dq and dq[0].state == "ghost":
                    dq.popleft()
                unsolicited.append(p)
        if dq is not None and not dq:
            del self._timers[key]

    def _settle_candidate(self, w: TimerWaiter, now: float, actions: list[Action]) -> bool:
        """Give a running wait its held result once nothing followed it in time (lock held)."""
        if w.candidate is None or w.state != "running" or now < w.candidate_until:
            return False
        dq = self._timers.get((w.addr, w.dev_id))
        if dq is not None and w in dq:
            dq.remove(w)
            if not dq:
                del self._timers[(w.addr, w.dev_id)]
        self._deliver(w, w.candidate, actions)
        return True

    def wait_timer(self, w: TimerWaiter, timeout: Optional[float]) -> Packet:
        """The result packet for `w`. Raises `Timeout` if it does not come in time (a result
        that comes later goes to the unsolicited queue)."""
        self._check_not_reader()
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            actions: list[Action] = []
            with self._lock:
                self._settle_candidate(w, time.monotonic(), actions)
                until = w.candidate_until if w.candidate is not None else None
            for act in actions:
                act()
            ends = [x for x in (deadline, until) if x is not None]
            left = None if not ends else max(0.0, min(ends) - time.monotonic())
            if w.event.wait(left):
                break
            if deadline is not None and time.monotonic() >= deadline:
                with self._lock:
                    if w.result is None and w.exc is None:
                        w.state = "ghost"
                        raise Timeout(
                            f"no timer result from module {w.addr} (device ID {w.dev_id}) within"
                            f" {timeout:.3g} s" + self.diagnosis()
                        )
                w.event.wait()
                break
        if w.result is not None:
            return w.result
        assert w.exc is not None
        raise w.exc

    def mark_needs_sync(self, addr: int) -> None:
        """Make the next call to `addr` sync first (a reply did not fit: the stream may hold
        answers that are not the next call's)."""
        with self._lock:
            self._needs_sync.add(addr)

    def take_needs_sync(self, addr: int) -> bool:
        """Whether a call to `addr` timed out since the last sync; clears the flag."""
        with self._lock:
            if addr in self._needs_sync:
                self._needs_sync.discard(addr)
                return True
            return False

    def put_unsolicited(self, packets: Iterable[Packet]) -> None:
        """Hand packets to the unsolicited queue (or callback)."""
        for p in packets:
            self._unsolicited(p)

    # ---- internals: writing ------------------------------------------------------------------------
    def _check_usable(self) -> None:
        if self._closed:
            raise LinkError("the link is closed")
        if self._broken is not None:
            raise LinkError(f"the port failed: {self._broken}")

    def _check_not_reader(self) -> None:
        if threading.current_thread() is self._reader:
            raise RuntimeError("a blocking brainstem_dio call cannot be made from a link callback")

    def _write_locked(self, raw: bytes, packets: list[bytes], note: str, sync_last: bool = False) -> None:
        """Write `raw` (the send lock is held). `packets`: the packets it consists of."""
        hold = self._hold_until - time.monotonic()
        if hold > 0:
            time.sleep(hold)
        try:
            self._ser.write(raw)
        except Exception as exc:  # noqa: BLE001 - any port failure
            raise LinkError(f"write to {self.port_name} failed: {exc}") from exc
        now = time.monotonic()
        if not packets:
            self._emit(LinkEvent("tx", now, None, raw, note))
            return
        for i, wire in enumerate(packets):
            self.stats.packets_out += 1
            p = Packet(wire[0], wire[2:], now) if len(wire) >= 2 and wire[1] == len(wire) - 2 else None
            internal = sync_last and i == len(packets) - 1
            self._emit(LinkEvent("tx", now, p, wire, "sync" if internal else note, internal))

    # ---- internals: the reader -------------------------------------------------------------------
    def _run(self) -> None:
        ser = self._ser
        while not self._stop.is_set():
            try:
                waiting = ser.in_waiting
                data = ser.read(waiting if waiting > 0 else 1)
            except Exception as exc:  # noqa: BLE001 - any port failure ends the link
                if not self._stop.is_set():
                    self._port_failed(exc)
                return
            now = time.monotonic()
            if data:
                self.stats.bytes_in += len(data)
                self.stats.last_rx = now
                events = self._parser.feed(data, now)
            else:
                events = self._parser.poll(now)
            for ev in events:
                try:
                    self._handle(ev)
                except LinkError as exc:
                    if not self._stop.is_set():
                        self._port_failed(exc)
                    return
                except Exception:  # noqa: BLE001 - a bug must not kill the reader silently
                    log.exception("brainstem_dio: error while handling %r", ev)

    def _port_failed(self, exc: BaseException) -> None:
        self._broken = exc
        self._fail_all(LinkError(f"the port failed: {exc}"))
        self._emit(LinkEvent("error", time.monotonic(), note=str(exc)))

    def _handle(self, ev: object) -> None:
        if isinstance(ev, Packet):
            self.stats.packets_in += 1
            self._packet(ev)
        elif isinstance(ev, FramingError):
            self.stats.framing_errors += 1
            self.stats.last_framing_error = ev.time
            self._emit(LinkEvent("framing", ev.time, raw=ev.dropped, note=ev.reason))
            self._resync()
        elif isinstance(ev, ResyncTimeout):
            self.stats.resync_timeouts += 1
            self._parser.resync_timeout = min(2.0, self._parser.resync_timeout * 2)
            self._emit(LinkEvent("resync-timeout", ev.time))
            self._resync()
        elif isinstance(ev, Resynced):
            self.stats.resyncs += 1
            self._parser.resync_timeout = self._resync_base
            self._emit(LinkEvent("resync", ev.time, note=f"{ev.discarded} byte(s) discarded"))

    def _resync(self) -> None:
        """Flush the input (until FLUSH_QUIET of silence, FLUSH_MAX at most), then send the
        probes `AD 00 AD 00`. Every call written before the probes has lost its answer."""
        ser = self._ser
        try:
            ser.reset_input_buffer()
        except Exception:  # noqa: BLE001
            pass
        start = last = time.monotonic()
        while not self._stop.is_set():
            now = time.monotonic()
            if now - last >= FLUSH_QUIET or now - start >= FLUSH_MAX:
                break
            try:
                waiting = ser.in_waiting
                data = ser.read(waiting if waiting > 0 else 1)
            except Exception as exc:  # noqa: BLE001
                raise LinkError(str(exc)) from exc
            if data:
                self.stats.bytes_in += len(data)
                last = time.monotonic()
        probe = bytes([P.ADDR_RESYNC, 0])
        with self._send_lock:
            with self._lock:
                mark = next(self._seq)
                lost = [t for t in self._pending if t.seq < mark]
            self._write_locked(probe + probe, [probe, probe], note="resync probe")
        self._parser.probes_sent(time.monotonic())
        if lost:
            self._fail(lost, ResyncError("a framing error on the link lost the answer (the link resynchronized)"))

    def _packet(self, p: Packet) -> None:
        if p.is_heartbeat:
            self.stats.heartbeats += 1
            self.stats.last_heartbeat = p.time
            self._emit(LinkEvent("rx", p.time, p, p.to_bytes(), "heartbeat"))
            if self.answer_heartbeats:
                answer = bytes([p.addr, 2, P.CMD_HB, p.data[1] + P.HB_ANSWER_OFFSET])
                self._check_usable()
                with self._send_lock:
                    self._write_locked(answer, [answer], note="heartbeat answer")
                self.stats.heartbeat_answers += 1
            return
        note = "unsolicited"
        internal = False
        unsolicited: list[Packet] = []
        actions: list[Action] = []
        with self._lock:
            if p.cmd == P.CMD_DEV_VAL and p.n == 4:
                note = self._timer_result(p, unsolicited, actions)
            elif p.is_message and p.message_code == P.MSG_STATE_POWER_RESET:
                r = next((t for t in self._pending if t.addr == p.addr and t.kind == "reset"), None)
                if r is not None:
                    self._reset_done(r, p, actions, unsolicited)
                    note = r.label
                else:
                    unsolicited.append(p)
                    self._module_reset(p.addr, actions, unsolicited)
            elif p.is_message and p.message_code in P.UNSOLICITED_MESSAGES:
                unsolicited.append(p)
                self._hold_until = time.monotonic() + OVERFLOW_HOLD
            else:
                t = self._attribute(p, actions, unsolicited)
                if t is not None:
                    note = t.label
                    internal = t.kind == "echo" and p is t.reply
        self._emit(LinkEvent("rx", p.time, p, p.to_bytes(), note, internal))
        for act in actions:
            act()
        for u in unsolicited:
            self._unsolicited(u)

    def _attribute(self, p: Packet, actions: list[Action], unsolicited: list[Packet]) -> Optional[Transaction]:
        """Give `p` to the call it belongs to (lock held); returns that call or None."""
        calls = [t for t in self._pending if t.addr == p.addr]
        if not calls:
            unsolicited.append(p)
            return None
        head = calls[0]
        if head.match(p):
            head.reply = p
            self._complete(head, actions, unsolicited)
            return head
        if p.is_message:
            if head.kind == "reset" and p.message_code != P.MSG_CMD_INVALID:
                # A late answer of a call that timed out (reset() does not sync first);
                # cmdInvalid is the answer of a module without cmdRESET.
                unsolicited.append(p)
                return None
            if head.kind != "echo":
                head.error = p
                self._complete(head, actions, unsolicited)
            else:
                head.packets.append(p)
                if head.error is None:
                    head.error = p
            return head
        for i, later in enumerate(calls[1:], start=1):
            if later.kind == "echo" and later.match(p):
                # Its echo is unique: every call before it has lost its answer.
                for lost in calls[:i]:
                    lost.exc = ProtocolError(
                        f"module {lost.addr} answered a later call: the answer to {lost.label} was lost"
                    )
                    self._complete(lost, actions, unsolicited)
                later.reply = p
                self._complete(later, actions, unsolicited)
                return later
        if head.kind == "echo":
            head.packets.append(p)
            return head
        unsolicited.append(p)
        return None

    def _complete(self, t: Transaction, actions: list[Action], unsolicited: list[Packet]) -> None:
        if t in self._pending:
            self._pending.remove(t)
        if t.detached:
            unsolicited.extend(t.packets)
        actions.extend(t._finish())

    def _timer_result(self, p: Packet, unsolicited: list[Packet], actions: list[Action]) -> str:
        key = (p.addr, p.data[1])
        n = self._timer_rx.get(key, 0) + 1
        self._timer_rx[key] = n
        dq = self._timers.get(key)
        starting = bool(dq) and any(o.state == "starting" for o in dq)  # type: ignore[union-attr]
        while dq:
            w = dq[0]
            if w.state == "running" and self._settle_candidate(w, time.monotonic(), actions):
                continue  # the held result was w's; this one is a later measurement's
            # A given-up measurement takes its late result, unless a start is unconfirmed:
            # its result was perhaps lost on the line and this is the new measurement's.
            if w.state != "running" and not (w.state == "ghost" and not starting):
                break
            dq.popleft()
            if not dq:
                del self._timers[key]
            if w.candidate is not None:  # a result after w's start was confirmed is w's
                unsolicited.append(w.candidate)
                w.candidate = None
            if w.state == "ghost":
                unsolicited.append(p)
                return "late timer result"
            self._deliver(w, p, actions)
            return "timer result"
        if starting:
            self._parked.setdefault(key, []).append((n, p))
            return "timer result (held until its start is confirmed)"
        unsolicited.append(p)
        return "unsolicited timer result"

    def _module_reset(self, addr: int, actions: list[Action], unsolicited: list[Packet]) -> None:
        """The module reset on its own: the measurements it had confirmed are gone (a start
        not yet confirmed may have been sent after the reset and stays)."""
        for key, dq in list(self._timers.items()):
            if key[0] != addr:
                continue
            for w in list(dq):
                if w.state in ("ghost", "unconfirmed"):
                    dq.remove(w)
                elif w.state == "running":
                    dq.remove(w)
                    w.state = "done"
                    w.exc = ModuleReset(f"module {addr} reset during the measurement")
                    actions.append(w.event.set)
            self._tidy(key, unsolicited)
        for key in [k for k in self._parked if k[0] == addr]:
            unsolicited.extend(p for _, p in self._parked.pop(key))

    def _reset_done(self, r: Transaction, p: Packet, actions: list[Action], unsolicited: list[Packet]) -> None:
        """The power-up message that answers the cmdRESET call `r` (lock held). The module
        dropped everything it had not sent: every call to it written before `r` and every
        timer wait whose PTIME_RD was fail with ModuleReset."""
        addr = r.addr
        for t in [t for t in self._pending if t.addr == addr and t.seq < r.seq]:
            t.exc = ModuleReset(f"module {addr} was reset before it answered {t.label}")
            self._complete(t, actions, unsolicited)
        for key, dq in list(self._timers.items()):
            if key[0] != addr:
                continue
            for w in [w for w in dq if w.seq < r.seq]:
                dq.remove(w)
                if w.state in ("starting", "running"):
                    w.exc = ModuleReset(f"module {addr} was reset during the measurement")
                    actions.append(w.event.set)
                w.state = "done"
            self._tidy(key, unsolicited)
        for key in [k for k in self._parked if k[0] == addr]:
            unsolicited.extend(q for _, q in self._parked.pop(key))
        self._needs_sync.discard(addr)
        r.reply = p
        self._complete(r, actions, unsolicited)

    def _drop_timer(self, w: Optional[TimerWaiter]) -> None:
        if w is None:
            return
        key = (w.addr, w.dev_id)
        dq = self._timers.get(key)
        if dq is not None and w in dq:
            dq.remove(w)
            if not dq:
                del self._timers[key]

    def _abandon(self, t: Transaction) -> bool:
        """A call gave up waiting; False if it ended meanwhile. The module is marked for a
        sync before its next call, so that a late answer is not taken for a later call's."""
        with self._lock:
            if t._finished:
                return False
            if t in self._pending:
                self._pending.remove(t)
            self._needs_sync.add(t.addr)
            t.exc = Timeout(f"no answer to {t.label}")
            actions = t._finish()
        for act in actions:
            act()
        return True

    def _fail(self, calls: list[Transaction], exc: BaseException) -> None:
        actions: list[Action] = []
        with self._lock:
            for t in calls:
                if t._finished:
                    continue
                t.exc = exc
                if t in self._pending:
                    self._pending.remove(t)
                actions.extend(t._finish())
        for act in actions:
            act()

    def _fail_all(self, exc: BaseException) -> None:
        with self._lock:
            calls = list(self._pending)
            waiters = [w for dq in self._timers.values() for w in dq]
            self._timers.clear()
            self._parked.clear()
            for w in waiters:
                if w.result is None and w.exc is None:
                    w.exc = exc
        self._fail(calls, exc)
        for w in waiters:
            w.event.set()

    def _unsolicited(self, p: Packet) -> None:
        self.stats.unsolicited += 1
        if self._on_unsolicited is not None:
            try:
                self._on_unsolicited(p)
            except Exception:  # noqa: BLE001
                log.exception("brainstem_dio: on_unsolicited callback failed")
            return
        self._mailbox.put(p)
        self.stats.unsolicited_dropped = self._mailbox.dropped

    def _emit(self, ev: LinkEvent) -> None:
        with self._lock:
            listeners = list(self._listeners)
        for fn in listeners:
            try:
                fn(ev)
            except Exception:  # noqa: BLE001
                log.exception("brainstem_dio: listener failed")


def _is_power_up(p: Packet) -> bool:
    return p.is_message and p.message_code == P.MSG_STATE_POWER_RESET


def exact_match(wire: bytes) -> Callable[[Packet], bool]:
    """A matcher for exactly the packet `wire` (address, N, data)."""
    addr, data = wire[0], wire[2:]
    return lambda p: p.addr == addr and p.data == data
