# SPDX-License-Identifier: Apache-2.0
"""Reference model of brainstem_dio: the contract (docs/PROTOCOL.md) plus the
decisions of docs/DESIGN.md.

The model is untimed. It is fed host bytes (`Model.feed`) and pad level changes
(`Model.set_pins`) and answers with what the core must produce, as an `Output`: whole
packets (`bytes`, `addr, N, data...`), `raw_trans` firings (pin numbers) and RFLX strobes
(`(id, data)`), in the order the core must produce them.

Time only enters in three places, each made explicit so the testbench supplies it:
- the inter-byte timeout: `feed(data, idle_before_s=...)` / `idle(seconds)`;
- event timers: the model knows which timers are busy and with which DEVCODE flags they were
  started; the testbench reports completions with `timer_complete(pin, result)` (or
  `timers_complete({pin: result})` for several on one clock); the expected result of a
  measurement is computed by the pure functions `timer_interval` / `expected_ticks`;
- heartbeats: `heartbeat_due()` / `heartbeat_skipped()` when the testbench knows one fell due.

Observers (`Model.observers`, callables) are told what the model decided, as the small events
below (`Event`), in the order it decided it: functional coverage (tb/lib/fcov.py) and the host
library's fake module (host/tests/host_fake.py) listen instead of reaching into the model.
`Model.packet` is the one place a whole host packet enters; a test double may extend it.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, field, fields

from bsd_protocol import ADDR_RESYNC as RESYNC_ADDR

# --- protocol constants (PROTOCOL.md §2, §3): generated from tools/protocol.toml ----------
# Re-exported: the tests import them from here.
from bsd_protocol import (
    CMD_DEBUG,
    CMD_DEV_VAL,
    CMD_DIG_CFG,
    CMD_DIG_IO,
    CMD_DIG_RST,
    CMD_HB,
    CMD_MAX_N,
    CMD_MSG,
    CMD_PTIME_RD,
    CMD_RESET,
    CMDF_ANY,
    CMDF_DEBUG,
    CMDF_DIG_CFG,
    CMDF_DIG_IO,
    CMDF_DIG_RST,
    CMDF_HB,
    CMDF_PTIME_RD,
    CMDF_RESET,
    DEFAULTS,
    DEVCODE_HOST,
    DEVCODE_PIN,
    DEVCODE_RFLX,
    DIGCFG_ENA,
    DIGCFG_FIXED,
    DIGCFG_IODIR,
    DIGCFG_RESET,
    DIGCFG_STORED,
    DIGCFG_TMODE,
    DIGCFG_TRG,
    DIGCFG_TSTATE,
    HB_UNIT_TICKS,
    HB_UP,
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
from bsd_protocol import HB_ANSWER_OFFSET as HB_ANSWER  # the host answers type t with t + HB_ANSWER
from bsd_protocol import MAX_N as MAX_DATA
from bsd_protocol import MSG_STATE_POWER_RESET as MSG_POWER_RESET

# Longest form of each host command the model executes, counting the command byte (longer is
# cmdTooLong). cmdHB is consumed apart; cmdDEBUG (any N from 1 to 8) is echoed back whole.
CMD_LONGEST = {c: CMD_MAX_N[c] for c in (CMD_DIG_CFG, CMD_DIG_IO, CMD_DIG_RST, CMD_PTIME_RD)}

TICK_S = 1.0 / TICK_HZ
HB_UNIT_S = HB_UNIT_TICKS / TICK_HZ
TIMER_TIMEOUT_S = TIMER_MAX_TICKS * TICK_S


# --- parameters ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Params:
    """The core's Verilog parameters (PROTOCOL.md §1), GP 1.0 defaults."""

    clk_hz: int = DEFAULTS["CLK_HZ"]
    module_addr: int = DEFAULTS["MODULE_ADDR"]
    num_pins: int = DEFAULTS["NUM_PINS"]
    timer_mask: int = DEFAULTS["TIMER_MASK"]
    fixed_mask: int = DEFAULTS["FIXED_MASK"]
    fixed_cfg: int = DEFAULTS["FIXED_CFG"]
    pin_id_base: int = DEFAULTS["PIN_ID_BASE"]
    timer_id_base: int = DEFAULTS["TIMER_ID_BASE"]
    trans_id_base: int = DEFAULTS["TRANS_ID_BASE"]
    poll_hz: int = DEFAULTS["POLL_HZ"]
    rx_timeout_us: int = DEFAULTS["RX_TIMEOUT_US"]
    hb_rate: int = DEFAULTS["HB_RATE"]

    def __post_init__(self) -> None:
        if self.clk_hz < 2_000_000:
            raise ValueError("CLK_HZ must be at least 2 MHz")
        if not (2 <= self.module_addr <= 254 and self.module_addr % 2 == 0):
            raise ValueError("MODULE_ADDR must be even, 2..254")
        if not 1 <= self.num_pins <= 64:
            raise ValueError("NUM_PINS must be 1..64")
        for name in ("timer_mask", "fixed_mask"):
            if getattr(self, name) >> self.num_pins:
                raise ValueError(f"{name} has bits above NUM_PINS")
        if self.fixed_cfg >> (8 * self.num_pins):
            raise ValueError("fixed_cfg has bytes above NUM_PINS")
        if self.pin_id_base + self.num_pins - 1 > 63:
            raise ValueError("pin device IDs must stay below 64")
        if self.timer_mask and self.timer_id_base + self.timer_mask.bit_length() - 1 > 63:
            raise ValueError("timer device IDs must stay below 64")
        if min(self.poll_hz, self.rx_timeout_us, self.hb_rate) < 0:
            raise ValueError("POLL_HZ, RX_TIMEOUT_US and HB_RATE are >= 0")

    # Vectors are passed as sized hex literals: Verilator's -G truncates a plain decimal
    # to 32 bits, and FIXED_CFG is 8*NUM_PINS bits wide.
    def to_hdl(self) -> dict[str, int | str]:
        """Verilog parameter values, names as in the contract, for the cocotb runner."""
        n = self.num_pins
        return {
            "CLK_HZ": self.clk_hz,
            "MODULE_ADDR": self.module_addr,
            "NUM_PINS": n,
            "TIMER_MASK": f"{n}'h{self.timer_mask:x}",
            "FIXED_MASK": f"{n}'h{self.fixed_mask:x}",
            "FIXED_CFG": f"{8 * n}'h{self.fixed_cfg:x}",
            "PIN_ID_BASE": self.pin_id_base,
            "TIMER_ID_BASE": self.timer_id_base,
            "TRANS_ID_BASE": self.trans_id_base,
            "POLL_HZ": self.poll_hz,
            "RX_TIMEOUT_US": self.rx_timeout_us,
            "HB_RATE": self.hb_rate,
        }

    @classmethod
    def from_hdl(cls, hdl: Mapping[str, object]) -> Params:
        """The inverse of to_hdl (missing names keep their defaults; other keys, such as a
        wrapper's BAUD, are not the core's and are ignored)."""
        names = {f.name for f in fields(cls)}
        values = {}
        for key, value in hdl.items():
            name = key.lower()
            if name in names:
                values[name] = verilog_int(value)
        return cls(**values)

    @classmethod
    def from_env(cls) -> Params:
        """Inside a cocotb test: the parameter set the simulation was built with."""
        from runner import hdl_params  # the runner's, only in a simulation: the model stays free of cocotb

        return cls.from_hdl(hdl_params())

    def to_json(self) -> str:
        return json.dumps(asdict(self), sort_keys=True)

    def replace(self, **changes: int) -> Params:
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        values.update(changes)
        return Params(**values)

    # Convenience views used by the model and the tests.
    @property
    def pins(self) -> range:
        return range(self.num_pins)

    def has_timer(self, pin: int) -> bool:
        return 0 <= pin < self.num_pins and bool(self.timer_mask >> pin & 1)

    def is_fixed(self, pin: int) -> bool:
        return 0 <= pin < self.num_pins and bool(self.fixed_mask >> pin & 1)

    def fixed_bits(self, pin: int) -> int:
        return self.fixed_cfg >> (8 * pin) & DIGCFG_STORED

    @property
    def timer_pins(self) -> list[int]:
        return [p for p in self.pins if self.has_timer(p)]

    @property
    def free_pins(self) -> list[int]:
        """Pins whose configuration the host may change."""
        return [p for p in self.pins if not self.is_fixed(p)]

    @property
    def rx_timeout_s(self) -> float | None:
        return self.rx_timeout_us * 1e-6 if self.rx_timeout_us else None

    @property
    def hb_period_s(self) -> float | None:
        return self.hb_rate * HB_UNIT_S if self.hb_rate else None

    def pin_id(self, pin: int) -> int:
        return self.pin_id_base + pin

    def timer_id(self, pin: int) -> int:
        return self.timer_id_base + pin


