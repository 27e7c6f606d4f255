# SPDX-License-Identifier: Apache-2.0
"""Functional coverage of the top-level testbench (tb/lib/bsd_tb.py).

Off unless $BSD_FCOV_DIR is set: then every TB gets a `Sampler` (TB.fcov), which listens to the
reference model the test attaches with `TB.start(model)` (its `observers`: the model tells what
it decided as small events) and samples only what the core was seen to do. A command, a timer result or a heartbeat is a *pending* sample until
- its bytes were accepted by the core (the model's fed byte stream is compared, byte for
  byte, with what the AXI-Stream source saw the core take; a test that sends bytes the model
  was not fed stops the command sampling of that TB until the next reset), and
- the packets / RFLX strobes the model expected for it (by identity of the model's objects)
  were compared equal to the core's in a passing `TB.expect` (silent commands: the first
  passing `expect` after their last byte was taken).
So a bin records what the TB sent and the core answered, checked by the model, never what a
test meant to do. At the end of the simulation the hits go to
$BSD_FCOV_DIR/<test>-<sim>-<pid>.json; tools/fcov_report.py merges the files.

The coverpoints and crosses (COVERPOINTS, the one definition that tools/fcov_report.py reads):
- command: command x form (N 0..9, 9 = N > 8) x outcome x pin kind. A sample on an
  in-range pin falls into several pin-kind bins at once: input/output, timer/no_timer and,
  for a fixed pin, fixed. Commands without a pin byte have pin kind "-"; N = 0 and N > 8
  packets to the module have command "none".
- timer: mode x TSTATE x outcome (a delivered result > 1, a timeout, result = 1, and
  tmrConflict with the running measurement's mode).
- latch: TRG x fired (a raw_trans pulse) / rearmed (DIG_RST or DIG_CFG set that arms an
  enabled input) / race (a re-arm on the clock a matching edge arrives: test_latch).
- backpressure: at each release of a stalled output (`AxisSink.paused` back to False),
  whether a command reply, a timer result and a heartbeat were waiting, i.e. had become
  due before the release and were sent after it.

This module imports nothing of cocotb at load time, so the report tool can read it.
"""

from __future__ import annotations

import atexit
import contextlib
import json
import os
import re
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from bsd_model import (
    ByteFed,
    CommandDone,
    Event,
    Framing,
    HeartbeatDue,
    HeartbeatSkipped,
    LatchArmed,
    LatchFired,
    Reset,
    TimerCompleted,
    TimerConflict,
    TimerStarted,
)
from bsd_protocol import (
    CMD_DEBUG,
    CMD_DIG_CFG,
    CMD_DIG_IO,
    CMD_DIG_RST,
    CMD_HB,
    CMD_MSG,
    CMD_PTIME_RD,
    CMD_RESET,
    DIGCFG_ENA,
    DIGCFG_IODIR,
    DIGCFG_TRG,
    MSG_CMD_INDEX_ERR,
    MSG_CMD_INVALID,
    MSG_CMD_TOO_LONG,
    MSG_CMD_TOO_SHORT,
    MSG_CONFIG_ERR,
    MSG_SERIAL_ERROR,
    MSG_TMR_CONFLICT,
    TICK_HZ,
    TIMER_MAX_TICKS,
)
from bsd_protocol import COMMANDS as COMMAND_TEXT
from bsd_protocol import MESSAGES as MESSAGE_TEXT

if TYPE_CHECKING:  # pragma: no cover
    from bsd_model import Model, Output
    from bsd_tb import TB, RxPacket

ENV = "BSD_FCOV_DIR"
FORMAT = 1

# The commands and messages the coverpoints name, by the protocol table's names.
_CMD = {c: COMMAND_TEXT[c].removeprefix("cmd") for c in (CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST, CMD_PTIME_RD, CMD_HB,
                                                         CMD_DEBUG, CMD_RESET)}
_MSG = {c: MESSAGE_TEXT[c] for c in (MSG_CMD_INVALID, MSG_CMD_TOO_LONG, MSG_CMD_INDEX_ERR, MSG_TMR_CONFLICT,
                                     MSG_CMD_TOO_SHORT, MSG_SERIAL_ERROR, MSG_CONFIG_ERR)}
_TICK_S = 1.0 / TICK_HZ

COMMANDS = ("DIG_CFG", "DIG_IO", "DIG_RST", "PTIME_RD", "HB", "DEBUG", "RESET", "invalid", "none")
FORMS = tuple(str(n) for n in range(10))
OUTCOMES = ("none", "reply") + tuple(_MSG[c] for c in sorted(_MSG))
PIN_KINDS = ("input", "output", "fixed", "timer", "no_timer", "out_of_range", "-")
BOOL = ("0", "1")

