# SPDX-License-Identifier: Apache-2.0
"""The virtual module (sim/virtual.cpp, `make virtual`): brainstem_dio_uart behind a pty.

A host here is plain os.open/termios on the pty path. One virtual module (per worker, while
this file's tests run) serves the tests that only talk to it (each starts with `reset` on stdin, which replays
power-up, so it does not depend on what an earlier test left); the tests of start-up, exit and
errors start their own. The build runs at 2 MHz / 115200 baud with the 256 ms heartbeat, so it
keeps real time on a loaded machine; every wait has a generous wall-clock limit, and nothing
checks that the simulation is fast, only that it is never ahead of the wall clock.
"""

from __future__ import annotations

import os
import re
import resource
import select
import signal
import subprocess
import termios
import time
from pathlib import Path
from typing import Callable, Iterator

import pytest

from harness import TIMEOUT, Lines, make_built

# One worker runs this file and tb/host_virtual (the same virtual module binary): it builds
# once there, and the module fixtures start once.
pytestmark = pytest.mark.xdist_group("virtual")

ROOT = Path(__file__).resolve().parents[2]
MAKE_VARS = ["CLK_HZ=2000000", "BAUD=115200", "HB_RATE=10", "VIRTUAL_PGO=0"]  # and the other GP 1.0 defaults
A = 2  # module address
HB = (A, 2, 0)  # a heartbeat packet starts so


@pytest.fixture(scope="session")
def virtual_bin() -> Path:
    return make_built("virtual-build", "virtual-path", MAKE_VARS)


class Virtual:
    """A running virtual module: its stdin, its transcript (stdout), its stderr, its pty."""

    def __init__(self, binary: Path, link: Path, *args: str, **popen) -> None:
        self.link = link
        self.started = time.monotonic()
        self.proc = subprocess.Popen([str(binary), "--link", str(link), *args], cwd=ROOT, stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, **popen)
        self.out = Lines(self.proc.stdout)
        self.err = Lines(self.proc.stderr)
        line = self.out.lines[self.out.wait(r"^port: ")]
        self.port = line.split(": ", 1)[1]

    def send(self, *lines: str) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.write("".join(f"{line}\n" for line in lines).encode())
        self.proc.stdin.flush()

    def open(self) -> "Host":
        return Host(os.open(self.port, os.O_RDWR | os.O_NOCTTY))

    def wait_exit(self, timeout: float = TIMEOUT) -> int:
        rc = self.proc.wait(timeout)
        deadline = time.monotonic() + 5
        while not (self.out.closed and self.err.closed) and time.monotonic() < deadline:
            time.sleep(0.01)
        return rc

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


class Host:
    """The host end of the pty: whole packets in, whole packets out. At a packet boundary a
    byte that is not the module's address is noise (that is how a host resyncs)."""

    def __init__(self, fd: int) -> None:
        self.fd = fd
        self.buf = bytearray()
        self.noise = bytearray()
        self.heartbeats: list[bytes] = []

    def write(self, *data: int) -> None:
        os.write(self.fd, bytes(data))

    def _fill(self, deadline: float) -> None:
        left = deadline - time.monotonic()
        if left <= 0:
            raise AssertionError(f"no whole packet in time; have {self.buf.hex(' ')}")
        ready, _, _ = select.select([self.fd], [], [], left)
        if ready:
            self.buf += os.read(self.fd, 4096)

    def packet(self, timeout: float = TIMEOUT, heartbeats: bool = False) -> bytes:
        """The next packet (address, N, data); heartbeats are skipped unless asked for."""
        deadline = time.monotonic() + timeout
        while True:
            while self.buf and self.buf[0] != A:
                self.noise.append(self.buf.pop(0))
            if len(self.buf) >= 2 and len(self.buf) >= 2 + self.buf[1]:
                n = 2 + self.buf[1]
                p = bytes(self.buf[:n])
                del self.buf[:n]
                if tuple(p[:3]) == HB and len(p) == 4:
                    self.heartbeats.append(p)
                    if not heartbeats:
                        continue
                return p
            self._fill(deadline)

    def raw_until(self, tail: bytes, timeout: float = TIMEOUT) -> bytes:
        """Every byte up to and including the first `tail`, unframed."""
        deadline = time.monotonic() + timeout
        while (i := self.buf.find(tail)) < 0:
            self._fill(deadline)
        raw = bytes(self.buf[:i + len(tail)])
        del self.buf[:i + len(tail)]
        return raw

    def reply(self, *data: int, timeout: float = TIMEOUT) -> bytes:
        self.write(*data)
        return self.packet(timeout)

    def close(self) -> None:
        os.close(self.fd)


