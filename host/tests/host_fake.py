# SPDX-License-Identifier: Apache-2.0
"""Test doubles for the host library: an in-memory serial pair, a socket end, and a fake
module (a small Python model of the core's packet behaviour, PROTOCOL.md) behind them."""

from __future__ import annotations

import select
import socket
import threading
import time
from typing import Callable, Optional

from brainstem_dio import protocol as P


class PortClosed(OSError):
    """Reading or writing a closed end (what pyserial raises for a vanished device)."""


class PipeEnd:
    """One end of an in-memory serial line, with pyserial's read/write/timeout interface."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.timeout: Optional[float] = None
        self.is_open = True
        self.peer: Optional[PipeEnd] = None
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
            peer_gone = lambda: self.peer is None or not self.peer.is_open  # noqa: E731
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
        self.timeout: Optional[float] = None
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


class FakeModule:
    """A fake BrainStem module on `port` (the device end of a line).

    The model follows PROTOCOL.md: framing (N > 8 -> serialError to its own address, the
    resync probe, other addresses ignored, the inter-byte timeout), every command and its
    errors with their precedence, the cmdDEBUG echo, cmdRESET (any N: back to the power-up
    state, running timers stopped, the power-up message as its answer; `resets` counts them),
    timers (a started measurement completes
    after `timer_delay` s with `timer_results[pin]` ticks, or times out with 0 after
    `timer_timeout_s` when that is None), heartbeats on demand, and answers recorded.

    Knobs for tests: `mute` (answer nothing), `reply_delay` (s before each answer),
    `instant_timers` (a measurement with a result in `timer_results` completes at once: its
    result leaves before anything the next packet causes, as the core's does for a pulse
    shorter than the bytes of the PTIME_RD's sync echo),
    `inject(raw)` (send bytes to the host), `on_packet` (a hook given each host packet;
    returning True means it was handled)."""

    def __init__(
        self,
        port,
        *,
        addr: int = 2,
        num_pins: int = 5,
        timer_mask: int = 0b11110,
        fixed: Optional[dict[int, int]] = None,
        pin_id_base: int = 5,
        timer_id_base: int = 10,
        rx_timeout: Optional[float] = 0.0256,
        power_up: bool = True,
        levels: int = 0,
    ) -> None:
        self.port = port
        self.port.timeout = 0.005
        self.addr = addr
        self.num_pins = num_pins
        self.timer_mask = timer_mask
        self.fixed = dict(fixed or {})
        self.pin_id_base = pin_id_base
        self.timer_id_base = timer_id_base
        self.rx_timeout = rx_timeout
        self.levels = levels
        self.cfg = [(self.fixed[p] & 0x1F) if p in self.fixed else P.DIGCFG_RESET for p in range(num_pins)]
        self.out_latch = [0] * num_pins
        self.busy: set[int] = set()
        self.timer_results: dict[int, Optional[int]] = {}
        self.timer_delay = 0.005
        self.instant_timers = False
        self.timer_timeout_s = P.TIMER_TIMEOUT_S
        self.reply_delay = 0.0
        self.mute = False
        self.on_packet: Optional[Callable[[int, bytes], bool]] = None
        self.received: list[tuple[int, bytes]] = []  # host packets, whole
        self.hb_answers: list[int] = []
        self.probes = 0
        self.dropped_partials = 0
        self._hb_next = P.HB_UP
        self._send_lock = threading.Lock()
        self._stop = threading.Event()
        self._state = "addr"
        self._pkt = bytearray()
        self._last = 0.0
        self._timers: list[threading.Timer] = []
        self._epoch = 0  # counts resets: a timer started before one never reports
        self.resets = 0
        self.knows_reset = True  # False: a module without cmdRESET (cmdInvalid)
        self._thread = threading.Thread(target=self._run, name="fake-module", daemon=True)
        self._power_up = power_up

    # ---- control ----
    def start(self) -> FakeModule:
        if self._power_up:
            self._send(bytes([self.addr, 2, P.CMD_MSG, P.MSG_STATE_POWER_RESET]))
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
        kind = self._hb_next
        self._hb_next ^= 1
        self._send(bytes([self.addr, 2, P.CMD_HB, kind]))
        return kind

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

    def _msg(self, code: int) -> None:
        self._answer(bytes([self.addr, 2, P.CMD_MSG, code]))

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                data = self.port.read(64)
            except OSError:
                return
            now = time.monotonic()
            if (
                self._state != "addr"
                and self.rx_timeout is not None
                and data
                and now - self._last > self.rx_timeout
            ):
                self._state = "addr"
                self.dropped_partials += 1
            for b in data:
                self._byte(b)
            if data:
                self._last = now

    def _byte(self, b: int) -> None:
        if self._state == "addr":
            self._pkt = bytearray([b])
            self._state = "len"
        elif self._state == "len":
            if b > P.MAX_N:
                self._state = "addr"
                if self._pkt[0] == self.addr:
                    self.received.append((self._pkt[0], bytes([b])))
                    self._msg(P.MSG_SERIAL_ERROR)
            elif b == 0:
                self._state = "addr"
                self.received.append((self._pkt[0], b""))
                if self._pkt[0] == P.ADDR_RESYNC:
                    self.probes += 1
                    self._answer(bytes([self.addr, 0]))
            else:
                self._pkt.append(b)
                self._state = "data"
        else:
            self._pkt.append(b)
            if len(self._pkt) == self._pkt[1] + 2:
                self._state = "addr"
                addr, data = self._pkt[0], bytes(self._pkt[2:])
                self.received.append((addr, data))
                if self.on_packet is not None and self.on_packet(addr, data):
                    return
                if addr == self.addr:
                    self._execute(data)

    # ---- commands ----
    def _execute(self, d: bytes) -> None:
        cmd = d[0]
        if cmd == P.CMD_HB:
            if len(d) >= 2:
                self.hb_answers.append(d[1])
            return
        if cmd == P.CMD_DEBUG:
            self._answer(bytes([self.addr, len(d)]) + d)
            return
        if cmd == P.CMD_RESET:
            if self.knows_reset:
                self._reset()
            else:
                self._msg(P.MSG_CMD_INVALID)
            return
        longest = P.CMD_MAX_N.get(cmd)
        if longest is None:
            self._msg(P.MSG_CMD_INVALID)
            return
        if len(d) < P.CMD_MIN_N[cmd]:
            self._msg(P.MSG_CMD_TOO_SHORT)
            return
        handler = {
            P.CMD_DIG_CFG: self._dig_cfg,
            P.CMD_DIG_IO: self._dig_io,
            P.CMD_DIG_RST: self._dig_rst,
            P.CMD_PTIME_RD: self._ptime_rd,
        }[cmd]
        error = handler(d[:longest])
        if error is not None:
            self._msg(error)
        elif len(d) > longest:
            self._msg(P.MSG_CMD_TOO_LONG)

    def _reset(self) -> None:
        with self._send_lock:  # no timer result may slip out between the reset and its answer
            self._epoch += 1
            self.resets += 1
            for t in self._timers:
                t.cancel()
            self._timers = []
            self.busy.clear()
            self.cfg = [(self.fixed[p] & 0x1F) if p in self.fixed else P.DIGCFG_RESET for p in range(self.num_pins)]
            self.out_latch = [0] * self.num_pins
            self._hb_next = P.HB_UP
        self._answer(bytes([self.addr, 2, P.CMD_MSG, P.MSG_STATE_POWER_RESET]))

    def _is_input(self, pin: int) -> bool:
        return bool(self.cfg[pin] & P.DIGCFG_IODIR)

    def _dig_cfg(self, d: bytes) -> Optional[int]:
        pin = d[1]
        if pin >= self.num_pins:
            return P.MSG_CMD_INDEX_ERR
        if len(d) == 2:
            value = self.cfg[pin] | (P.DIGCFG_FIXED if pin in self.fixed else 0)
            self._answer(bytes([self.addr, 3, P.CMD_DIG_CFG, pin, value]))
            return None
        if pin in self.fixed:
            return P.MSG_CONFIG_ERR
        self.cfg[pin] = d[2] & P.DIGCFG_STORED
        return None

    def _dig_io(self, d: bytes) -> Optional[int]:
        if len(d) == 2:
            pin = d[1] & P.DEVCODE_PIN
            if pin >= self.num_pins or not self._is_input(pin):
                return P.MSG_CMD_INDEX_ERR
            if d[1] & P.DEVCODE_HOST:
                self._answer(bytes([self.addr, 3, P.CMD_DEV_VAL, self.pin_id_base + pin, self.levels >> pin & 1]))
            return None
        pin = d[1]
        if pin >= self.num_pins or self._is_input(pin):
            return P.MSG_CMD_INDEX_ERR
        self.out_latch[pin] = int(d[2] != 0)
        return None

    def _dig_rst(self, d: bytes) -> Optional[int]:
        return P.MSG_CMD_INDEX_ERR if d[1] >= self.num_pins else None

    def _ptime_rd(self, d: bytes) -> Optional[int]:
        devcode = d[1]
        pin = devcode & P.DEVCODE_PIN
        if pin >= self.num_pins or not self.timer_mask >> pin & 1 or not self._is_input(pin):
            return P.MSG_CMD_INDEX_ERR
        if pin in self.busy:
            return P.MSG_TMR_CONFLICT
        self.busy.add(pin)
        ticks = self.timer_results.get(pin)
        if self.instant_timers and ticks is not None:
            self._timer_done(pin, ticks, bool(devcode & P.DEVCODE_HOST), self._epoch)
            return None
        delay = self.timer_timeout_s if ticks is None else self.timer_delay
        t = threading.Timer(delay, self._timer_done, (pin, ticks or 0, bool(devcode & P.DEVCODE_HOST), self._epoch))
        t.daemon = True
        self._timers.append(t)
        t.start()
        return None

    def _timer_done(self, pin: int, ticks: int, host: bool, epoch: int) -> None:
        with self._send_lock:
            if epoch != self._epoch:
                return  # stopped by a reset
            if host and not self.mute:
                try:
                    self.port.write(bytes([self.addr, 4, P.CMD_DEV_VAL, self.timer_id_base + pin, ticks >> 8, ticks & 0xFF]))
                except OSError:
                    pass
            self.busy.discard(pin)


class FakeServer:
    """A FakeModule behind a TCP socket on 127.0.0.1 (for `socket://` URLs): serves one
    connection at a time, a fresh fake module for each."""

    def __init__(self, setup: Optional[Callable[[FakeModule], None]] = None, **fake_options) -> None:
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
            except (socket.timeout, OSError):
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
        self.timeout: Optional[float] = None
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
