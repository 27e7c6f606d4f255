#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""A noise soak (README, "The noise soak"): the host library against the virtual module (2 MHz,
115200 baud, HB_RATE 10) on a line that flips bits; a quiet baseline, random calls against a
shadow model at each BER, then the noise off and a functional check. Exit 1, naming the
criterion, when a call outlasted its bound (its timeout + the sync after a Timeout + 0.5 s),
raised outside `BrainStemError`, the reader thread died, the link did not answer within 2 s
after the noise or a check failed; wrong values under noise are counted, not failures. The
report goes to sim/build/soak/report.md, the module's transcript beside it.

    .venv/bin/python sim/soak.py --calls 300 --bers 1e-3 --baseline 50 --seed 7
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import datetime
import os
import random
import re
import shlex
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tb" / "lib"))
import brainstem_dio
from brainstem_dio import BrainStemError, CmdIndexErr, DigCfg, ModuleError
from harness import Lines, make_built

BAUD = 115200
A = 2
NUM_PINS = 5
TICK_S = 1.6e-6
TIMER_TIMEOUT_S = 65535 * TICK_S
# Low pulses on pins 3 and 4 (the pads rest high) every 360 us, timed in width mode: a result
# usually comes before the module confirms the start (about 0.4 ms at 115 200 baud), the case
# where it must not go to an older, lost measurement's wait.
PULSE_US = {3: 100, 4: 160}  # 62.5 and 100 ticks
TRAIN_PERIOD_S = 360e-6
TRAIN = ["pin 3 pulse 100us", "wait 50us", "pin 4 pulse 160us", "wait 50us"]
TICK_SLACK = 2  # ±1 tick of phase, plus the synchronizer's few clocks
CALL_TIMEOUT = 0.5  # the library's default
GRACE_S = 0.5
STATS = re.compile(r"^stats: ber (\S+): rx (\d+) of (\d+) bits flipped, tx (\d+) of (\d+) bits flipped$")
TRANSCRIPT = ROOT / "sim" / "build" / "soak" / "transcript.txt"
OK, WRONG = "ok", "wrong value"
# The random calls' weights (Soak.op_<name>).
OPS = {"configure": 14, "query": 14, "write": 12, "read": 14, "time_pin": 12, "echo": 14, "no_timer": 4, "pipelined": 8}
LINK_COUNTS = ("framing_errors", "resyncs", "resync_timeouts", "unsolicited")  # the library's, per phase