# Module scope, not session: a running virtual module keeps half a core busy simulating
# real time, which the rest of `make test` should not pay for.
@pytest.fixture(scope="module")
def shared(virtual_bin: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Virtual]:
    v = Virtual(virtual_bin, tmp_path_factory.mktemp("virtual") / "port")
    yield v
    v.send("quit")
    try:
        v.wait_exit()
    finally:
        v.stop()


@pytest.fixture
def fresh(virtual_bin: Path, tmp_path: Path) -> Iterator[Callable[..., Virtual]]:
    started: list[Virtual] = []

    def start(*args: str, **popen) -> Virtual:
        v = Virtual(virtual_bin, tmp_path / "port", *args, **popen)
        started.append(v)
        return v

    yield start
    for v in started:
        v.stop()


def powered_up(v: Virtual) -> tuple[Host, int]:
    """Open the port, replay power-up (`reset`), and read the power-up message: a host that
    opens the port after start-up has missed the first one, as with a real module."""
    mark = len(v.out)
    host = v.open()
    v.send("reset")
    # A power-up message of start-up, on a loaded machine still on its way when the port was
    # opened, may come first. The transcript says how many reached the host: every one from
    # the open up to this reset's, less those marked lost. Each is read whole, so none of them
    # can be taken later for a reply (the pty hands bytes on a moment after the write).
    power_up = r"< 2:power reset +\(02:80,04\)"
    this = v.out.wait(power_up, v.out.wait(r"\] reset\s*$", mark))
    assert "[lost" not in v.out.lines[this], v.out.lines[this]
    sent = [line for line in v.out.lines[mark:this + 1] if re.search(power_up, line) and "[lost" not in line]
    for _ in sent:
        assert host.packet() == bytes([A, 2, 0x80, 4]), "a packet other than power-up"
    return host, mark


# ---------------------------------------------------------------- start-up and the port

def test_start_up_power_up_is_lost_until_reset(shared: Virtual) -> None:
    assert os.path.realpath(shared.link) == os.path.realpath(shared.port)
    assert re.match(r"/dev/pts/\d+$", shared.port)
    # Sent before any host had the port: gone, and the transcript says so.
    shared.out.wait(r"< 2:power reset .*\[lost: no host\]")
    host, mark = powered_up(shared)
    try:
        shared.out.wait(r"host opened the port")
        shared.out.wait(r"< 2:power reset +\(02:80,04\)$", mark)
    finally:
        host.close()


def test_worked_examples_round_trip(shared: Virtual) -> None:
    host, mark = powered_up(shared)
    try:
        assert host.reply(A, 2, 0x1A, 3) == bytes([A, 3, 0x1A, 3, 1])  # query pin 3: input
        assert host.reply(0xAD, 0) == bytes([A, 0])  # resync probe
        assert host.reply(A, 2, 0x1B, 0x81) == bytes([A, 3, 0x04, 6, 1])  # pad 1 is pulled up
        host.write(A, 3, 0x1A, 1, 0)  # pin 1 becomes an output
        host.write(A, 3, 0x1B, 1, 1)  # drive pin 1 high
        assert host.reply(A, 2, 0x1B, 0x81) == bytes([A, 2, 0x80, 0x0A])  # an output: cmdIndexErr
        assert host.reply(A, 3, 0x1A, 7, 1) == bytes([A, 2, 0x80, 0x0A])  # no pin 7
        assert host.reply(A, 1, 0x63) == bytes([A, 2, 0x80, 8])  # unknown command
        # Binary-transparent both ways (what a tty left cooked would eat or change: ^C, LF,
        # CR, XON, XOFF, DEL, NUL): another module's packet, and pin 3's DIGCFG there and back.
        host.write(4, 6, 0x03, 0x0A, 0x0D, 0x11, 0x13, 0x7F)
        for cfg in (0x11, 0x13, 0x0D, 0x0A, 0x00, 0x01):
            host.write(A, 3, 0x1A, 3, cfg)
            assert host.reply(A, 2, 0x1A, 3) == bytes([A, 3, 0x1A, 3, cfg])
        out = shared.out
        out.wait(r"> 02:1A,03 +query pin 3 config$", mark)
        out.wait(r"< 02:1A,03,01 +pin 3 config 0x01: input$", mark)
        out.wait(r"> AD: +resync probe$", mark)
        out.wait(r"< 02: +resync reply$", mark)
        out.wait(r"> 02:1A,01,00 +set pin 1 config 0x00: output$", mark)
        out.wait(r"pin 1 driven low", mark)
        out.wait(r"> 02:1B,01,01 +drive pin 1 high$", mark)
        out.wait(r"pin 1 driven high", mark)
        out.wait(r"< 2:cmd index error +\(02:80,0A\)$", mark)
        out.wait(r"> 04:03,0A,0D,11,13,7F +not for module 2: ignored$", mark)
        out.wait(r"> 02:63 +unknown command 0x63$", mark)
        out.wait(r"< 02:1A,03,0A +pin 3 config 0x0A: output, latch on 1->0, edge timer to high$", mark)
    finally:
        host.close()


