# SPDX-License-Identifier: Apache-2.0
"""The target of tb/host_virtual: the virtual module (sim/virtual.cpp, `make virtual`'s binary),
or a real board with `--port`.

    .venv/bin/python -m pytest tb/host_virtual                          # the virtual module
    .venv/bin/python -m pytest tb/host_virtual --port /dev/ttyUSB1      # a board on that port

`--port` is registered here, so it is known when this folder (or a file in it) is on the
command line, not with `pytest tb`. Against a board, the tests that need the virtual module's
standard input (pads, noise) or its transcript are skipped, and saying so.
"""

from __future__ import annotations

from typing import Iterator

import pytest

from host_target import MAKE_VARS, Target, Virtual, virtual_build  # noqa: E402


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--port", default=None, metavar="PORT",
                     help="tb/host_virtual: run against the board on this serial port (e.g. /dev/ttyUSB1) "
                          "instead of the virtual module")
    parser.addoption("--baud", type=int, default=9600,
                     help="tb/host_virtual with --port: the board's baud rate (default 9600)")


# Module scope: a running virtual module keeps half a core busy simulating real time, which
# the rest of `make test` should not pay for.
@pytest.fixture(scope="module")
def target(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Target]:
    port = request.config.getoption("--port", default=None)
    if port:
        yield Target(port, request.config.getoption("--baud", default=9600), None)
        return
    v = Virtual(virtual_build(MAKE_VARS), tmp_path_factory.mktemp("host_virtual") / "port")
    try:
        yield Target(v.port, 9600, v)  # the pty ignores the host's baud setting
    finally:
        v.stop()
