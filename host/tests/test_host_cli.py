# SPDX-License-Identifier: Apache-2.0
"""The brainstem-dio command line: argument errors, port errors, and every command against
the fake module (in memory through a patched port opener, and once over socket://)."""

from __future__ import annotations

import io
import re
import subprocess
import sys

import pytest
from host_fake import FakeModule, FakeServer, serial_pair

import brainstem_dio.link
from brainstem_dio.cli import main


@pytest.fixture
def fake_port(monkeypatch):
    """Port names `fake` (a fake module), `mute` (one that answers nothing) for the CLI."""
    fakes: list[FakeModule] = []
    real_open = brainstem_dio.link.open_serial

    def open_serial(port, baudrate, timeout, write_timeout):
        if port not in ("fake", "mute"):
            return real_open(port, baudrate, timeout, write_timeout)
        host, dev = serial_pair()
        host.timeout = timeout  # as pyserial's open would
        fake = FakeModule(dev, levels=0b10001)
        fake.timer_results[4] = 500
        fake.timer_delay = 0.01
        fake.mute = port == "mute"
        fakes.append(fake.start())
        return host

    monkeypatch.setattr(brainstem_dio.link, "open_serial", open_serial)
    yield fakes
    for f in fakes:
        f.stop()


def run(argv, stdin: str = ""):
    out = io.StringIO()
    rc = main(argv, stdin=io.StringIO(stdin), stdout=out)
    return rc, out.getvalue()


# ---- argument errors: exit 2 and a message ----

ARG_ERRORS = [
    ([], "required: COMMAND"),
    (["frobnicate", "fake"], "invalid choice"),
    (["read"], "required: PORT"),
    (["read", "fake"], "required: PIN"),
    (["read", "fake", "x"], "not a number"),
    (["read", "fake", "64"], "a pin is 0..63"),
    (["write", "fake", "1"], "required: VALUE"),
    (["write", "fake", "1", "2"], "a value is 0/1"),
    (["read", "fake", "0", "--addr", "3"], "even, 2..254"),
    (["read", "fake", "0", "--addr", "0"], "even, 2..254"),
    (["read", "fake", "0", "--addr", "256"], "even, 2..254"),
    (["--addr", "5", "read", "fake", "0"], "even, 2..254"),
    (["read", "fake", "0", "--baud", "0"], "positive"),
    (["read", "fake", "0", "--baud", "fast"], "not a number"),
    (["read", "fake", "0", "--timeout", "-1"], ">= 0"),
    (["read", "fake", "0", "--timeout", "0"], "more than 0 seconds"),
    (["watch", "fake", "--count", "0"], "a count is a positive number"),
    (["watch", "fake", "--count", "-3"], "a count is a positive number"),
    (["watch", "fake", "--count", "x"], "not a number"),
    (["time", "fake", "1", "--edge", "--width"], "not allowed with"),
]


@pytest.mark.parametrize("argv, message", ARG_ERRORS, ids=[" ".join(a) or "(none)" for a, _ in ARG_ERRORS])
def test_argument_errors_exit_2(argv, message, capsys):
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    assert message in capsys.readouterr().err


def test_port_that_does_not_exist(capsys):
    rc, _out = run(["read", "/dev/brainstem-dio-nope", "0"])
    assert rc == 1
    err = capsys.readouterr().err
    assert "error: cannot open port '/dev/brainstem-dio-nope': No such file or directory" in err


def test_nobody_answers(fake_port, capsys):
    rc, _out = run(["probe", "mute", "--timeout", "0.05"])
    assert rc == 1
    err = capsys.readouterr().err
    assert "no answer from module 2" in err and "--baud 9600" in err and "--addr 2" in err


def test_wrong_address_nobody_answers(fake_port, capsys):
    rc, _ = run(["read", "fake", "0", "--addr", "4", "--timeout", "0.05"])
    assert rc == 1
    assert "no answer from module 4" in capsys.readouterr().err


# ---- commands ----


def test_probe(fake_port):
    rc, out = run(["probe", "fake"])
    assert rc == 0
    assert re.search(r"module 2 answered the resync probe in [\d.]+ ms", out)
    assert "echoed cmdDEBUG" in out


def test_read(fake_port):
    assert run(["read", "fake", "0"]) == (0, "1\n")
    assert run(["read", "fake", "1"]) == (0, "0\n")


def test_read_an_output_is_a_module_error(fake_port, capsys):
    rc, _ = run(["write", "fake", "1", "1"])
    assert rc == 1
    assert "cmdIndexErr (10)" in capsys.readouterr().err


def test_write_with_output(fake_port):
    assert run(["write", "fake", "1", "high", "--output"]) == (0, "")
    fake = fake_port[-1]
    assert fake.cfg[1] == 0 and fake.out_latch[1] == 1


def test_time(fake_port):
    rc, out = run(["time", "fake", "4", "--width", "--high"])
    assert (rc, out) == (0, "pin 4: 500 ticks = 800.0 us\n")
    assert fake_port[-1].cfg[4] == 0x19


def test_time_timeout_is_a_result(fake_port):
    rc, out = run(["time", "fake", "3", "--timeout", "0.1"])
    assert rc == 0 and "pin 3: timeout" in out


def test_time_on_a_pin_without_timer(fake_port, capsys):
    rc, _ = run(["time", "fake", "0"])
    assert rc == 1 and "no timer on it" in capsys.readouterr().err


def test_config(fake_port):
    assert run(["config", "fake", "3"]) == (0, "pin 3: 0x01 input\n")
    rc, out = run(["config", "fake", "2", "--latch", "rising", "--output"])
    assert (rc, out) == (0, "pin 2: 0x06 output, latch on 0->1\n")