def test_host_framing_in_the_transcript(shared: Virtual) -> None:
    host, mark = powered_up(shared)
    try:
        host.write(A, 3, 0x1A)  # left incomplete: the core drops it after RX_TIMEOUT_US
        shared.out.wait(r"> 02:1A +incomplete: dropped after 25.6 ms$", mark)
        assert host.reply(A, 2, 0x1A, 3) == bytes([A, 3, 0x1A, 3, 1])
        assert host.reply(A, 9) == bytes([A, 2, 0x80, 0x1C])  # N > 8: serialError
        shared.out.wait(r"> 02 N=9 +N > 8: framing error, both bytes dropped$", mark)
        shared.out.wait(r"< 2:serial error +\(02:80,1C\)$", mark)
    finally:
        host.close()


def test_heartbeat_answered_raises_link_up(shared: Virtual) -> None:
    host, mark = powered_up(shared)
    try:
        up = host.packet(heartbeats=True)
        assert up == bytes([A, 2, 0, 0])  # UP, one period after reset
        host.write(A, 2, 0, 2)
        shared.out.wait(r"> 02:00,02 +heartbeat UP answered$", mark)
        up_at = shared.out.wait(r"\* link_up 1 +the host answers the heartbeat$", mark)
        # Unanswered from here: DOWN comes, then the next one falls due and the link is down.
        assert host.packet(heartbeats=True) == bytes([A, 2, 0, 1])
        shared.out.wait(r"\* link_up 0 +a heartbeat went unanswered$", up_at)
    finally:
        host.close()


def test_noise_reaches_the_host_between_packets(shared: Virtual) -> None:
    host, mark = powered_up(shared)
    try:
        shared.send("noise 03 02")
        shared.out.wait(r"< noise 03,02 +between packets$", mark)
        host.write(A, 2, 0x1A, 3)
        # 03 02 looks like the start of a packet to the module itself: a host must resync.
        raw = host.raw_until(bytes([A, 3, 0x1A, 3, 1]))
        for hb in (bytes([A, 2, 0, 0]), bytes([A, 2, 0, 1])):  # heartbeats may come in between
            raw = raw.replace(hb, b"")
        assert raw == bytes([3, 2, A, 3, 0x1A, 3, 1]), raw.hex(" ")
    finally:
        host.close()


def test_closed_port_loses_bytes_and_reopens(shared: Virtual) -> None:
    host, mark = powered_up(shared)
    host.close()
    shared.out.wait(r"host closed the port", mark)
    # Power-up again while no host has the port: lost, not kept for the next host.
    mark = len(shared.out)
    shared.send("reset")
    shared.out.wait(r"< 2:power reset .*\[lost: no host\]$", mark)
    host = shared.open()
    try:
        shared.out.wait(r"host opened the port", mark)
        # The host's own baud setting changes nothing: the line runs at the build's BAUD.
        attrs = termios.tcgetattr(host.fd)
        attrs[4] = attrs[5] = termios.B300
        termios.tcsetattr(host.fd, termios.TCSANOW, attrs)
        assert host.reply(A, 2, 0x1A, 3) == bytes([A, 3, 0x1A, 3, 1])  # not the power-up message
        assert not host.noise
    finally:
        host.close()
    for _ in range(3):  # open and close as often as it likes
        host = shared.open()
        try:
            assert host.reply(A, 2, 0x1A, 2) == bytes([A, 3, 0x1A, 2, 1])
        finally:
            host.close()