# --- packet builders ---------------------------------------------------------------------


def packet(addr: int, *data: int) -> bytes:
    """A whole packet: address, N, data."""
    return bytes([addr, len(data), *data])


def message(addr: int, code: int) -> bytes:
    return packet(addr, CMD_MSG, code)


def dev_val(addr: int, dev_id: int, value: int, wide: bool) -> bytes:
    if wide:
        return packet(addr, CMD_DEV_VAL, dev_id, value >> 8 & 0xFF, value & 0xFF)
    return packet(addr, CMD_DEV_VAL, dev_id, value)


# --- model outputs -----------------------------------------------------------------------


@dataclass
class Output:
    """What the core must produce, in order, per kind."""

    packets: list[bytes] = field(default_factory=list)
    trans: list[int] = field(default_factory=list)
    rflx: list[tuple[int, int]] = field(default_factory=list)

    def extend(self, other: Output) -> Output:
        self.packets += other.packets
        self.trans += other.trans
        self.rflx += other.rflx
        return self

    def __bool__(self) -> bool:
        return bool(self.packets or self.trans or self.rflx)


@dataclass(frozen=True)
class TimerRun:
    """A started measurement: where its result goes and the mode it started with."""

    host: bool
    rflx: bool
    width: bool
    target: int


# --- what the model tells its observers ----------------------------------------------------


