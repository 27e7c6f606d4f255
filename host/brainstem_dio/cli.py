# SPDX-License-Identifier: Apache-2.0
"""`brainstem-dio`: the command-line tool of the brainstem_dio host library.

    brainstem-dio console PORT            interactive: packets (`2 26 3`) or commands by name
    brainstem-dio probe PORT              resync probe and cmdDEBUG echo check
    brainstem-dio read PORT PIN           print an input pin's level
    brainstem-dio write PORT PIN VALUE    drive an output pin
    brainstem-dio time PORT PIN           time a pin with its event timer
    brainstem-dio config PORT PIN [...]   show or change a pin's configuration
    brainstem-dio watch PORT              print every packet, heartbeats included

Options for every command: --baud (9600), --addr (2), --timeout (0.5 s),
--inter-byte-timeout (0.1 s, 0 = none). Exit status: 0 done, 1 an error (no port, no
answer, a module message), 2 bad arguments, 130 interrupted.
"""

from __future__ import annotations

import argparse
import shlex
import sys
import threading
import time
from collections.abc import Callable, Sequence
from typing import Any, TextIO

from . import __version__
from . import protocol as P
from .errors import BrainStemError, ModuleError, PortError, Timeout
from .link import Link, LinkEvent
from .module import Module

PROG = "brainstem-dio"


# ---- argument types -------------------------------------------------------------------------------
def _int(text: str) -> int:
    try:
        return int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None


def _addr(text: str) -> int:
    value = _int(text)
    if not (2 <= value <= 254 and value % 2 == 0):
        raise argparse.ArgumentTypeError(f"a module address is even, 2..254 (got {text})")
    return value


def _positive(what: str) -> Callable[[str], int]:
    """An argument type: a number above 0, refused as `what` ("a baud rate") otherwise."""

    def parse(text: str) -> int:
        value = _int(text)
        if value <= 0:
            raise argparse.ArgumentTypeError(f"{what} is a positive number (got {text})")
        return value

    return parse


def _pin(text: str) -> int:
    value = _int(text)
    if not 0 <= value <= P.DEVCODE_PIN:
        raise argparse.ArgumentTypeError(f"a pin is 0..63 (got {text})")
    return value


def _level(text: str) -> int:
    key = text.strip().lower()
    if key in ("1", "high", "on", "true"):
        return 1
    if key in ("0", "low", "off", "false"):
        return 0
    raise argparse.ArgumentTypeError(f"a value is 0/1, low/high or off/on (got {text!r})")


def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number of seconds: {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"seconds must be >= 0 (got {text})")
    return value


def _timeout(text: str) -> float:
    value = _seconds(text)
    if value == 0:  # every answer would time out, and the message would blame the link
        raise argparse.ArgumentTypeError(f"a timeout is more than 0 seconds (got {text})")
    return value