def test_pin_lines_drive_the_pads(shared: Virtual) -> None:
    host, mark = powered_up(shared)
    try:
        shared.send("pin 0 low")
        shared.out.wait(r"\] pin 0 low", mark)
        assert host.reply(A, 2, 0x1B, 0x80) == bytes([A, 3, 4, 5, 0])
        shared.send("pin 0 high")
        shared.out.wait(r"\] pin 0 high", mark)
        assert host.reply(A, 2, 0x1B, 0x80) == bytes([A, 3, 4, 5, 1])
        # The transition latch on pin 2 (0->1) and an RFLX read, in the transcript.
        shared.send("pin 2 low")
        shared.out.wait(r"\] pin 2 low", mark)
        host.write(A, 3, 0x1A, 2, 0x07)
        shared.out.wait(r"> 02:1A,02,07 ", mark)
        shared.send("pin 2 high")
        shared.out.wait(r"\* raw input 17 +pin 2 transition latch fired$", mark)
        host.write(A, 2, 0x1B, 0x42)
        shared.out.wait(r"\* RFLX id 7 = 1", mark)
        # A pulse on stdin, timed by the core: width timer of a high pulse on pin 4.
        shared.send("pin 4 low")
        host.write(A, 3, 0x1A, 4, 0x19)
        host.write(A, 2, 0x1D, 0x84)
        shared.out.wait(r"> 02:1D,84 +time pin 4 \(HOST\)$", mark)
        shared.send("pin 4 pulse 800us")
        p = host.packet()
        assert p[:4] == bytes([A, 4, 4, 14]), p.hex(" ")
        assert abs(((p[4] << 8) | p[5]) - 500) <= 1, p.hex(" ")  # 800 us = 500 ticks
        shared.out.wait(r"< 02:04,0E,01,F[345] +pin 4 timer: 50[01] ticks", mark)
    finally:
        shared.send("pin 0 high", "pin 2 high", "pin 4 high")
        host.close()


@pytest.fixture(scope="session")
def virtual_wave_bin() -> Path:
    """The build with tracing (`make virtual WAVES=1`): the others leave it out for speed."""
    return make_built("virtual-build", "virtual-path", [*MAKE_VARS, "WAVES=1"])


def test_waves_record_the_session(virtual_wave_bin: Path, tmp_path: Path) -> None:
    wave = tmp_path / "session.vcd"
    v = Virtual(virtual_wave_bin, tmp_path / "port", "--wave", str(wave))
    try:
        host, _ = powered_up(v)
        try:
            assert host.reply(A, 2, 0x1A, 3) == bytes([A, 3, 0x1A, 3, 1])
        finally:
            host.close()
        v.send("quit")
        assert v.wait_exit() == 0
    finally:
        v.stop()
    assert f"waveform {wave}" in v.out.lines[-1]
    data = wave.read_bytes()
    if data.startswith(b"$"):  # a VCD (an FST when lz4's header is installed)
        assert b"$enddefinitions" in data and b" tx " in data and b"\n#" in data
    else:
        assert len(data) > 1000


def test_wave_needs_the_traced_build(virtual_bin: Path, tmp_path: Path) -> None:
    # The default build has no tracing (it costs every clock): a waveform asked of it is
    # refused, not silently left out.
    run = subprocess.run([str(virtual_bin), "--wave", str(tmp_path / "w.vcd")], cwd=ROOT, capture_output=True,
                         text=True, stdin=subprocess.DEVNULL, timeout=TIMEOUT)
    assert run.returncode == 2
    assert "error: --wave needs the build with tracing: make virtual WAVES=1" in run.stderr, run.stderr
    assert not (tmp_path / "w.vcd").exists()


