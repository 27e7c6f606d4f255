# SPDX-License-Identifier: Apache-2.0
"""Test doubles for the host library: an in-memory serial pair, a socket end, and a fake
module (the testbenches' model of the core, tb/lib/bsd_model.py, on a line) behind them."""

from __future__ import annotations

import select
import socket
import threading
import time
from collections.abc import Callable
from typing import Any

from brainstem_dio import protocol as P
from bsd_model import Event, Framing, Model, Output, Params, PartialDropped, Reset, TimerStarted, message


class PortClosed(OSError):
    """Reading or writing a closed end (what pyserial raises for a vanished device)."""


class PipeEnd:
    """One end of an in-memory serial line, with pyserial's read/write/timeout interface."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.timeout: float | None = None
        self.is_open = True
        self.peer: PipeEnd | None = None
        self._buf = bytearray()
        self._cond = threading.Condition()
        self.written = bytearray()  # everything this end wrote

    def write(self, data: bytes) -> int:
        if not self.is_open or self.peer is None or not self.peer.is_open:
            raise PortClosed(f"{self.name}: the line is closed")
        self.written += data
        with self.peer._cond:
            self.peer._buf += data
            self.peer._cond.notify_all()
        return len(data)

    def read(self, size: int = 1) -> bytes:
        with self._cond:
            peer_gone = lambda: self.peer is None or not self.peer.is_open
            self._cond.wait_for(lambda: self._buf or not self.is_open or peer_gone(), self.timeout)
            if not self.is_open:
                raise PortClosed(f"{self.name}: closed")
            if not self._buf and peer_gone():
                raise PortClosed(f"{self.name}: the other end went away")
            out = bytes(self._buf[:size])
            del self._buf[:size]
            return out

    @property
    def in_waiting(self) -> int:
        return len(self._buf)

    def reset_input_buffer(self) -> None:
        with self._cond:
            self._buf.clear()

    def close(self) -> None:
        self.is_open = False
        for end in (self, self.peer):
            if end is not None:
                with end._cond:
                    end._cond.notify_all()


def serial_pair() -> tuple[PipeEnd, PipeEnd]:
    """(host end, device end)."""
    a, b = PipeEnd("host"), PipeEnd("device")
    a.peer, b.peer = b, a
    return a, b


class SocketEnd:
    """A connected socket with the same read/write interface (the fake's side of socket://)."""

    def __init__(self, sock: socket.socket) -> None:
        self.sock = sock
        self.timeout: float | None = None
        self.is_open = True
        self.name = "socket"

    def write(self, data: bytes) -> int:
        self.sock.sendall(data)
        return len(data)

    def read(self, size: int = 1) -> bytes:
        ready, _, _ = select.select([self.sock], [], [], self.timeout)
        if not ready:
            return b""
        data = self.sock.recv(size)
        if not data:
            raise PortClosed("socket closed")
        return data

    @property
    def in_waiting(self) -> int:
        return 0

    def reset_input_buffer(self) -> None:
        pass

    def close(self) -> None:
        self.is_open = False
        try:
            self.sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        self.sock.close()


class FakeModel(Model):
    """The testbenches' model of the core (tb/lib/bsd_model.py) with the fake's own switches
    on the packets it takes: `fake.on_packet` sees every whole packet first, and a module
    without cmdRESET (`fake.knows_reset` False) refuses it as cmdInvalid."""

    def __init__(self, fake: FakeModule, params: Params, levels: int) -> None:
        self.fake = fake
        super().__init__(params, levels)

    def packet(self, addr: int, data: bytes, out: Output) -> None:
        fake = self.fake
        fake.received.append((addr, data))
        if addr == self.p.module_addr and data[0] == P.CMD_HB and len(data) >= 2:
            fake.hb_answers.append(data[1])
        if fake.on_packet is not None and fake.on_packet(addr, data):
            return
        if addr == self.p.module_addr and data[0] == P.CMD_RESET and not fake.knows_reset:
            out.packets.append(message(addr, P.MSG_CMD_INVALID))
            return
        super().packet(addr, data, out)
        # An instant timer's result leaves before anything the next packet causes, as the
        # core's does for a pulse shorter than the bytes of the PTIME_RD's sync echo.
        for pin in fake.instant_done:
            out.extend(self.timer_complete(pin, fake.timer_results[pin] or 0))
        fake.instant_done.clear()


class FakeModule:
    """A fake BrainStem module on `port` (the device end of a line).

    What the module decides (framing, the resync probe, the inter-byte timeout, every command
    and its errors with their precedence, the cmdDEBUG echo, cmdRESET: back to the power-up
    state, running timers stopped, the power-up message as its answer) is the testbenches'
    model of the core, `bsd_model.Model` (`model`). The fake adds the line and the clock: a
    started measurement completes after `timer_delay` s with `timer_results[pin]` ticks, or
    times out with 0 after `timer_timeout_s` when that is None; heartbeats on demand; host
    packets recorded (`received`, `hb_answers`, `probes`, `resets`, `dropped_partials`).

    Knobs for tests: `mute` (answer nothing), `reply_delay` (s before each answer),
    `instant_timers` (a measurement with a result in `timer_results` completes at once),
    `knows_reset` (False: a module without cmdRESET), `inject(raw)` (send bytes to the host),
    `on_packet` (a hook given each host packet; returning True means it was handled)."""

    def __init__(
        self,
        port: Any,
        *,
        addr: int = 2,
        num_pins: int = 5,
        timer_mask: int = 0b11110,
        fixed: dict[int, int] | None = None,
        pin_id_base: int = 5,
        timer_id_base: int = 10,
        rx_timeout: float | None = 0.0256,
        power_up: bool = True,
        levels: int = 0,
    ) -> None:
        self.port = port
        self.port.timeout = 0.005
        self.addr = addr
        fixed = dict(fixed or {})
        params = Params(
            module_addr=addr,
            num_pins=num_pins,
            timer_mask=timer_mask,
            fixed_mask=sum(1 << p for p in fixed),
            fixed_cfg=sum((cfg & P.DIGCFG_STORED) << (8 * p) for p, cfg in fixed.items()),
            pin_id_base=pin_id_base,
            timer_id_base=timer_id_base,
            rx_timeout_us=round(rx_timeout * 1e6) if rx_timeout else 0,
        )
        self.timer_results: dict[int, int | None] = {}
        self.timer_delay = 0.005
        self.instant_timers = False
        self.instant_done: list[int] = []  # instant measurements started by the packet in hand
        self.timer_timeout_s = P.TIMER_TIMEOUT_S
        self.reply_delay = 0.0
        self.mute = False
        self.knows_reset = True  # False: a module without cmdRESET (cmdInvalid)
        self.on_packet: Callable[[int, bytes], bool] | None = None
        self.received: list[tuple[int, bytes]] = []  # host packets, whole
        self.hb_answers: list[int] = []
        self.probes = 0
        self.dropped_partials = 0
        self.resets = 0
        self._lock = threading.RLock()  # the model, between the line's thread and the timers'
        self._send_lock = threading.Lock()
        self._stop = threading.Event()
        self._last = 0.0
        self._timers: list[threading.Timer] = []
        self._epoch = 0  # counts resets: a timer started before one never reports
        self.model = FakeModel(self, params, levels)
        self.model.observers.append(self._observe)
        self._thread = threading.Thread(target=self._run, name="fake-module", daemon=True)
        self._power_up = power_up

    # ---- the model's state, as the tests read it ----
    @property
    def cfg(self) -> list[int]:
        return self.model.cfg

    @property
    def out_latch(self) -> list[int]:
        return self.model.out_latch

    @property
    def busy(self) -> set[int]:
        """Pins whose timer is measuring."""
        return set(self.model.timers)

    @property
    def levels(self) -> int:
        return self.model.levels

    @levels.setter
    def levels(self, value: int) -> None:
        with self._lock:
            self.model.set_pins(value)  # latch firings do not reach the host line

    # ---- control ----
    def start(self) -> FakeModule:
        if self._power_up:
            self._send(message(self.addr, P.MSG_STATE_POWER_RESET))
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        for t in self._timers:
            t.cancel()
        self._thread.join(timeout=2)

    def inject(self, raw: bytes) -> None:
        """Bytes to the host, as they are."""
        self._send(bytes(raw))

    def heartbeat(self) -> int:
        """Send the next heartbeat (UP, DOWN, UP ...); returns its type."""
        with self._lock:
            out = self.model.heartbeat_due()
        for pk in out.packets:
            self._send(pk)
        return out.packets[0][3]

    def packets_with(self, cmd: int) -> list[bytes]:
        return [d for a, d in self.received if a == self.addr and d and d[0] == cmd]

    # ---- the line ----
    def _send(self, raw: bytes) -> None:
        with self._send_lock:
            try:
                self.port.write(raw)
            except OSError:
                pass

    def _answer(self, raw: bytes) -> None:
        if self.mute:
            return
        if self.reply_delay:
            time.sleep(self.reply_delay)
        self._send(raw)

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                data = self.port.read(64)
            except OSError:
                return
            if not data:
                continue
            now = time.monotonic()
            idle = now - self._last
            self._last = now
            # Byte by byte, each one's answers sent before the next byte is taken: a hook
            # that writes to the line sees every earlier answer already sent.
            for b in data:
                with self._lock:
                    out = self.model.feed([b], idle_before_s=idle)
                idle = 0.0
                for pk in out.packets:
                    self._answer(pk)

    # ---- what the model decided ----
    def _observe(self, ev: Event) -> None:
        if isinstance(ev, Framing):
            if ev.n == 0:
                self.received.append((ev.addr, b""))
                self.probes += ev.addr == P.ADDR_RESYNC
            elif ev.addr == self.addr:
                self.received.append((ev.addr, bytes([ev.n])))
        elif isinstance(ev, PartialDropped):
            self.dropped_partials += 1
        elif isinstance(ev, Reset):
            self.resets += 1
            self._epoch += 1
            for t in self._timers:
                t.cancel()
            self._timers = []
            self.instant_done.clear()
        elif isinstance(ev, TimerStarted):
            ticks = self.timer_results.get(ev.pin)
            if self.instant_timers and ticks is not None:
                self.instant_done.append(ev.pin)
                return
            delay = self.timer_timeout_s if ticks is None else self.timer_delay
            t = threading.Timer(delay, self._timer_done, (ev.pin, ticks or 0, self._epoch))
            t.daemon = True
            self._timers.append(t)
            t.start()

    def _timer_done(self, pin: int, ticks: int, epoch: int) -> None:
        with self._lock:
            if epoch != self._epoch:
                return  # stopped by a reset
            out = self.model.timer_complete(pin, ticks)
            if not self.mute:
                for pk in out.packets:
                    self._send(pk)


class FakeServer:
    """A FakeModule behind a TCP socket on 127.0.0.1 (for `socket://` URLs): serves one
    connection at a time, a fresh fake module for each."""

    def __init__(self, setup: Callable[[FakeModule], None] | None = None, **fake_options) -> None:
        self._listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self._listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self._listener.bind(("127.0.0.1", 0))
        self._listener.listen(4)
        self.port = self._listener.getsockname()[1]
        self.url = f"socket://127.0.0.1:{self.port}"
        self._setup = setup
        self._options = fake_options
        self.fakes: list[FakeModule] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def _serve(self) -> None:
        self._listener.settimeout(0.05)
        while not self._stop.is_set():
            try:
                conn, _ = self._listener.accept()
            except (TimeoutError, OSError):
                continue
            conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            fake = FakeModule(SocketEnd(conn), **self._options)
            if self._setup is not None:
                self._setup(fake)
            self.fakes.append(fake)
            fake.start()

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2)
        for f in self.fakes:
            f.stop()
            f.port.close()
        self._listener.close()


class FdEnd:
    """The master side of a pty (os.openpty) with the same read/write interface."""

    def __init__(self, fd: int) -> None:
        self.fd = fd
        self.timeout: float | None = None
        self.is_open = True
        self.name = "pty-master"

    def write(self, data: bytes) -> int:
        import os

        return os.write(self.fd, data)

    def read(self, size: int = 1) -> bytes:
        import os

        ready, _, _ = select.select([self.fd], [], [], self.timeout)
        if not ready:
            return b""
        return os.read(self.fd, size)

    @property
    def in_waiting(self) -> int:
        return 0

    def reset_input_buffer(self) -> None:
        pass

    def close(self) -> None:
        import os

        if self.is_open:
            self.is_open = False
            os.close(self.fd)


def wait_for(cond: Callable[[], object], timeout: float = 2.0, step: float = 0.002) -> bool:
    """Poll `cond` until it is true or `timeout` s pass; returns the last result."""
    deadline = time.monotonic() + timeout
    while True:
        if cond():
            return True
        if time.monotonic() >= deadline:
            return bool(cond())
        time.sleep(step)