def _link_options(parser: argparse.ArgumentParser, suppress: bool) -> None:
    def default(value: object) -> object:
        return argparse.SUPPRESS if suppress else value

    g = parser.add_argument_group("link options")
    g.add_argument("--baud", type=_positive("a baud rate"), default=default(9600), help="baud rate (default 9600)")
    g.add_argument("--addr", type=_addr, default=default(P.DEFAULT_MODULE_ADDR), help="module address (default 2)")
    g.add_argument("--timeout", type=_timeout, default=default(0.5), help="seconds to wait for an answer (default 0.5)")
    g.add_argument(
        "--inter-byte-timeout",
        type=_seconds,
        default=default(0.1),
        help="drop a partial packet after this many seconds without a byte (default 0.1; 0 = never)",
    )


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Talk to a BrainStem 1.0 digital I/O module (or the brainstem_dio core) over a serial port.",
        epilog="PORT is a device (/dev/ttyUSB0), a pty path, or a pyserial URL (socket://host:port, loop://).",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    _link_options(parser, suppress=False)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    def add(name: str, help_text: str) -> argparse.ArgumentParser:
        p = sub.add_parser(name, help=help_text, description=help_text)
        p.add_argument("port", metavar="PORT", help="serial device, pty path or pyserial URL")
        _link_options(p, suppress=True)
        return p

    p = add("console", "interactive session: type packets (`2 26 3`) or commands (`help` lists them)")
    p.add_argument("--heartbeats", action="store_true", help="show heartbeats and their answers")
    p.add_argument("-v", "--verbose", action="store_true", help="show the sync echoes the library adds")
    p.add_argument("--linger", type=_seconds, default=0.2, help="seconds to keep printing after the input ends")

    add("probe", "send the resync probe AD 00 and a cmdDEBUG echo; report whether the module answers")

    add("reset", "reset the module (cmdRESET) and wait for its power-up message")

    p = add("read", "print the level (0 or 1) of an input pin")
    p.add_argument("pin", type=_pin, metavar="PIN")

    p = add("write", "drive an output pin")
    p.add_argument("pin", type=_pin, metavar="PIN")
    p.add_argument("value", type=_level, metavar="VALUE", help="0/1, low/high")
    p.add_argument("--output", action="store_true", help="configure the pin as an output first")

    p = add("time", "time a pin with its event timer (edge or width, in 1.6 us ticks)")
    p.add_argument("pin", type=_pin, metavar="PIN")
    _timer_options(p)

    p = add("config", "show a pin's configuration, or change it with the options")
    p.add_argument("pin", type=_pin, metavar="PIN")
    d = p.add_mutually_exclusive_group()
    d.add_argument("--output", dest="output", action="store_true", default=None, help="make it an output")
    d.add_argument("--input", dest="output", action="store_false", help="make it an input")
    p.add_argument("--latch", choices=("off", "rising", "falling"), help="the one-shot transition latch")
    _timer_options(p)

    p = add("watch", "print every packet that arrives, heartbeats included, until interrupted")
    p.add_argument("--duration", type=_seconds, help="stop after this many seconds")
    p.add_argument("--count", type=_positive("a count"), help="stop after this many packets")
    p.add_argument("--no-answer", action="store_true", help="do not answer heartbeats")
    return parser


def _timer_options(p: argparse.ArgumentParser) -> None:
    m = p.add_mutually_exclusive_group()
    m.add_argument("--edge", dest="width", action="store_false", default=None, help="edge timer: until the pin reaches the target level")
    m.add_argument("--width", dest="width", action="store_true", help="width timer: how long the pin stays at the target level")
    t = p.add_mutually_exclusive_group()
    t.add_argument("--high", dest="high", action="store_true", default=None, help="target level high")
    t.add_argument("--low", dest="high", action="store_false", help="target level low")


# ---- output ---------------------------------------------------------------------------------------------
class Printer:
    """Timestamped, decoded packet lines (shared by console and watch), thread-safe."""

    def __init__(self, out: TextIO, module: Module, heartbeats: bool = True, verbose: bool = False) -> None:
        self.out = out
        self.m = module
        self.heartbeats = heartbeats
        self.verbose = verbose
        self.t0 = time.monotonic()
        self.lock = threading.Lock()
        self.prompt: str | None = None  # set while an interactive prompt is showing
        self.line_buffer: Callable[[], str] = lambda: ""

    def line(self, text: str, when: float | None = None) -> None:
        stamp = ((when if when is not None else time.monotonic()) - self.t0) * 1e3
        self.plain(f"[{stamp:12.3f} ms] {text}")

    def plain(self, text: str) -> None:
        with self.lock:
            if self.prompt is not None:
                # A packet arrived while the user types: print it above the prompt line.
                self.out.write("\r\x1b[K" + text + "\n" + self.prompt + self.line_buffer())
            else:
                self.out.write(text + "\n")
            self.out.flush()

    def event(self, ev: LinkEvent) -> None:
        if ev.internal and not self.verbose:
            return
        if ev.kind in ("rx", "tx"):
            hb = ev.note in ("heartbeat", "heartbeat answer")
            if hb and not self.heartbeats:
                return
            arrow = "<" if ev.kind == "rx" else ">"
            if ev.packet is None:
                self.line(f"{arrow} raw {ev.raw.hex(' ').upper()}", ev.time)
                return
            p = ev.packet
            text = P.describe(
                p.addr,
                p.data,
                from_host=ev.kind == "tx",
                pin_id_base=self.m.pin_id_base,
                timer_id_base=self.m.timer_id_base,
            )
            if ev.kind == "tx" and p.addr == P.ADDR_RESYNC:
                text = "resync probe"
            extra = ev.note if ev.note in ("unsolicited", "late timer result", "unsolicited timer result", "sync") else ""
            tail = "  ".join(x for x in (text, f"({extra})" if extra else "") if x)
            self.line(f"{arrow} {p!s:<22} {tail}".rstrip(), ev.time)
        elif ev.kind == "framing":
            self.line(f"! framing error ({ev.note}): dropped {ev.raw.hex(' ').upper() or 'nothing'}; resynchronizing", ev.time)
        elif ev.kind == "resync":
            self.line(f"! resynchronized ({ev.note})", ev.time)
        elif ev.kind == "resync-timeout":
            self.line("! no answer to the resync probes; probing again", ev.time)
        elif ev.kind == "error":
            self.line(f"! port failed: {ev.note}", ev.time)