@dataclass(frozen=True)
class ByteFed:
    """A host byte entered the framing (before it takes effect)."""

    value: int


@dataclass(frozen=True)
class Framing:
    """A length byte that ends its packet at once: N = 0 (the resync probe when sent to
    RESYNC_ADDR) or N > MAX_DATA (a framing error). `packets`: what it caused."""

    addr: int
    n: int
    packets: list[bytes]


@dataclass(frozen=True)
class PartialDropped:
    """The inter-byte timeout dropped a partial packet."""


@dataclass(frozen=True)
class CommandDone:
    """A packet to this module was executed. `pin`: the pin it names (None for a command
    without one), `was_input`: that pin's direction when the command arrived (None when the
    pin does not exist), `error`: the message it was refused with (or cmdTooLong after it
    ran), `packets`: everything it caused, in order."""

    data: tuple[int, ...]
    pin: int | None
    was_input: bool | None
    error: int | None
    packets: list[bytes]


@dataclass(frozen=True)
class TimerStarted:
    pin: int
    run: TimerRun


@dataclass(frozen=True)
class TimerConflict:
    """A PTIME_RD found `run` still measuring on `pin` (tmrConflict)."""

    pin: int
    run: TimerRun


@dataclass(frozen=True)
class TimerCompleted:
    """The measurement `run` on `pin` ended with `result` (0 = timeout); `output` is what it
    delivers (nothing when it went neither to the host nor to RFLX)."""

    pin: int
    run: TimerRun
    result: int
    output: Output


@dataclass(frozen=True)
class LatchArmed:
    """DIG_CFG (set) or DIG_RST armed the transition latch of `pin`, configured `cfg`."""

    pin: int
    cfg: int


@dataclass(frozen=True)
class LatchFired:
    pin: int
    cfg: int


@dataclass(frozen=True)
class HeartbeatDue:
    kind: int
    packets: list[bytes]


@dataclass(frozen=True)
class HeartbeatSkipped:
    """A heartbeat fell due while the previous one was not yet sent."""


@dataclass(frozen=True)
class Reset:
    """Back to the power-up state (rst or cmdRESET)."""


Event = (
    ByteFed | Framing | PartialDropped | CommandDone | TimerStarted | TimerConflict | TimerCompleted
    | LatchArmed | LatchFired | HeartbeatDue | HeartbeatSkipped | Reset
)
Observer = Callable[[Event], None]


# --- the model -----------------------------------------------------------------------------