Axes = tuple[tuple[str, tuple[str, ...]], ...]
COVERPOINTS: dict[str, Axes] = {
    "command": (("cmd", COMMANDS), ("n", FORMS), ("outcome", OUTCOMES), ("pin", PIN_KINDS)),
    "timer": (("mode", ("edge", "width")), ("tstate", BOOL),
              ("outcome", ("completed", "timeout", "result_1", "conflict"))),
    "latch": (("trg", ("fall", "rise")), ("event", ("fired", "rearmed", "race"))),
    "backpressure": (("reply", BOOL), ("timer", BOOL), ("heartbeat", BOOL)),
}

Bin = tuple[str, ...]


def bin_key(values: Sequence[str]) -> str:
    return "|".join(values)


def bins_of(axes: Axes) -> list[Bin]:
    """Every bin (one value per axis) of a coverpoint with these axes."""
    out: list[Bin] = [()]
    for _, values in axes:
        out = [b + (v,) for b in out for v in values]
    return out


def all_bins(name: str) -> list[Bin]:
    return bins_of(COVERPOINTS[name])


class Hits:
    """Hit counts per coverpoint and bin, checked against COVERPOINTS."""

    def __init__(self) -> None:
        self.counts: dict[str, Counter[Bin]] = {name: Counter() for name in COVERPOINTS}

    def hit(self, name: str, *values: str) -> None:
        axes = COVERPOINTS[name]
        if len(values) != len(axes) or any(v not in vals for v, (_, vals) in zip(values, axes)):
            raise ValueError(f"fcov: {values} is not a bin of {name} {[a for a, _ in axes]}")
        self.counts[name][tuple(values)] += 1

    def to_json(self) -> dict[str, dict[str, int]]:
        return {name: {bin_key(b): n for b, n in sorted(c.items())} for name, c in self.counts.items()}

    def __bool__(self) -> bool:
        return any(self.counts.values())


# ------------------------------------------------------------------------------- the sampler

_HITS = Hits()  # one simulation's hits, from every TB it builds
_WRITER_REGISTERED = False


def enabled() -> bool:
    return bool(os.environ.get(ENV))


def _current_test() -> str:
    """The running cocotb test (its main task is named `Test <name>`), for the file name."""
    with contextlib.suppress(Exception):  # outside a test's own task: no name
        from cocotb.task import current_task

        name = current_task().get_name()
        if name.startswith("Test "):
            return name[len("Test "):]
    return "unknown"


def output_path(directory: Path, test: str, sim: str, pid: int) -> Path:
    safe = re.sub(r"[^A-Za-z0-9_.-]+", "_", f"{test}-{sim}")
    return directory / f"{safe}-{pid}.json"


def write_hits(hits: Hits, directory: Path, test: str, sim: str, params: str) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    path = output_path(directory, test, sim, os.getpid())
    doc = {"format": FORMAT, "test": test, "sim": sim, "params": json.loads(params),
           "hits": hits.to_json()}
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(doc, sort_keys=True) + "\n")
    tmp.replace(path)
    return path


def _register_writer(test: str, sim: str, params: str) -> None:
    global _WRITER_REGISTERED
    if _WRITER_REGISTERED:
        return
    _WRITER_REGISTERED = True
    directory = Path(os.environ[ENV])

    def write() -> None:
        write_hits(_HITS, directory, _current_test() if test == "unknown" else test, sim, params)

    # The simulator's embedded Python ends through its normal finalisation, which runs atexit.
    atexit.register(write)


@dataclass
class _Pending:
    kind: str                       # "cmd", "timer" or "hb"
    hits: list[tuple[str, Bin]]
    objs: list[object]              # the model's packets / RFLX tuples for it (by identity)
    end: int | None = None          # command: index of its last byte in the fed stream
    ready: float | None = None      # timer: completion time; hb: due time
    on_commit: Callable[[float], None] | None = None  # gets the command's acceptance time
    t_accept: float | None = None


@dataclass
class _Verified:
    kind: str
    ready: float | None
    t_first: float


@dataclass
class _Stall:
    t0: float
    t1: float | None = None
    skipped: list[float] = field(default_factory=list)