def test_wait_follows_the_wall_clock(fresh) -> None:
    v = fresh()
    v.send("wait 200ms", "pin 3 low")
    i = v.out.wait(r"\] pin 3 low")
    seen = time.monotonic() - v.started
    # 200 ms of simulated time, and the line not ahead of the wall clock. (Not "0.2 s of wall
    # time since the send": a module that had fallen behind on a loaded machine catches up
    # faster than real time, so that measure was once 0.197 s.)
    stamp = float(re.match(r"\[ *([\d.]+) ms\]", v.out.lines[i]).group(1)) / 1e3
    assert 0.2 <= stamp <= seen, (stamp, seen)
    v.proc.stdin.close()
    assert v.wait_exit() == 0
    elapsed = time.monotonic() - v.started
    done = v.out.lines[v.out.wait(r"^done \(end of input\): ")]
    simulated = float(re.search(r": ([\d.]+) s simulated", done).group(1))
    assert 0.2 <= simulated <= elapsed, done  # never ahead of the wall clock


def test_falling_behind_is_reported_at_most_once_a_second(fresh) -> None:
    v = fresh()
    v.send("pin 3 high")  # its line shows that the paced run has begun
    v.out.wait(r"\] pin 3 high")
    v.proc.send_signal(signal.SIGSTOP)  # a stall, as under heavy load
    time.sleep(1.5)
    v.proc.send_signal(signal.SIGCONT)
    t0 = time.monotonic()
    v.err.wait(r"^behind real time: x0\.\d\d, stalled 1\.\d{3} s$")  # the 1.5 s stop
    time.sleep(1.0)
    v.send("quit")
    assert v.wait_exit() == 0
    reports = [line for line in v.err.lines if line.startswith("behind real time")]
    assert 1 <= len(reports) <= time.monotonic() - t0 + 2, reports


# ---------------------------------------------------------------- line noise (ber, stats)

NOISE_SEED = 20261202  # fixed: a failure repeats (each test's messages name it)
FLIP = re.compile(r"\* noise (rx|tx) ([0-9A-F]{2}) +flipped((?: (?:start|d[0-7]|stop))+) \[bits ([\d ]+)\]$")
STATS = re.compile(r"^stats: ber (\S+): rx (\d+) of (\d+) bits flipped, tx (\d+) of (\d+) bits flipped$")
CORE = re.compile(r"\] < (?:\d+:[a-z ]+ +\()?([0-9A-F]{2}):([0-9A-F,]*)\)?")


def stats(v: Virtual) -> tuple[int, int, int, int]:
    """`stats` on stdin -> (rx flips, rx bits, tx flips, tx bits)."""
    mark = len(v.out)
    v.send("stats")
    m = STATS.match(v.out.lines[v.out.wait(STATS.pattern, mark)])
    return int(m[2]), int(m[3]), int(m[4]), int(m[5])


def flips(v: Virtual, start: int, end: int | None = None) -> list[tuple[str, str, str, list[int]]]:
    """The transcript's flip lines: (line, byte, which bits, their positions on the line)."""
    found = []
    for line in v.out.lines[start:end]:
        m = FLIP.search(line)
        if m:
            found.append((m[1], m[2], m[3].strip(), [int(b) for b in m[4].split()]))
    return found


def core_stream(v: Virtual, start: int, end: int) -> bytes:
    """The bytes the core really sent, from the transcript's `<` lines (packets without N)."""
    out = bytearray()
    for line in v.out.lines[start:end]:
        m = CORE.search(line)
        if m and "noise" not in line:
            data = bytes.fromhex(m[2].replace(",", "")) if m[2] else b""
            out += bytes([int(m[1], 16), len(data)]) + data
    return bytes(out)


def host_bytes_until(host: Host, tail: bytes, timeout: float = TIMEOUT) -> bytes:
    """Every byte the host's UART passed on, up to and including `tail`."""
    return host.raw_until(tail, timeout)