def _open(args: argparse.Namespace, **options: Any) -> Module:
    link = Link(
        args.port,
        baudrate=args.baud,
        resync_addr=args.addr,
        inter_byte_timeout=args.inter_byte_timeout or None,
        **options,
    )
    return Module(link, args.addr, timeout=args.timeout, owns_link=True)


def _error(text: str) -> int:
    sys.stderr.write(f"{PROG}: error: {text}\n")
    sys.stderr.flush()
    return 1


# ---- commands ----------------------------------------------------------------------------------------------
def cmd_probe(m: Module, args: argparse.Namespace, out: TextIO) -> int:
    rtt = m.probe()
    out.write(f"module {m.addr} answered the resync probe in {rtt * 1e3:.1f} ms\n")
    start = time.monotonic()
    m.echo(bytes([0x42]))
    out.write(f"module {m.addr} echoed cmdDEBUG in {(time.monotonic() - start) * 1e3:.1f} ms\n")
    return 0


def cmd_reset(m: Module, args: argparse.Namespace, out: TextIO) -> int:
    start = time.monotonic()
    m.reset()
    out.write(f"module {m.addr} reset: power-up message after {(time.monotonic() - start) * 1e3:.1f} ms\n")
    return 0


def cmd_read(m: Module, args: argparse.Namespace, out: TextIO) -> int:
    out.write(f"{m.read(args.pin)}\n")
    return 0


def cmd_write(m: Module, args: argparse.Namespace, out: TextIO) -> int:
    if args.output:
        m.update_config(args.pin, output=True)
    m.write(args.pin, args.value)
    return 0


def cmd_time(m: Module, args: argparse.Namespace, out: TextIO) -> int:
    changes = _timer_changes(args)
    if changes:
        m.update_config(args.pin, output=False, **changes)
    result = m.time_pin(args.pin, timeout=args.timeout + P.TIMER_TIMEOUT_S)
    if result.timed_out:
        out.write(f"pin {args.pin}: timeout (no completion within {P.TIMER_TIMEOUT_S * 1e3:.1f} ms)\n")
    else:
        out.write(f"pin {args.pin}: {result}\n")
    return 0


def _timer_changes(args: argparse.Namespace) -> dict[str, bool]:
    changes = {}
    if args.width is not None:
        changes["timer_width"] = args.width
    if args.high is not None:
        changes["timer_high"] = args.high
    return changes


def cmd_config(m: Module, args: argparse.Namespace, out: TextIO) -> int:
    changes = _timer_changes(args)
    if args.output is not None:
        changes["output"] = args.output
    if args.latch is not None:
        changes["latch"] = args.latch != "off"
        if args.latch != "off":
            changes["latch_rising"] = args.latch == "rising"
    cfg = m.update_config(args.pin, **changes) if changes else m.query(args.pin)
    out.write(f"pin {args.pin}: 0x{int(cfg):02X} {cfg}\n")
    return 0


def cmd_watch(m: Module, args: argparse.Namespace, out: TextIO) -> int:
    printer = Printer(out, m, heartbeats=True, verbose=True)
    count = [0]
    done = threading.Event()

    def listener(ev: LinkEvent) -> None:
        printer.event(ev)
        if ev.kind == "rx":
            count[0] += 1
            if args.count is not None and count[0] >= args.count:
                done.set()
        elif ev.kind == "error":
            done.set()

    m.link.add_listener(listener)
    printer.plain(f"watching {args.port} at {args.baud} baud (module {m.addr}); Ctrl-C stops")
    done.wait(args.duration)
    if not m.link.is_open:
        return _error(f"the port failed{m.link.diagnosis()}")
    if count[0] == 0:
        printer.plain(f"nothing received{m.link.diagnosis()}")
    return 0