class Sampler:
    """Attached to one TB: listens to the model given to `attach`, and is told by the TB when an
    `expect` passed (`on_expect`), when the output stalls (`on_pause`) and on reset."""

    def __init__(self, tb: TB) -> None:
        self.tb = tb
        self.p = tb.p
        self.hits = _HITS
        self.model: Model | None = None
        self._fed = bytearray()
        self._base = 0           # index in tb.source.accepted of self._fed[0]
        self._checked = 0        # fed bytes compared equal with accepted ones
        self._desync = False
        self._pending: list[_Pending] = []
        self._trans: list[tuple[int, str]] = []  # (pin, trg) of model firings not yet verified
        self._stalls: list[_Stall] = []
        self._timer_start: dict[int, float] = {}
        self._extra: list[tuple[str, Bin]] = []  # samples of the command being executed
        self._started: int | None = None  # the timer it started
        sim = "unknown"
        with contextlib.suppress(Exception):  # outside a simulation: the name stays unknown
            import cocotb

            sim = str(cocotb.SIM_NAME).split()[0].lower()
        _register_writer(_current_test(), sim, self.p.to_json())

    # ------------------------------------------------------------- listening to a model
    def attach(self, model: Model) -> None:
        if self.model is model:
            return
        if self.model is not None:
            self.model.observers.remove(self.observe)
        self.model = model
        model.observers.append(self.observe)
        self._restart()

    def observe(self, ev: Event) -> None:
        """What the model decided (bsd_model's events), turned into pending samples."""
        if isinstance(ev, ByteFed):
            self._fed.append(ev.value)
        elif isinstance(ev, Framing):
            if ev.addr == self.p.module_addr:
                n = "0" if ev.n == 0 else "9"
                outcome = self._outcome(ev.packets[0] if ev.packets else None)
                self._add(_Pending("cmd", [("command", ("none", n, outcome, "-"))], list(ev.packets),
                                   end=len(self._fed) - 1))
        elif isinstance(ev, CommandDone):
            self._command(ev)
        elif isinstance(ev, TimerStarted):
            self._started = ev.pin
        elif isinstance(ev, TimerConflict):
            self._extra.append(("timer", (self._mode(ev.run.width), str(ev.run.target), "conflict")))
        elif isinstance(ev, LatchArmed):
            if ev.cfg & DIGCFG_IODIR and ev.cfg & DIGCFG_ENA:
                self._extra.append(("latch", (self._trg(ev.cfg), "rearmed")))
        elif isinstance(ev, LatchFired):
            self._trans.append((ev.pin, self._trg(ev.cfg)))
        elif isinstance(ev, TimerCompleted):
            self._timer_completed(ev)
        elif isinstance(ev, HeartbeatDue):
            self._add(_Pending("hb", [], list(ev.packets), ready=self._hb_due_time()))
        elif isinstance(ev, HeartbeatSkipped):
            for st in self._stalls:
                if st.t1 is None:
                    st.skipped.append(self._hb_due_time())
        elif isinstance(ev, Reset):
            self._restart()

    def _restart(self) -> None:
        """A reset (of the TB or the model): both byte streams start again."""
        self._fed = bytearray()
        self._base = len(self.tb.source.accepted)
        self._checked = 0
        self._desync = False
        self._pending = []
        self._trans = []
        self._timer_start = {}

    def on_reset(self) -> None:
        self._restart()
        self._stalls = []

    # ------------------------------------------------------------------- classification
    @staticmethod
    def _mode(width: bool) -> str:
        return "width" if width else "edge"

    @staticmethod
    def _trg(cfg: int) -> str:
        return "rise" if cfg & DIGCFG_TRG else "fall"

    @staticmethod
    def _outcome(first: bytes | None, error: int | None = None) -> str:
        """A command's outcome: the message it was refused with, else whether it answered."""
        if error is not None:
            return _MSG.get(error, "reply")
        if first is None:
            return "none"
        if len(first) == 4 and first[2] == CMD_MSG:
            return _MSG.get(first[3], "reply")
        return "reply"

    def _kinds(self, pin: int | None, was_input: bool | None) -> list[str]:
        p = self.p
        if pin is None:
            return ["-"]
        if was_input is None:
            return ["out_of_range"]
        kinds = ["input" if was_input else "output", "timer" if p.has_timer(pin) else "no_timer"]
        if p.is_fixed(pin):
            kinds.append("fixed")
        return kinds

    def _command(self, ev: CommandDone) -> None:
        cmd = _CMD.get(ev.data[0], "invalid")
        outcome = self._outcome(ev.packets[0] if ev.packets else None, ev.error)
        hits: list[tuple[str, Bin]] = [("command", (cmd, str(len(ev.data)), outcome, k))
                                       for k in self._kinds(ev.pin, ev.was_input)]
        hits += self._extra
        on_commit: Callable[[float], None] | None = None
        if self._started is not None:
            def on_commit(t: float, pin: int = self._started) -> None:
                self._timer_start[pin] = t
        self._extra, self._started = [], None
        self._add(_Pending("cmd", hits, list(ev.packets), end=len(self._fed) - 1, on_commit=on_commit))

    def _timer_completed(self, ev: TimerCompleted) -> None:
        start = self._timer_start.pop(ev.pin, None)
        if not (ev.run.host or ev.run.rflx):
            return
        outcome = "timeout" if ev.result == 0 else "result_1" if ev.result == 1 else "completed"
        ready = None
        if not ev.run.width and start is not None:
            ready = start + (ev.result or TIMER_MAX_TICKS) * _TICK_S
        self._add(_Pending("timer", [("timer", (self._mode(ev.run.width), str(ev.run.target), outcome))],
                           list(ev.output.packets) + list(ev.output.rflx), ready=ready))

    def _hb_due_time(self) -> float:
        period = self.p.hb_period_s or 0.0
        now = self.tb.now_s()
        if not period:
            return now
        k = round((now - self.tb.t_reset) / period)
        return self.tb.t_reset + k * period

    def _add(self, item: _Pending) -> None:
        if item.kind == "cmd" and self._desync:
            return
        self._pending.append(item)

    # ------------------------------------------------------------------- explicit samples
    def latch_race(self, trg: int) -> None:
        """A test measured a re-arm meeting a matching edge on the same clock (and checked
        the outcome itself)."""
        self.hits.hit("latch", "rise" if trg else "fall", "race")

    # ------------------------------------------------------------------------ TB events
    def on_pause(self, paused: bool) -> None:
        now = self.tb.now_s()
        if paused:
            if not self._stalls or self._stalls[-1].t1 is not None:
                self._stalls.append(_Stall(now))
        elif self._stalls and self._stalls[-1].t1 is None:
            self._stalls[-1].t1 = now

    def _check_stream(self) -> int:
        """How many fed bytes the core has taken, compared byte for byte."""
        acc = self.tb.source.accepted
        n = min(len(self._fed), len(acc) - self._base)
        while self._checked < n and not self._desync:
            if acc[self._base + self._checked][1] != self._fed[self._checked]:
                self._desync = True
                self.tb.log.info("fcov: the bytes sent differ from the bytes fed to the model at "
                                 "byte %d: no command samples until the next reset", self._checked)
                self._pending = [it for it in self._pending if it.kind != "cmd"]
            else:
                self._checked += 1
        return self._checked

    def on_expect(self, exp: Output, got: Sequence[RxPacket],
                  rflx: Sequence[tuple[float, int, int]], t_begin: float) -> None:
        """`TB.expect` found the core's packets, strobes and pulses equal to the model's."""
        times: dict[int, float] = {id(o): pk.t_first for o, pk in zip(exp.packets, got)}
        times.update({id(o): t for o, (t, _, _) in zip(exp.rflx, rflx)})
        taken = self._check_stream()
        acc = self.tb.source.accepted
        verified: list[_Verified] = []
        keep: list[_Pending] = []
        for it in self._pending:
            if it.end is not None and it.end >= taken:
                keep.append(it)  # not sent (yet)
                continue
            if not all(id(o) in times for o in it.objs):
                keep.append(it)  # its packets are not among these
                continue
            if it.end is not None:
                it.t_accept = acc[self._base + it.end][0]
                if it.on_commit is not None:
                    it.on_commit(it.t_accept)
            for name, b in it.hits:
                self.hits.hit(name, *b)
            ready = it.t_accept if it.kind == "cmd" else it.ready
            if it.kind == "timer":
                # A result with RFLX: its strobe marks its completion (never held back).
                for o in it.objs:
                    if isinstance(o, tuple):
                        ready = times[id(o)]
            for o in it.objs:
                if isinstance(o, bytes):
                    verified.append(_Verified(it.kind, ready, times[id(o)]))
        self._pending = keep
        # Transition latch firings, in the order the model and the core produced them.
        for pin in exp.trans:
            for i, (q, trg) in enumerate(self._trans):
                if q == pin:
                    self.hits.hit("latch", trg, "fired")
                    del self._trans[i]
                    break
        self._sample_stalls(verified, t_begin)

    def _sample_stalls(self, verified: Sequence[_Verified], t_begin: float) -> None:
        left = []
        margin = 2 * _TICK_S
        for st in self._stalls:
            if st.t1 is None or st.t1 > t_begin:
                left.append(st)
                continue
            t = st.t1

            def waiting(kind: str, slack: float = 0.0, t: float = t) -> bool:
                return any(v.kind == kind and v.ready is not None and v.ready + slack < t <= v.t_first
                           for v in verified)

            hb = waiting("hb") or any(st.t0 < due < t for due in st.skipped)
            self.hits.hit("backpressure", str(int(waiting("cmd"))), str(int(waiting("timer", margin))),
                          str(int(hb)))
        self._stalls = left