class Model:
    """Untimed model of one brainstem_dio core."""

    def __init__(self, params: Params | None = None, pins: int = 0) -> None:
        self.p = params or Params()
        self.levels = pins
        self.observers: list[Observer] = []
        self.reset()

    def _tell(self, event: Event) -> None:
        for observer in self.observers:
            observer(event)

    # ---- state ----
    def reset(self, pins: int | None = None) -> Output:
        """`rst`: back to the power-up state (§6). Returns the power-up message."""
        p = self.p
        if pins is not None:
            self.levels = pins
        self.cfg = [p.fixed_bits(i) if p.is_fixed(i) else DIGCFG_RESET for i in p.pins]
        self.out_latch = [0] * p.num_pins
        # Arming loads the current level; for non-fixed pins ENA = 0, so this is inert.
        self.armed = [True] * p.num_pins
        self.prev = [self.level(i) for i in p.pins]
        self.timers: dict[int, TimerRun] = {}
        self._state = "addr"
        self._addr = 0
        self._n = 0
        self._data: list[int] = []
        self._hb_next = HB_UP
        self._hb_latest: int | None = None
        self._hb_answered = False
        self.link_up = False
        self._tell(Reset())
        return Output(packets=[message(p.module_addr, MSG_POWER_RESET)])

    def level(self, pin: int) -> int:
        return self.levels >> pin & 1

    def is_input(self, pin: int) -> bool:
        return bool(self.cfg[pin] & DIGCFG_IODIR)

    def digcfg(self, pin: int) -> int:
        """The DIGCFG byte a query returns."""
        return self.cfg[pin] | (DIGCFG_FIXED if self.p.is_fixed(pin) else 0)

    def pin_oe(self) -> int:
        return sum((0 if self.is_input(i) else 1) << i for i in self.p.pins)

    def pin_o(self) -> int:
        # An input pin shows its output latch too (§5).
        return sum(self.out_latch[i] << i for i in self.p.pins)

    def timer_busy(self, pin: int) -> bool:
        return pin in self.timers

    def timer_run(self, pin: int) -> TimerRun:
        return self.timers[pin]

    @property
    def mid_packet(self) -> bool:
        return self._state != "addr"

    # ---- host bytes ----
    def feed(self, data: Iterable[int], idle_before_s: float = 0.0) -> Output:
        """Host bytes, back to back, after `idle_before_s` of input idle time (only time
        with `s_axis_tready` 1 and `s_axis_tvalid` 0 counts)."""
        out = Output()
        self.idle(idle_before_s)
        for byte in data:
            self._byte(byte & 0xFF, out)
        return out

    def idle(self, seconds: float) -> None:
        """Input idle time. The core drops a partial packet somewhere between RX_TIMEOUT_US
        and RX_TIMEOUT_US + 1 tick of idle time (DESIGN.md 10); the model drops it at
        RX_TIMEOUT_US, so tests keep their gaps clear of that window."""
        limit = self.p.rx_timeout_s
        if limit is not None and seconds >= limit:
            if self._state != "addr":
                self._tell(PartialDropped())
            self._state = "addr"

    def _byte(self, b: int, out: Output) -> None:
        a = self.p.module_addr
        self._tell(ByteFed(b))
        if self._state == "addr":
            self._addr = b
            self._state = "len"
        elif self._state == "len":
            if b > MAX_DATA or b == 0:
                # N > 8, a framing error: address and length dropped, the next byte is an
                # address. N = 0: the resync probe when sent to RESYNC_ADDR.
                caused = []
                if b and self._addr == a:
                    caused.append(message(a, MSG_SERIAL_ERROR))
                elif not b and self._addr == RESYNC_ADDR:
                    caused.append(packet(a))
                out.packets += caused
                self._state = "addr"
                self._tell(Framing(self._addr, b, caused))
            else:
                self._n = b
                self._data = []
                self._state = "data"
        else:
            self._data.append(b)
            if len(self._data) == self._n:
                self._state = "addr"
                self.packet(self._addr, bytes(self._data), out)

    def packet(self, addr: int, data: bytes, out: Output) -> None:
        """A whole host packet (N >= 1) to `addr`: executed when it is this module's."""
        if addr == self.p.module_addr:
            self._execute(data, out)

    # ---- commands ----
    def _msg(self, out: Output, code: int) -> None:
        out.packets.append(message(self.p.module_addr, code))

    @staticmethod
    def pin_of(d: Sequence[int]) -> int | None:
        """The pin a command names: its pin byte, or the pin field of its DEVCODE."""
        if d[0] not in CMD_LONGEST or len(d) < 2:
            return None
        devcode = d[0] == CMD_PTIME_RD or (d[0] == CMD_DIG_IO and len(d) == 2)
        return d[1] & DEVCODE_PIN if devcode else d[1]

    def _execute(self, d: Sequence[int], out: Output) -> None:
        before = len(out.packets)
        pin = self.pin_of(d)
        was_input = self.is_input(pin) if pin is not None and pin < self.p.num_pins else None
        error = self._command(d, out)
        self._tell(CommandDone(tuple(d), pin, was_input, error, out.packets[before:]))

    def _command(self, d: Sequence[int], out: Output) -> int | None:
        """Runs a command; returns the message it was refused with (or cmdTooLong)."""
        cmd = d[0]
        if cmd == CMD_HB:
            self._hb_answer(d)
            return None
        if cmd == CMD_DEBUG:
            out.packets.append(packet(self.p.module_addr, *d))
            return None
        if cmd == CMD_RESET:
            # Any N; the power-up message is its answer. What the core had not yet sent is
            # dropped, which the caller's expectations must leave out (DESIGN.md).
            out.extend(self.reset())
            return None
        longest = CMD_LONGEST.get(cmd)
        if longest is None or len(d) == 1:
            refused = MSG_CMD_INVALID if longest is None else MSG_CMD_TOO_SHORT
            self._msg(out, refused)
            return refused
        handler = {
            CMD_DIG_CFG: self._dig_cfg,
            CMD_DIG_IO: self._dig_io,
            CMD_DIG_RST: self._dig_rst,
            CMD_PTIME_RD: self._ptime_rd,
        }[cmd]
        error = handler(d[:longest], out)
        if error is None and len(d) > longest:
            error = MSG_CMD_TOO_LONG
        if error is not None:
            self._msg(out, error)
        return error

    def _dig_cfg(self, d: Sequence[int], out: Output) -> int | None:
        pin = d[1]
        if pin >= self.p.num_pins:
            return MSG_CMD_INDEX_ERR
        if len(d) == 2:
            out.packets.append(packet(self.p.module_addr, CMD_DIG_CFG, pin, self.digcfg(pin)))
            return None
        if self.p.is_fixed(pin):
            return MSG_CONFIG_ERR
        self.cfg[pin] = d[2] & DIGCFG_STORED
        self._arm(pin)
        return None

    def _dig_io(self, d: Sequence[int], out: Output) -> int | None:
        if len(d) == 2:
            devcode = d[1]
            pin = devcode & DEVCODE_PIN
            if pin >= self.p.num_pins or not self.is_input(pin):
                return MSG_CMD_INDEX_ERR
            dev_id, value = self.p.pin_id(pin), self.level(pin)
            if devcode & DEVCODE_HOST:
                out.packets.append(dev_val(self.p.module_addr, dev_id, value, wide=False))
            if devcode & DEVCODE_RFLX:
                out.rflx.append((dev_id, value))
            return None
        pin = d[1]
        if pin >= self.p.num_pins or self.is_input(pin):
            return MSG_CMD_INDEX_ERR
        self.out_latch[pin] = int(d[2] != 0)
        return None

    def _dig_rst(self, d: Sequence[int], out: Output) -> int | None:
        pin = d[1]
        if pin >= self.p.num_pins:
            return MSG_CMD_INDEX_ERR
        self._arm(pin)  # DESIGN.md 6: on an output or with ENA = 0 this is silent and inert
        return None

    def _ptime_rd(self, d: Sequence[int], out: Output) -> int | None:
        devcode = d[1]
        pin = devcode & DEVCODE_PIN
        # The three cmdIndexErr reasons come before tmrConflict (§2 lists them first).
        if pin >= self.p.num_pins or not self.p.has_timer(pin) or not self.is_input(pin):
            return MSG_CMD_INDEX_ERR
        if pin in self.timers:
            self._tell(TimerConflict(pin, self.timers[pin]))
            return MSG_TMR_CONFLICT
        cfg = self.cfg[pin]
        run = self.timers[pin] = TimerRun(
            host=bool(devcode & DEVCODE_HOST),
            rflx=bool(devcode & DEVCODE_RFLX),
            width=bool(cfg & DIGCFG_TMODE),
            target=int(bool(cfg & DIGCFG_TSTATE)),
        )
        self._tell(TimerStarted(pin, run))
        return None

    # ---- timers ----
    def timer_complete(self, pin: int, result: int) -> Output:
        """The measurement on `pin` finished with `result` ticks (0 = timed out)."""
        if pin not in self.timers:
            raise KeyError(f"timer of pin {pin} is not running")
        if not 0 <= result <= TIMER_MAX_TICKS:
            raise ValueError("a result is 16 bits")
        run = self.timers.pop(pin)
        out = Output()
        dev_id = self.p.timer_id(pin)
        if run.host:
            out.packets.append(dev_val(self.p.module_addr, dev_id, result, wide=True))
        if run.rflx:
            out.rflx.append((dev_id, result))
        self._tell(TimerCompleted(pin, run, result, out))
        return out

    def timers_complete(self, results: dict[int, int]) -> Output:
        """Several measurements finishing on the same clock: ascending pin order (§5)."""
        out = Output()
        for pin in sorted(results):
            out.extend(self.timer_complete(pin, results[pin]))
        return out

    def timer_done(self, pin: int) -> None:
        """A measurement whose result goes nowhere (neither HOST nor RFLX) finished or timed
        out: the timer is free again (DESIGN.md 3)."""
        self.timer_complete(pin, 0)

    # ---- pads ----
    def set_pins(self, levels: int) -> Output:
        """New (synchronized) pad levels. Assumes each level lasts long enough to be
        sampled at POLL_HZ; returns the transition latches that fire, ascending pin."""
        out = Output()
        old, self.levels = self.levels, levels
        for pin in self.p.pins:
            new = levels >> pin & 1
            if new != (old >> pin & 1):
                self._sample(pin, new, out)
        return out

    def set_pin(self, pin: int, level: int) -> Output:
        mask = 1 << pin
        return self.set_pins(self.levels & ~mask | (mask if level else 0))

    def _arm(self, pin: int) -> None:
        self.armed[pin] = True
        self.prev[pin] = self.level(pin)
        self._tell(LatchArmed(pin, self.cfg[pin]))

    def _sample(self, pin: int, new: int, out: Output) -> None:
        cfg = self.cfg[pin]
        if not (cfg & DIGCFG_IODIR and cfg & DIGCFG_ENA and self.armed[pin]):
            return
        want = int(bool(cfg & DIGCFG_TRG))
        if new != self.prev[pin] and new == want:
            out.trans.append(pin)
            self.armed[pin] = False
            self._tell(LatchFired(pin, cfg))
        self.prev[pin] = new

    # ---- heartbeat (DESIGN.md 8) ----
    def heartbeat_due(self) -> Output:
        """A heartbeat falls due and can be queued (the previous one has been sent)."""
        if self._hb_latest is not None and not self._hb_answered:
            self.link_up = False
        kind = self._hb_next
        self._hb_next ^= 1
        self._hb_latest = kind
        self._hb_answered = False
        out = Output(packets=[packet(self.p.module_addr, CMD_HB, kind)])
        self._tell(HeartbeatDue(kind, out.packets))
        return out

    def heartbeat_skipped(self) -> Output:
        """A heartbeat falls due while the previous one is not yet sent: no packet, no
        toggle of the type, and it counts as unanswered."""
        self.link_up = False
        self._hb_answered = False
        self._tell(HeartbeatSkipped())
        return Output()

    def _hb_answer(self, d: Sequence[int]) -> None:
        if len(d) >= 2 and self._hb_latest is not None and d[1] == self._hb_latest + HB_ANSWER:
            self._hb_answered = True
            self.link_up = True