# ---- console -----------------------------------------------------------------------------------------------
CONSOLE_HELP = """\
Type a packet as the BrainStem Console takes it: the address, then the data bytes, decimal or
0x hex; N is added (`2 26 3` queries pin 3 of module 2). A command name may stand for the
address and command code, to the --addr module: `DIG_CFG 3` (also `cmdDIG_CFG`, `dig_cfg`).
Commands:
  query PIN                      the pin's configuration
  config PIN [output|input] [latch-rising|latch-falling|latch-off] [edge|width] [high|low]
  read PIN                       an input's level
  write PIN VALUE                drive an output (0/1)
  rearm PIN                      re-arm the transition latch (cmdDIG_RST)
  reset                          reset the module (cmdRESET) and wait for its power-up message
  time PIN                       time the pin (cmdPTIME_RD)
  echo [BYTE...]                 cmdDEBUG echo
  probe                          the resync probe AD 00
  sync                           wait until everything sent has been executed
  help, quit
Lines starting with # are ignored. `<` lines came from the module, `>` lines were sent."""


def _console_line(m: Module, line: str, printer: Printer) -> bool:
    """Run one console line; False to quit."""
    words = shlex.split(line, comments=True)
    if not words:
        return True
    verb = words[0].lower()
    rest = words[1:]
    if verb in ("quit", "exit", "q"):
        return False
    if verb in ("help", "?"):
        printer.plain(CONSOLE_HELP)
        return True
    try:
        code = P.command_code(verb)
        if verb in ("reset", "cmdreset"):  # before the command-name form: wait for the answer
            if rest:
                printer.plain("? reset takes no argument (rearm PIN re-arms a pin's latch)")
            else:
                m.reset()
                printer.plain("= ok (the module sent its power-up message)")
        elif words[0][0].isdigit():
            _console_packet(m, [int(w, 0) for w in words], printer)
        elif code is not None:
            _console_packet(m, [m.addr, code] + [int(w, 0) for w in rest], printer)
        elif verb == "query":
            cfg = m.query(int(rest[0], 0))
            printer.plain(f"= 0x{int(cfg):02X} {cfg}")
        elif verb in ("config", "configure"):
            changes = _console_config(rest[1:])
            cfg = m.update_config(int(rest[0], 0), **changes)
            printer.plain(f"= 0x{int(cfg):02X} {cfg}")
        elif verb == "read":
            printer.plain(f"= {m.read(int(rest[0], 0))}")
        elif verb == "write":
            m.write(int(rest[0], 0), _level(rest[1]))
            printer.plain("= ok")
        elif verb in ("rearm", "dig_rst_pin"):
            m.rearm(int(rest[0], 0))
            printer.plain("= ok")
        elif verb == "time":
            printer.plain(f"= {m.time_pin(int(rest[0], 0))}")
        elif verb == "echo":
            printer.plain(f"= {m.echo(bytes(int(w, 0) for w in rest)).hex(' ').upper() or '(empty)'}")
        elif verb == "probe":
            printer.plain(f"= answered in {m.probe() * 1e3:.1f} ms")
        elif verb == "sync":
            m.sync()
            printer.plain("= ok")
        else:
            printer.plain(f"? unknown command {words[0]!r} (help lists them)")
    except IndexError:
        printer.plain("? missing argument (help lists the commands)")
    except (ValueError, argparse.ArgumentTypeError) as exc:
        printer.plain(f"? {exc} (help lists the commands)")
    except ModuleError as exc:
        printer.plain(f"! {exc.name} ({exc.code})")
    except BrainStemError as exc:
        printer.plain(f"! {exc}")
    return True