def test_noise_flips_bits_on_both_lines_and_counts_them(fresh) -> None:
    v = fresh("--seed", str(NOISE_SEED))
    seed = v.out.lines[v.out.wait(r"^line noise: ber 0, seed ")]
    assert f"seed {NOISE_SEED} " in seed, seed
    host, _ = powered_up(v)
    try:
        start = len(v.out)
        # The power-up line is the first of the core's bytes the host reads from here.
        v.send("ber 0.01")
        v.out.wait(r"\] ber 0\.01 +line noise on both lines$", start)
        before = stats(v)
        sent = []
        for i in range(150):  # 150 echoes, each its own bytes: 6000 bits each way
            sent.append(bytes([A, 3, 0x17, i, 0x5A]))
            host.write(*sent[-1])
            time.sleep(0.001)
        time.sleep(0.3)
        v.send("ber 0")
        off = v.out.wait(r"\] ber 0 +line noise off$", start)
        time.sleep(0.1)  # the line idle: the host's UART in step again
        noisy = stats(v)
        host.write(A, 3, 0x17, 0xAA, 0x55)  # clean on both lines
        last = v.out.wait(r"\] < 02:17,AA,55 ", off)
        got = host_bytes_until(host, bytes([A, 3, 0x17, 0xAA, 0x55]))
        rx_flips, rx_bits, tx_flips, tx_bits = (a - b for a, b in zip(noisy, before))
        where = f"seed {NOISE_SEED}; stats {before} -> {noisy}"
        # Counted: the transcript's flip lines list exactly the bits `stats` counts.
        lines = flips(v, start, off + 1)
        assert sum(len(f[3]) for f in lines if f[0] == "rx") == rx_flips, where
        assert sum(len(f[3]) for f in lines if f[0] == "tx") == tx_flips, where
        # At about the rate asked for (about 60 flips each way expected).
        assert rx_bits >= 150 * 5 * 10 and tx_bits >= 100 * 5 * 10, where
        assert 0.004 <= rx_flips / rx_bits <= 0.025 and 0.004 <= tx_flips / tx_bits <= 0.025, where
        # The rx flips reach the core: it answered packets the host never sent.
        truth = core_stream(v, start, last + 1)
        clean = {bytes([A, 2, 0, t]) for t in (0, 1)} | set(sent)
        core_pkts, i = set(), 0
        while i < len(truth):
            core_pkts.add(truth[i:i + 2 + truth[i + 1]])
            i += 2 + truth[i + 1]
        assert core_pkts - clean - {bytes([A, 3, 0x17, 0xAA, 0x55])}, where
        # The tx flips reach the host: what its UART passed on is not what the core sent.
        assert truth.endswith(bytes([A, 3, 0x17, 0xAA, 0x55])), where
        assert got != truth, where
    finally:
        host.close()


def test_ber_0_stops_the_flips(fresh) -> None:
    v = fresh("--seed", str(NOISE_SEED))
    host, _ = powered_up(v)
    try:
        v.send("ber 0.02")
        v.out.wait(r"\] ber 0\.02 ")
        for i in range(40):
            host.write(A, 3, 0x17, i, 0x0F)
        time.sleep(0.2)
        v.send("ber 0")
        off = v.out.wait(r"\] ber 0 +line noise off$")
        time.sleep(0.1)  # the core drops a partial packet after 25.6 ms; the host drops all
        while select.select([host.fd], [], [], 0.05)[0]:
            os.read(host.fd, 4096)
        host.buf.clear()
        before = stats(v)
        assert before[0] > 0 and before[2] > 0, f"seed {NOISE_SEED}: no flips at ber 0.02: {before}"
        mark = len(v.out)
        for i in range(150):
            assert host.reply(A, 3, 0x17, i, 0xF0) == bytes([A, 3, 0x17, i, 0xF0])
        after = stats(v)
        assert after[1] == before[1] + 150 * 50 and after[3] >= before[3] + 150 * 50, (before, after)
        assert (after[0], after[2]) == (before[0], before[2]), f"flips after ber 0: {before} -> {after}"
        assert not flips(v, mark), flips(v, mark)
        assert off < mark
    finally:
        host.close()