# --- event timer expectations (pure) --------------------------------------------------------

Waveform = Sequence[tuple[float, int]]


def level_at(waveform: Waveform, t: float) -> int:
    """Level of a waveform [(time_s, level), ...] (sorted; first entry at or before any
    time asked about) at time t."""
    level = None
    for when, lvl in waveform:
        if when > t:
            break
        level = lvl
    if level is None:
        raise ValueError("waveform starts after the time asked about")
    return level


def timer_completion(start_s: float, waveform: Waveform, width: bool, target: int) -> tuple[float, float] | None:
    """(completion time, measured interval) of a measurement started at `start_s`, ignoring
    the timeout; None if the waveform never completes it."""
    level = level_at(waveform, start_s)
    begin: float | None = None
    for when, lvl in waveform:
        if when <= start_s or lvl == level:
            continue
        level = lvl
        if not width:
            if lvl == target:
                return when, when - start_s
        elif begin is None:
            if lvl == target:
                begin = when
        else:  # back to non-target
            return when, when - begin
    return None


def timer_interval(start_s: float, waveform: Waveform, width: bool, target: int) -> float | None:
    """True interval in seconds a measurement reports, None if it times out (§4.2)."""
    done = timer_completion(start_s, waveform, width, target)
    if done is None or (done[0] - start_s) * TICK_HZ > TIMER_MAX_TICKS:
        return None
    return done[1]