def _console_config(words: Sequence[str]) -> dict[str, bool]:
    table: dict[str, dict[str, bool]] = {
        "output": {"output": True},
        "input": {"output": False},
        "latch-rising": {"latch": True, "latch_rising": True},
        "latch-falling": {"latch": True, "latch_rising": False},
        "latch-off": {"latch": False},
        "edge": {"timer_width": False},
        "width": {"timer_width": True},
        "high": {"timer_high": True},
        "low": {"timer_high": False},
    }
    changes: dict[str, bool] = {}
    for w in words:
        if w.lower() not in table:
            raise ValueError(f"unknown config word {w!r}")
        changes.update(table[w.lower()])
    return changes


def _console_packet(m: Module, values: list[int], printer: Printer) -> None:
    if any(not 0 <= v <= 255 for v in values):
        raise ValueError("bytes are 0..255")
    addr, data = values[0], bytes(values[1:])
    if len(data) > P.MAX_N:
        raise ValueError("at most 8 data bytes")
    if addr and addr % 2 == 0:
        # Followed by a sync echo: the answers are all in (and shown) when it returns.
        target = m if addr == m.addr else Module(m.link, addr, timeout=m.timeout)
        target.request(data, check=False)
    else:
        m.link.send_packet(addr, data)
        time.sleep(min(0.05, m.timeout))


def cmd_console(m: Module, args: argparse.Namespace, out: TextIO, stdin: TextIO) -> int:
    printer = Printer(out, m, heartbeats=args.heartbeats, verbose=args.verbose)
    m.link.add_listener(printer.event)
    interactive = stdin.isatty()
    printer.plain(
        f"{PROG} console on {args.port} at {args.baud} baud, module {m.addr}; `help` lists the commands"
    )
    try:
        m.echo(b"\x00")
    except Timeout as exc:
        printer.plain(f"warning: {exc}")
    if interactive:
        try:
            import readline  # line editing for input()

            printer.line_buffer = readline.get_line_buffer
        except ImportError:
            pass
    while True:
        try:
            if interactive:
                with printer.lock:
                    printer.prompt = "> "
                try:
                    line = input("> ")
                finally:
                    with printer.lock:
                        printer.prompt = None
            else:
                line = stdin.readline()
        except EOFError:
            break
        if not interactive:
            if not line:
                break
            line = line.rstrip("\n")
        if not _console_line(m, line, printer):
            break
    time.sleep(args.linger)
    return 0


COMMANDS: dict[str, Callable[..., int]] = {
    "probe": cmd_probe,
    "reset": cmd_reset,
    "read": cmd_read,
    "write": cmd_write,
    "time": cmd_time,
    "config": cmd_config,
    "watch": cmd_watch,
}


def main(argv: Sequence[str] | None = None, stdin: TextIO | None = None, stdout: TextIO | None = None) -> int:
    """The console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    out = stdout or sys.stdout
    options: dict[str, object] = {}
    if args.command == "watch" and args.no_answer:
        options["answer_heartbeats"] = False
    if args.command in ("console", "watch"):
        options["on_unsolicited"] = lambda p: None  # printed by the listener already
    try:
        m = _open(args, **options)
    except PortError as exc:
        return _error(str(exc))
    try:
        if args.command == "console":
            return cmd_console(m, args, out, stdin or sys.stdin)
        return COMMANDS[args.command](m, args, out)
    except KeyboardInterrupt:
        return 130
    except Timeout as exc:
        return _error(f"{exc} (port {args.port}, --baud {args.baud}, --addr {args.addr})")
    except ModuleError as exc:
        return _error(f"the module answered {exc.name} ({exc.code}): {_explain(exc)}")
    except BrainStemError as exc:
        return _error(str(exc))
    finally:
        m.close()


def _explain(exc: ModuleError) -> str:
    return {
        P.MSG_CMD_INDEX_ERR: "no such pin, no timer on it, or the wrong direction (read an output / write an input)",
        P.MSG_TMR_CONFLICT: "the pin's timer is still busy",
        P.MSG_CONFIG_ERR: "the pin's configuration is fixed",
        P.MSG_CMD_INVALID: "the module does not know the command",
        P.MSG_CMD_TOO_SHORT: "the command lacks bytes",
        P.MSG_CMD_TOO_LONG: "the command had extra bytes (it was executed)",
        P.MSG_SERIAL_ERROR: "a packet with N > 8",
    }.get(exc.code, str(exc))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