def test_the_seed_repeats_the_flips(fresh) -> None:
    def run(seed: int) -> tuple[list, list]:
        v = fresh("--seed", str(seed))
        host, _ = powered_up(v)
        try:
            v.send("ber 0.02")  # before the host's first byte: rx counts from its bit 0
            v.out.wait(r"\] ber 0\.02 ")
            for i in range(60):
                host.write(A, 3, 0x17, i, 0x3C)
            host.write(A, 3, 0x17, 0xAA, 0x55)
            v.out.wait(r"\] > 02:17,AA,55 ")
            time.sleep(0.1)
            lines = flips(v, 0)
        finally:
            host.close()
        v.send("quit")
        assert v.wait_exit() == 0
        # rx: the same bytes on the line, so the same bytes hit in the same bits. tx: the
        # power-up messages and heartbeats before `ber` fall as the wall clock has it, so
        # the positions are comparable from the first flip on: their gaps.
        rx = [f for f in lines if f[0] == "rx"]
        tx = [p for f in lines if f[0] == "tx" for p in f[3]]
        return rx, [b - a for a, b in zip(tx, tx[1:])]
    rx1, tx1 = run(NOISE_SEED)
    rx2, tx2 = run(NOISE_SEED)
    rx3, tx3 = run(NOISE_SEED + 1)
    assert len(rx1) >= 10 and len(tx1) >= 5, (rx1, tx1)
    assert rx1 == rx2, f"seed {NOISE_SEED}: {rx1} != {rx2}"
    n = min(len(tx1), len(tx2))
    assert n >= 5 and tx1[:n] == tx2[:n], f"seed {NOISE_SEED}: {tx1} != {tx2}"
    assert rx3 != rx1 and tx3[:n] != tx1[:n], f"seeds {NOISE_SEED} and {NOISE_SEED + 1} flip alike"


BAD_BER = [
    ("ber x", "bad bit error rate 'x' (a bit error rate from 0 to 1, e.g. 1e-3); the rate stays as it was"),
    ("ber -1", "bad bit error rate '-1'"),
    ("ber 2", "bad bit error rate '2'"),
    ("ber nan", "bad bit error rate 'nan'"),
    ("ber 1e-3x", "bad bit error rate '1e-3x'"),
    ("ber", "expected 'ber P' (a bit error rate from 0 to 1, e.g. 1e-3)"),
    ("ber 1e-3 1e-2", "expected 'ber P'"),
]


def test_bad_ber_is_refused_and_the_run_goes_on(fresh) -> None:
    v = fresh("--seed", str(NOISE_SEED))
    v.send(*(line for line, _ in BAD_BER))
    for i, (line, message) in enumerate(BAD_BER, 1):
        v.err.wait(re.escape(f"error: stdin:{i}: {message}"))
    host, _ = powered_up(v)  # still running, still answering, and without noise
    try:
        for i in range(20):
            assert host.reply(A, 3, 0x17, i, 0xC3) == bytes([A, 3, 0x17, i, 0xC3])
        before = stats(v)
        assert before[0::2] == (0, 0), before  # the rate stayed 0
        v.send("ber 1")  # a good line after them is taken: every bit flipped
        v.out.wait(r"\] ber 1 +line noise on both lines$")
        host.write(A, 3, 0x17, 1, 2)
        time.sleep(0.2)
        after = stats(v)
        assert after[0] - before[0] == after[1] - before[1] == 50, (before, after)
    finally:
        host.close()
    v.send("quit")
    assert v.wait_exit() == 0
    assert len(v.err.lines) == len(BAD_BER), v.err.text()


def test_make_virtual_passes_ber_and_seed() -> None:
    run = subprocess.run(["make", "-n", "virtual", "BER=1e-3", "SEED=42"], cwd=ROOT, capture_output=True,
                         text=True, timeout=TIMEOUT)
    assert run.returncode == 0, run.stderr
    assert re.search(r"/virtual --link \S+ --ber 1e-3 --seed 42$", run.stdout, re.M), run.stdout


# ---------------------------------------------------------------- exit and errors

@pytest.mark.parametrize("how", ["eof", "quit", "SIGTERM", "SIGINT"])
def test_clean_exit_removes_the_link(fresh, how: str) -> None:
    v = fresh()
    assert os.path.islink(v.link) and os.readlink(v.link) == v.port
    host = v.open()  # a host still holding the port does not stop the exit
    try:
        if how == "eof":
            v.proc.stdin.close()
        elif how == "quit":
            v.send("quit")
        else:
            v.proc.send_signal(getattr(signal, how))
        assert v.wait_exit() == 0, v.err.text()
    finally:
        host.close()
    reason = {"eof": "end of input", "quit": "quit"}.get(how, how)
    assert re.match(rf"done \({reason}\): [\d.]+ s simulated", v.out.lines[-1]), v.out.text()
    assert not os.path.lexists(v.link)
    assert not [line for line in v.err.lines if not line.startswith("behind real time")], v.err.text()