def test_watch_prints_everything_heartbeats_included(fake_port):
    import threading
    import time

    def beats():
        while not fake_port:
            time.sleep(0.002)
        time.sleep(0.03)
        fake_port[-1].heartbeat()
        fake_port[-1].inject(bytes([2, 2, 0x80, 12]))
        fake_port[-1].heartbeat()

    t = threading.Thread(target=beats)
    t.start()
    rc, out = run(["watch", "fake", "--count", "3", "--duration", "2"])
    t.join()
    assert rc == 0
    lines = out.splitlines()
    assert lines[0].startswith("watching fake at 9600 baud")
    assert any("< 02:00,00" in line and "heartbeat UP" in line for line in lines)
    assert any("> 02:00,02" in line and "heartbeat answer 2" in line for line in lines)
    assert any("< 02:80,0C" in line and "cmdQOverflow" in line for line in lines)
    assert any("< 02:00,01" in line and "heartbeat DOWN" in line for line in lines)
    assert all(re.match(r"\[ *[\d.]+ ms\] ", line) for line in lines[1:])


def test_watch_nothing(fake_port):
    rc, _out = run(["watch", "mute", "--duration", "0.05"])
    assert rc == 0


CONSOLE = """\
# packets as the Console takes them
2 26 3
2 0x1A 0x07
DIG_CFG 2
cmdDIG_IO 0x80
query 3
config 1 output
write 1 1
read 0
read 1
time 4
echo 1 2
probe
rearm 2
2 1 99
sync
bogus
read
help
quit
read 0
"""


def test_console_session(fake_port):
    rc, out = run(["console", "fake", "--linger", "0"], CONSOLE)
    assert rc == 0
    lines = out.splitlines()

    def index(pattern: str) -> int:
        for i, line in enumerate(lines):
            if re.search(pattern, line):
                return i
        raise AssertionError(f"{pattern!r} not in:\n{out}")

    # Each answer follows its packet, decoded, with a timestamp.
    assert index(r"\] > 02:1A,03 +query pin 3") < index(r"\] < 02:1A,03,01 +pin 3 config 0x01: input")
    assert index(r"> 02:1A,07") < index(r"< 02:80,0A +cmdIndexErr")
    assert index(r"> 02:1A,02 ") < index(r"< 02:1A,02,01")
    assert index(r"> 02:1B,80 +read pin 0 \(HOST\)") < index(r"< 02:04,05,01 +pin 0 level 1")
    assert index(r"^= 0x01 input") > index(r"> 02:1A,03 +query")
    assert "= 0x00 output" in lines
    assert index(r"^= 1$") > 0
    assert index(r"^! cmdIndexErr \(10\)") > index(r"> 02:1B,81")  # read 1, an output
    assert index(r"< 02:04,0E,01,F4 +pin 4 timer: 500 ticks = 800.0 us") < index(r"^= 500 ticks")
    assert "= 01 02" in lines
    assert index(r"^= answered in") > index(r"> AD: +resync probe")
    assert index(r"< 02:80,08 +cmdInvalid") > index(r"> 02:01,63")
    assert index(r"^\? unknown command 'bogus'") > 0
    assert index(r"^\? missing argument") > 0
    assert index(r"query PIN") > 0  # help
    assert lines[-1].startswith("Lines starting")  # quit: the last `read 0` never ran
    # The library's own sync echoes are not shown without -v.
    assert not re.search(r"02:17,B5", out)


def test_console_verbose_shows_the_sync_echoes(fake_port):
    _rc, out = run(["console", "fake", "-v", "--linger", "0"], "write 1 1\n")
    assert re.search(r"> 02:17,B5,[0-9A-F]{2} +echo request +\(sync\)", out)


def test_console_warns_when_nobody_answers(fake_port):
    rc, out = run(["console", "mute", "--timeout", "0.05", "--linger", "0"], "")
    assert rc == 0 and "warning: no answer from module 2" in out


def test_cli_over_a_socket_url():
    server = FakeServer(levels=0b1)
    try:
        assert run(["read", server.url, "0"]) == (0, "1\n")
        rc, out = run(["probe", server.url])
        assert rc == 0 and "answered" in out
    finally:
        server.close()


def test_python_m_entry_point():
    proc = subprocess.run(
        [sys.executable, "-m", "brainstem_dio", "read", "/dev/brainstem-dio-nope", "0"],
        capture_output=True,
        text=True,
        timeout=30,
        check=False,
    )
    assert proc.returncode == 1
    assert "cannot open port" in proc.stderr


def test_help_lists_every_command(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--help"])
    assert info.value.code == 0
    out = capsys.readouterr().out
    for command in ("console", "probe", "read", "write", "time", "config", "watch", "--baud", "--addr"):
        assert command in out


# ---- reset ----


def test_reset_command(fake_port):
    rc, out = run(["reset", "fake"])
    assert rc == 0, out
    assert re.fullmatch(r"module 2 reset: power-up message after [\d.]+ ms\n", out), out
    (fake,) = fake_port
    assert fake.resets == 1 and fake.packets_with(24) == [b"\x18"]


def test_reset_command_without_an_answer(fake_port, capsys):
    rc, out = run(["reset", "mute", "--timeout", "0.05"])
    assert rc == 1 and out == ""
    assert "no answer from module 2" in capsys.readouterr().err


def test_reset_in_the_console(fake_port):
    rc, out = run(["console", "fake", "--linger", "0"], "config 1 output\nreset\nquery 1\nreset 1\n")
    assert rc == 0
    assert "= ok (the module sent its power-up message)" in out
    assert "= 0x01 input" in out  # pin 1 is an input again
    assert "? reset takes no argument" in out
    assert fake_port[0].resets == 1
