# SPDX-License-Identifier: Apache-2.0
"""Fixtures of the host library's unit tests: a fake module on an in-memory line."""

from __future__ import annotations

from collections.abc import Callable, Iterator

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
