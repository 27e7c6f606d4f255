# SPDX-License-Identifier: Apache-2.0
"""Fixtures of the host library's unit tests: a fake module on an in-memory line.

The fake module is the testbenches' model of the core (tb/lib/bsd_model.py): these tests run
from the repository, so tb/lib goes on the import path here (it is not part of the library)."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tb" / "lib"))

import pytest
from host_fake import FakeModule, serial_pair

import brainstem_dio


@pytest.fixture
def rig() -> Iterator[Callable[..., tuple[brainstem_dio.Module, FakeModule]]]:
    """`rig(fake_options..., link options as link_<name>, module options as mod_<name>)`
    -> (module, fake): a Module on an in-memory line to a started FakeModule. Everything is
    closed at the end of the test."""
    made: list[tuple[brainstem_dio.Module, FakeModule]] = []

    def make(**options: object) -> tuple[brainstem_dio.Module, FakeModule]:
        link_opts = {k[5:]: v for k, v in options.items() if k.startswith("link_")}
        mod_opts = {k[4:]: v for k, v in options.items() if k.startswith("mod_")}
        fake_opts = {k: v for k, v in options.items() if not k.startswith(("link_", "mod_"))}
        host, dev = serial_pair()
        fake = FakeModule(dev, **fake_opts)
        link = brainstem_dio.Link(host, **link_opts)
        m = brainstem_dio.Module(link, fake.addr, owns_link=True, **mod_opts)
        fake.start()
        made.append((m, fake))
        return m, fake

    yield make
    for m, fake in made:
        m.close()
        fake.stop()