BAD_LINES = [
    ("fly 3", "stdin:2: unknown keyword 'fly' (standard input takes pin, wait, reset, noise, ber, stats and quit)"),
    ("pin 9 high", "stdin:2: bad pin number '9' (0..4)"),
    ("pin 1 pulse 3parsecs", "stdin:2: bad time '3parsecs'"),
    ("wait", "stdin:2: expected 'wait TIME'"),
    ("noise 3 300", "stdin:2: bad byte '300' (0..255)"),
    ("quit now", "stdin:2: 'quit' takes no argument"),
    ("2 26 3", "stdin:2: packets come from the host through the port"),
    ("expect 2 0", "stdin:2: 'expect' belongs in make sim scripts"),
    ("stats now", "stdin:2: 'stats' takes no argument"),
]


@pytest.mark.parametrize("line,message", BAD_LINES)
def test_bad_stdin_line_stops_with_a_message(fresh, line: str, message: str) -> None:
    v = fresh()
    v.send("# a comment", line, "wait 1s")
    assert v.wait_exit() == 1
    assert f"error: {message}" in v.err.text(), v.err.text()
    assert not os.path.lexists(v.link)


@pytest.mark.parametrize("args,message", [
    (["--bogus"], "error: unknown option '--bogus'"),
    (["extra"], "error: unexpected argument 'extra'"),
    (["--wave"], "error: option '--wave' needs a value"),
    (["--bench", "soon"], "error: --bench needs a number of seconds, not 'soon'"),
    (["--ber", "2"], "error: --ber needs a bit error rate from 0 to 1, e.g. 1e-3, not '2'"),
    (["--ber", "x"], "error: --ber needs a bit error rate from 0 to 1, e.g. 1e-3, not 'x'"),
    (["--ber", "-1"], "error: --ber needs a bit error rate from 0 to 1, e.g. 1e-3, not '-1'"),
    (["--seed", "-3"], "error: --seed needs a decimal number from 0 to 2^64-1, not '-3'"),
    (["--seed", "99999999999999999999"], "error: --seed needs a decimal number from 0 to 2^64-1"),
])
def test_bad_argument_gives_usage(virtual_bin: Path, args: list[str], message: str) -> None:
    run = subprocess.run([str(virtual_bin), *args], cwd=ROOT, capture_output=True, text=True,
                         stdin=subprocess.DEVNULL, timeout=TIMEOUT)
    assert run.returncode == 2
    assert message in run.stderr and "usage: virtual" in run.stderr, run.stderr


def test_bad_make_variable_is_refused() -> None:
    run = subprocess.run(["make", "-n", "virtual-build", "BAUD=fast"], cwd=ROOT, capture_output=True, text=True,
                         timeout=TIMEOUT)
    assert run.returncode != 0
    assert "BAUD=fast: a decimal number, please" in run.stderr, run.stderr


def test_pty_that_cannot_be_opened(virtual_bin: Path, tmp_path: Path) -> None:
    # Four file descriptors: enough to start, one short of opening the pty's slave.
    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_NOFILE, (4, 4))
    run = subprocess.run([str(virtual_bin), "--link", str(tmp_path / "port")], cwd=ROOT, capture_output=True,
                         text=True, stdin=subprocess.DEVNULL, timeout=TIMEOUT, preexec_fn=limit)
    assert run.returncode == 1
    assert re.search(r"error: cannot open (a|the) pseudo-terminal", run.stderr), run.stderr
    assert not os.path.lexists(tmp_path / "port")


def test_link_in_use_is_refused(fresh, virtual_bin: Path) -> None:
    v = fresh()
    run = subprocess.run([str(virtual_bin), "--link", str(v.link)], cwd=ROOT, capture_output=True, text=True,
                         stdin=subprocess.DEVNULL, timeout=TIMEOUT)
    assert run.returncode == 1
    assert "another virtual module is running with the link" in run.stderr, run.stderr
    assert os.readlink(v.link) == v.port  # the running one keeps its link