def ticks_of(interval_s: float) -> int:
    """Nominal tick count of an interval; a completed result is never 0 (§4.2)."""
    return min(TIMER_MAX_TICKS, max(1, round(interval_s * TICK_HZ)))


def expected_ticks(start_s: float, waveform: Waveform, width: bool, target: int) -> int | None:
    """Expected result of a measurement: ticks (>= 1), or None for a timeout (result 0).
    The core may differ by one tick (tick phase) plus its fixed latency (a few clocks)."""
    interval = timer_interval(start_s, waveform, width, target)
    return None if interval is None else ticks_of(interval)


def result_of(ticks: int | None) -> int:
    """The 16-bit value a DEV_VAL/RFLX carries for `expected_ticks`' answer."""
    return 0 if ticks is None else ticks


def tick_tolerance(clk_hz: int, latency_clocks: int = 4) -> float:
    """Allowed |result - interval/1.6 us| in ticks: one tick, plus the core's fixed latency
    difference between start and end references (a few clocks, significant at 2 MHz)."""
    return 1.0 + latency_clocks * TICK_HZ / clk_hz


def ticks_close(result: int, interval_s: float, clk_hz: int, latency_clocks: int = 4) -> bool:
    """Whether a completed result matches a true interval within the accuracy of §4.2."""
    if result == 0:
        return False
    exact = interval_s * TICK_HZ
    return abs(result - exact) <= tick_tolerance(clk_hz, latency_clocks) or (exact < 1 and result == 1)