class Virtual:
    """The virtual module (its stdin, transcript, pty and noise counts) and the pulse trains
    queued on its stdin; stdin lines run in order, so `until` is when the last train ends."""

    def __init__(self, binary: Path, link: Path, seed: int) -> None:
        self.proc = subprocess.Popen([str(binary), "--link", str(link), "--seed", str(seed)], cwd=ROOT,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        self.out, self.err = Lines(self.proc.stdout), Lines(self.proc.stderr)
        self.port = self.out.lines[self.out.wait(r"^port: ")].split(": ", 1)[1]
        self.seed_line = self.out.lines[self.out.wait(r"^line noise: ")]
        self.lock, self.until = threading.Lock(), 0.0

    def send(self, *lines: str) -> None:
        with self.lock:
            self.proc.stdin.write("".join(f"{line}\n" for line in lines).encode())
            self.proc.stdin.flush()

    def ask(self, line: str, pattern: str) -> str:
        mark = len(self.out)
        self.send(line)
        return self.out.lines[self.out.wait(pattern, mark, timeout=60)]

    def stats(self) -> tuple[int, ...]:
        """(rx flips, rx bits, tx flips, tx bits) so far."""
        return tuple(int(x) for x in STATS.match(self.ask("stats", STATS.pattern)).groups()[1:])

    def cover(self, seconds: float) -> None:
        """Pulse trains for at least `seconds` from now."""
        now = time.monotonic()
        if self.until < now + seconds:
            reps = int(2 * seconds / TRAIN_PERIOD_S)
            self.send(*(TRAIN * reps))
            self.until = max(self.until, now) + reps * TRAIN_PERIOD_S

    def trains_running(self) -> bool:
        return time.monotonic() < self.until + 0.2  # the module may lag the wall clock a little

    def trains_wait_out(self) -> None:
        time.sleep(max(0.0, self.until + 0.1 - time.monotonic()))

    def stop(self) -> None:
        try:
            if self.proc.poll() is None:
                self.send("quit")
                self.proc.wait(30)
        except (OSError, subprocess.TimeoutExpired):
            self.proc.kill()
            self.proc.wait()


@dataclass
class Phase:
    """One phase's calls: each one's outcome counted, its time against its bound, and what
    fails the soak (a call past its bound, an exception outside BrainStemError) in `failures`."""

    name: str
    outcomes: collections.Counter = field(default_factory=collections.Counter)
    slowest: tuple[float, float, str] = (0.0, 0.0, "")  # (ratio to timeout, seconds, call)
    failures: list[str] = field(default_factory=list)
    wrong: list[str] = field(default_factory=list)
    flips: tuple[int, ...] = (0, 0, 0, 0)
    link: dict[str, int] = field(default_factory=dict)
    seconds: float = 0.0

    @property
    def calls(self) -> int:
        return sum(self.outcomes.values())

    def call(self, op: str, fn: Callable[[], Any], check: Callable[[Any], str | None], *,
             timeout: float = CALL_TIMEOUT, expect: type | None = None, either: type | None = None) -> tuple[str, Any]:
        """`check(result)`: None when the result is what the shadow predicts, else the
        difference; `expect`: the module error predicted instead; `either`: a module error as
        good as a result (the shadow does not know)."""
        t0 = time.monotonic()
        try:
            result = fn()
        except BrainStemError as e:
            result = e
            outcome = OK if isinstance(e, expect or either or ()) else (
                f"{type(e).__name__} ({e.code})" if isinstance(e, ModuleError) else type(e).__name__)
        except Exception as e:  # noqa: BLE001 - that is what this counts
            result, outcome = e, f"foreign {type(e).__name__}"
            self.failures.append(f"an exception outside BrainStemError: {op}: {type(e).__name__}: {e}")
        else:
            diff = f"no {expect.__name__}" if expect is not None else check(result)
            outcome = OK if diff is None else WRONG
            self.wrong += [f"{op}: {diff}"] * (diff is not None)
        took, bound = time.monotonic() - t0, timeout + CALL_TIMEOUT + GRACE_S
        if took > bound:
            self.failures.append(f"a call past its bound: {op}: {took:.3f} s (bound {bound:.3f} s)")
        self.slowest = max(self.slowest, (took / timeout, took, op))
        self.outcomes[outcome] += 1
        return outcome, result


Call = Callable[..., tuple[str, Any]]


class Soak:
    """The shadow (each pin's DIGCFG, None when unknown) and the random calls."""

    def __init__(self, m: brainstem_dio.Module, v: Virtual, rng: random.Random) -> None:
        self.m, self.v, self.rng = m, v, rng
        self.cfg: list[int | None] = [0x01] * NUM_PINS
        self.framing: list[str] = []  # the library's framing errors: when, why, what it dropped
        m.link.add_listener(lambda e: self.framing.append(f"{e.time:.3f}: {e.note} ({bytes(e.raw or b'').hex(' ')})")
                            if e.kind == "framing" else None)

    def output(self, pin: int) -> bool | None:
        return None if self.cfg[pin] is None else not self.cfg[pin] & 0x01

    def index_err(self, pin: int, when: bool | None) -> dict[str, type | None]:
        """CmdIndexErr expected when the pin's direction is `when`, as good as a result when unknown."""
        out = self.output(pin)
        return {"expect": CmdIndexErr if out is when else None, "either": CmdIndexErr if out is None else None}

    def _configure(self, call: Call, pin: int, cfg: int) -> bool:
        outcome, _ = call(f"configure pin {pin} 0x{cfg:02X}", lambda: self.m.configure(pin, cfg), lambda r: None)
        self.cfg[pin] = cfg if outcome == OK else None
        return outcome == OK

    def op_configure(self, call: Call) -> None:
        self._configure(call, self.rng.randrange(NUM_PINS), self.rng.randrange(32) | (self.rng.random() < 0.6))

    def op_query(self, call: Call) -> None:
        pin = self.rng.randrange(NUM_PINS)
        want = self.cfg[pin]
        outcome, r = call(f"query pin {pin}", lambda: self.m.query(pin), lambda r: None if want is None or int(r) == want
                          else f"pin {pin} config 0x{int(r):02X}, not 0x{want:02X}")
        if isinstance(r, DigCfg):
            self.cfg[pin] = int(r) & 0x1F  # what the module says, right or not, from now on
        elif outcome != OK:
            self.cfg[pin] = None

    def op_write(self, call: Call) -> None:
        pin, value = self.rng.randrange(NUM_PINS), self.rng.randrange(2)
        call(f"write pin {pin} {value}", lambda: self.m.write(pin, value), lambda r: None, **self.index_err(pin, False))

    def op_read(self, call: Call) -> None:
        pin = self.rng.randrange(NUM_PINS)
        out, want = self.output(pin), None if pin in PULSE_US and self.v.trains_running() else 1  # pull-ups, or a train

        def check(r: int) -> str | None:
            if r not in (0, 1):
                return f"pin {pin} read {r}"
            return None if out is None or want is None or r == want else f"pin {pin} read {r}, not {want}"
        call(f"read pin {pin}", lambda: self.m.read(pin), check, **self.index_err(pin, True))

    def op_time_pin(self, call: Call) -> None:
        pin = self.rng.choice(sorted(PULSE_US))
        if self._configure(call, pin, 0x11):  # input, width timer of a low pulse
            self.v.cover(1.0)
            want = PULSE_US[pin] * 1e-6 / TICK_S
            call(f"time_pin pin {pin}", lambda: self.m.time_pin(pin), lambda r: None if abs(r.ticks - want) <= TICK_SLACK
                 else f"pin {pin} timer {r.ticks} ticks, not {want:g}", timeout=CALL_TIMEOUT + TIMER_TIMEOUT_S)

    def op_echo(self, call: Call) -> None:
        data = bytes(self.rng.randrange(256) for _ in range(self.rng.randrange(8)))
        call(f"echo {data.hex()}", lambda: self.m.echo(data), lambda r: None if r == data else f"echo {r.hex()}, not {data.hex()}")

    def op_no_timer(self, call: Call) -> None:
        call("time_pin pin 0", lambda: self.m.time_pin(0), lambda r: None, expect=CmdIndexErr,
             timeout=CALL_TIMEOUT + TIMER_TIMEOUT_S)

    def op_pipelined(self, call: Call) -> None:
        pin = self.rng.randrange(3)
        if not self.output(pin) and not self._configure(call, pin, 0x00):
            return
        values = [self.rng.randrange(2) for _ in range(self.rng.randrange(3, 9))]
        pendings = [call(f"write(wait=False) pin {pin} {v}", lambda v=v: self.m.write(pin, v, wait=False), lambda r: None)
                    for v in values]
        for value, (outcome, p) in zip(values, pendings):
            if outcome == OK:
                call(f"Pending.result pin {pin} {value}", p.result, lambda r: None)

    def phase(self, name: str, ber: float, calls: int) -> Phase:
        """`calls` random calls at `ber`, with the line's and the library's counts of the phase."""
        self.v.trains_wait_out()
        self.v.ask(f"ber {ber:g}", rf"\] ber {re.escape(f'{ber:g}')} +line noise")
        flips0, link0, phase, t0 = self.v.stats(), link_counts(self.m), Phase(name), time.monotonic()
        while phase.calls < calls:
            getattr(self, "op_" + self.rng.choices(list(OPS), list(OPS.values()))[0])(phase.call)
        phase.seconds = time.monotonic() - t0
        self.v.trains_wait_out()
        phase.flips = tuple(a - b for a, b in zip(self.v.stats(), flips0))
        phase.link = {k: val - link0[k] for k, val in link_counts(self.m).items()}
        if not reader_alive():
            phase.failures.append("the library's reader thread is dead")
        return phase


def link_counts(m: brainstem_dio.Module) -> dict[str, int]:
    return {k: getattr(m.link.stats, k) for k in LINK_COUNTS}


def reader_alive() -> bool:
    return any(t.name == "brainstem_dio-reader" and t.is_alive() for t in threading.enumerate())


def answering_after(m: brainstem_dio.Module, since: float, limit: float = 2.0) -> float | None:
    """Seconds from `since` to the first echo that comes back, or None if none in `limit`."""
    while time.monotonic() - since < limit:
        with contextlib.suppress(BrainStemError):
            if m.echo(b"\x5a", timeout=max(0.05, min(CALL_TIMEOUT, limit - (time.monotonic() - since)))) == b"\x5a":
                return time.monotonic() - since
    return None


class Checks:
    """The functional check once the noise is off: each check's name and its failure, if any."""

    def __init__(self, soak: Soak) -> None:
        self.s, self.m, self.v = soak, soak.m, soak.v
        self.results: list[tuple[str, str | None]] = []
        self.retried: list[str] = []  # checks run again: the module had fallen behind real time
        self.excused_framing = self.excused_unsolicited = 0

    def check(self, name: str, fn: Callable[[], str | None]) -> None:
        """Run a check; one that failed after the library dropped a partial packet for its
        inter-byte timeout while the virtual module fell behind real time or stalled (its stderr
        says so, at most a second later) runs once more, and the report says so: to the library
        a simulation descheduled for 0.1 s mid-packet is a lost byte, which no real module does."""
        for attempt in (1, 2):
            lag0, seen0 = len(self.v.err), len(self.s.framing)
            framing0, unsolicited0 = self.m.link.stats.framing_errors, self.m.link.stats.unsolicited
            try:
                why = fn()
            except Exception as e:  # noqa: BLE001 - reported as the check's failure
                why = ("" if isinstance(e, BrainStemError) else "foreign ") + f"{type(e).__name__}: {e}"
            if why is None or attempt == 2 or not any(": timeout (" in f for f in self.s.framing[seen0:]):
                break
            time.sleep(1.1)
            if not (behind := self.v.err.find(r"^behind real time", lag0)):
                break
            self.retried.append(f"{name}: {why} (the module: {behind[0]})")
            self.excused_framing += self.m.link.stats.framing_errors - framing0
            self.excused_unsolicited += self.m.link.stats.unsolicited - unsolicited0
            self.m.drain()
        self.results.append((name, why))

    def every_configuration(self) -> str | None:
        bad = []
        for pin in range(NUM_PINS):
            for cfg in range(32):
                self.m.configure(pin, cfg)
                if (got := int(self.m.query(pin))) != cfg:
                    bad.append(f"pin {pin}: wrote 0x{cfg:02X}, read 0x{got:02X}")
            self.m.configure(pin)
        return "; ".join(bad[:5]) or None

    def time_pin_on_trains(self) -> str | None:
        bad = []
        for pin, us in PULSE_US.items():
            self.m.configure(pin, timer_width=True, timer_high=False)
            self.v.cover(1.0)
            for _ in range(5):
                try:
                    if abs((r := self.m.time_pin(pin)).ticks - us * 1e-6 / TICK_S) > TICK_SLACK:
                        bad.append(f"pin {pin}: {r.ticks} ticks, not {us * 1e-6 / TICK_S:g}")
                except BrainStemError as e:
                    bad.append(f"pin {pin}: {type(e).__name__}")
            self.m.configure(pin)
        self.v.trains_wait_out()
        return "; ".join(bad) or None

    def pipelined_writes(self) -> str | None:
        pins, mark, last = (0, 1, 2), len(self.v.out), {}  # from inputs: becoming an output is a pad line too
        for pin in pins:
            self.m.configure(pin, output=True)
        pendings = []
        for i in range(24):
            pin, value = pins[i % 3], (i // 3) % 2 ^ (i % 2)
            pendings.append(self.m.write(pin, value, wait=False))
            last[pin] = value
        for p in pendings:
            p.result()
        self.m.sync()
        bad = []
        for pin in pins:
            seen = ([m[1] for ln in self.v.out.lines[mark:] if (m := re.search(rf"\] pin {pin} driven (high|low)", ln))]
                    or ["unchanged"])[-1]
            if seen != ("high" if last[pin] else "low"):
                bad.append(f"pin {pin}: last write {last[pin]}, the pad {seen}")
            self.m.configure(pin)
        return "; ".join(bad) or None

    def heartbeat_link_up(self) -> str | None:
        answers, pattern, mark = self.m.link.stats.heartbeat_answers, r"\* link_up [01] ", len(self.v.out)
        last = (self.v.out.find(pattern) or ["none"])[-1]
        deadline = time.monotonic() + 3.0  # HB_RATE 10: a heartbeat every 256 ms
        while time.monotonic() < deadline:
            last = (self.v.out.find(pattern, mark) or [last])[-1]
            # Two answers since the noise went, and the module's link_up says so.
            if self.m.link.stats.heartbeat_answers >= answers + 2 and "link_up 1" in last:
                return None
            time.sleep(0.05)
        return f"heartbeats answered {self.m.link.stats.heartbeat_answers - answers} in 3 s; last link_up line: {last}"

    def run(self) -> None:
        self.m.drain()  # what the noise left in the queue
        framing0, seen0, unsolicited0 = self.m.link.stats.framing_errors, len(self.s.framing), self.m.link.stats.unsolicited

        def no_strays() -> str | None:
            self.m.sync()
            stray = self.m.drain()
            framing = self.m.link.stats.framing_errors - framing0 - self.excused_framing
            unsolicited = self.m.link.stats.unsolicited - unsolicited0 - self.excused_unsolicited
            if stray or framing or unsolicited:
                return (f"{unsolicited} unsolicited packets ({', '.join(str(p) for p in stray[:4])}), "
                        f"{framing} framing errors ({'; '.join(self.s.framing[seen0:][:4])})")
            return None
        # First, while what the noise left in the library is there: a measurement whose start
        # was lost must not take the result of the next one on its pin.
        for name, fn in ((("time_pin on pins 3 and 4 while pulse trains run (5 each; the results mostly come "
                           "before the start's confirmation)"), self.time_pin_on_trains),
                         ("every pin's configuration written and read back (5 x 32)", self.every_configuration),
                         ("24 pipelined wait=False writes on pins 0-2 (pads in the transcript)", self.pipelined_writes),
                         ("the heartbeat's link_up back up", self.heartbeat_link_up),
                         ("no stray packet, no framing error during the checks", no_strays)):
            self.check(name, fn)
        if not reader_alive():
            self.results.append(("the library's reader thread alive after the checks", "dead"))


@dataclass
class Result:
    phases: list[Phase]
    checks: list[tuple[str, str | None]]  # the first: the link answering after the noise
    retried: list[str]
    behind: list[str]  # the virtual module's reports of lag and stalls

    @property
    def failures(self) -> list[str]:
        return ([f"{p.name}: {f}" for p in self.phases for f in p.failures[:10]]
                + [f"check failed: {name}: {why}" for name, why in self.checks if why is not None])


def report(res: Result) -> str:
    def row(name: str, cell: Callable[[Phase], object]) -> str:
        return f"| {name} | " + " | ".join(str(cell(p)) for p in res.phases) + " |"
    kinds = [OK, WRONG] + sorted({o for p in res.phases for o in p.outcomes} - {OK, WRONG})
    lines = [
        "| | " + " | ".join(p.name for p in res.phases) + " |", "|---|" + "---:|" * len(res.phases),
        row("calls", lambda p: p.calls), *(row(k, lambda p, k=k: p.outcomes.get(k, 0)) for k in kinds),
        row("slowest call / its timeout", lambda p: f"{p.slowest[1]:.3f} s = {p.slowest[0]:.2f} x ({p.slowest[2]})"),
        row("bits flipped host → module", lambda p: f"{p.flips[0]} of {p.flips[1]}"),
        row("bits flipped module → host", lambda p: f"{p.flips[2]} of {p.flips[3]}"),
        *(row(f"library: {k.replace('_', ' ')}", lambda p, k=k: p.link.get(k, 0)) for k in LINK_COUNTS),
        row("wall time", lambda p: f"{p.seconds:.1f} s"), "", "After the noise, the functional check:", ""]
    lines += [f"- {'pass' if why is None else 'FAIL'}: {name}" + ("" if why is None else f": {why}") for name, why in res.checks]
    lines += [f"- run again, having failed while the module was behind real time: {r}" for r in res.retried]
    if wrong := [f"- {p.name}: {w}" for p in res.phases for w in p.wrong]:
        lines += ["", f"Wrong values ({len(wrong)}; counted, not failures), the first ones:", "", *wrong[:8]]
    if res.behind:
        lines += ["", f"The virtual module fell behind real time {len(res.behind)} times (a busy machine): "
                  + "; ".join(b.removeprefix("behind real time: ") for b in res.behind[:6])
                  + ("; ..." if len(res.behind) > 6 else "")]
    return "\n".join([*lines, "", "Result: " + ("FAIL" if res.failures else "PASS"), *(f"- {f}" for f in res.failures)])


def run_soak(*, seed: int, baseline: int, calls: int, bers: list[float], log: Callable[[str], None]) -> Result:
    """The whole soak; the virtual module's transcript (stdout and stderr) goes to TRANSCRIPT."""
    binary = make_built("virtual-build", "virtual-path", ["CLK_HZ=2000000", f"BAUD={BAUD}", "HB_RATE=10", "VIRTUAL_PGO=0"])
    with tempfile.TemporaryDirectory(prefix="bsd-soak-") as tmp:
        v = Virtual(binary, Path(tmp) / "port", seed)
        log(f"soak: seed {seed}; virtual module: {v.seed_line}")
        try:
            with brainstem_dio.open(v.port, A, timeout=CALL_TIMEOUT) as m:
                m.sync()
                soak, phases = Soak(m, v, random.Random(seed)), []
                for name, ber, n in [("quiet", 0.0, baseline)] + [(f"BER {b:g}", b, calls) for b in bers]:
                    phases.append(phase := soak.phase(name, ber, n))
                    log(f"soak: {name}: {phase.calls} calls in {phase.seconds:.1f} s: "
                        + ", ".join(f"{k} {c}" for k, c in phase.outcomes.most_common()))
                v.ask("ber 0", r"\] ber 0 +line noise")
                rec = answering_after(m, time.monotonic())
                for pin in range(NUM_PINS):  # what the noise left: every pin an input again
                    with contextlib.suppress(BrainStemError):
                        m.configure(pin)
                checks = Checks(soak)
                checks.results.append(("the link answering within 2 s of the noise stopping"
                                       + ("" if rec is None else f" ({rec:.3f} s)"), None if rec is not None else "no answer"))
                checks.run()
                return Result(phases, checks.results, checks.retried, v.err.find(r"^behind real time"))
        finally:
            v.stop()
            TRANSCRIPT.parent.mkdir(parents=True, exist_ok=True)
            TRANSCRIPT.write_text(v.out.text() + "\n" + v.err.text() + "\n", encoding="utf-8")
            log(f"soak: the virtual module's transcript: {TRANSCRIPT}")


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(prog="sim/soak.py", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=None, help="seed of the calls and the noise (default: random, printed)")
    ap.add_argument("--baseline", type=int, default=300, help="calls of the quiet baseline (default 300)")
    ap.add_argument("--calls", type=int, default=2000, help="calls per noisy phase (default 2000)")
    ap.add_argument("--bers", type=float, nargs="+", default=[1e-4, 1e-3], metavar="P",
                    help="the noisy phases' bit error rates (default 1e-4 1e-3)")
    args = ap.parse_args(argv)
    if args.baseline < 0 or args.calls < 1 or not all(0 < b <= 1 for b in args.bers) or not 0 <= (args.seed or 0) < 2**64:
        ap.error("--baseline 0 or more, --calls 1 or more, --bers above 0 and at most 1, --seed 0 to 2^64-1")
    seed = args.seed if args.seed is not None else int.from_bytes(os.urandom(4), "little")
    date = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    try:
        res = run_soak(seed=seed, baseline=args.baseline, calls=args.calls, bers=args.bers,
                       log=lambda s: print(s, file=sys.stderr, flush=True))
    except (AssertionError, subprocess.CalledProcessError, OSError) as e:
        print(f"sim/soak.py: error: the soak could not run: {e}", file=sys.stderr)
        return 1
    cmd = shlex.join(["sim/soak.py", *argv] + ([] if args.seed is not None else ["--seed", str(seed)]))
    text = (f"_Measured {date} by `{cmd}` (seed {seed}; the virtual module at 2 MHz, {BAUD} baud, "
            f"HB_RATE 10; the library's default timeout, {CALL_TIMEOUT} s)._\n\n{report(res)}")
    print(text)
    (TRANSCRIPT.parent / "report.md").write_text(text + "\n", encoding="utf-8")
    if res.failures:
        print("sim/soak.py: FAIL: " + "; ".join(res.failures), file=sys.stderr)
    return 1 if res.failures else 0


if __name__ == "__main__":
    sys.exit(main())