# --- block interfaces --------------------------------------------------------------------
# bsd_parser hands the executor d0 decoded (pkt_cmd_o, bsd_exec's pkt_cmd_i): bit CMDF_<NAME>
# (tools/protocol.toml) is "d0 is CMD_<NAME>", bit CMDF_ANY "d0 is any of them".
CMD_FLAG_BITS = {CMD_HB: CMDF_HB, CMD_DEBUG: CMDF_DEBUG, CMD_RESET: CMDF_RESET, CMD_DIG_CFG: CMDF_DIG_CFG,
                 CMD_DIG_IO: CMDF_DIG_IO, CMD_DIG_RST: CMDF_DIG_RST, CMD_PTIME_RD: CMDF_PTIME_RD}
CMD_FLAGS = tuple(CMD_FLAG_BITS)  # the commands that have a flag


def cmd_flags(d0: int) -> int:
    bit = CMD_FLAG_BITS.get(d0)
    return 0 if bit is None else 1 << bit | 1 << CMDF_ANY


def verilog_int(v: object) -> int:
    """An HDL parameter's value: an int, a decimal string or a sized Verilog literal
    ("5'h1e", "7'b1001010", "56'h1d_0000")."""
    if isinstance(v, int):
        return v
    s = str(v).replace("_", "")
    if "'" not in s:
        return int(s)
    radix = s.split("'")[1]
    return int(radix[1:], {"b": 2, "o": 8, "d": 10, "h": 16}[radix[0].lower()])


def pin_sel(d1: int, num_pins: int) -> int:
    """d1's pin (bits 5:0) as bsd_parser hands it over (pkt_sel_o, bsd_exec's pkt_sel_i): a
    one-hot over the pins, 0 for a pin past the last."""
    pin = d1 & 0x3F
    return 1 << pin if pin < num_pins else 0
