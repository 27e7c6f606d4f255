# SPDX-License-Identifier: Apache-2.0
"""A test file's cocotb tests, each with the builds it needs, and the pytest cases that run them.

A test file holds its cocotb tests and its own pytest entry (taxi's layout). Each cocotb test
names the builds it runs on where it is defined, so there is no list of test names to keep
in step with the tests:

    SUITE = Suite(__file__, "brainstem_dio", TOP_BUILDS)

    @SUITE.test("gp1", "gp2")           # no names: every build of the suite
    async def test_dig_cfg(dut): ...

    @pytest.mark.parametrize("case", SUITE.cases())
    def test_brainstem_dio_commands(case): SUITE.run(case)

The pytest case `verilator-gp1-test_dig_cfg` builds `brainstem_dio` with gp1's parameters
(once for all cases that share them) and runs exactly that cocotb test; runner.run fails
the case if that test did not run.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Mapping, Sequence

import cocotb
import pytest

import runner

# Per-case knobs: a fixed dict, or a function of (simulator, build name).
Args = Mapping[str, object] | Callable[[str, str], Mapping[str, object]]


@dataclass(frozen=True)
class Case:
    sim: str
    build: str
    test: str
    args: Mapping[str, object] = field(default_factory=dict)

    @property
    def id(self) -> str:
        return f"{self.sim}-{self.build}-{self.test}"


@dataclass
class _Entry:
    name: str
    builds: tuple[str, ...]
    sims: tuple[str, ...]
    args: Args | None
    only: Callable[[str, str], bool] | None
    deep: Callable[[str, str], bool] | None


class Suite:
    """The cocotb tests of one file, on one toplevel, over named HDL parameter sets."""

    def __init__(
        self,
        module_file: str,
        toplevel: str,
        builds: Mapping[str, Mapping[str, object]] | None = None,
        sims: Sequence[str] = runner.SIMULATORS,
        sources: Sequence[Path] | None = None,
    ) -> None:
        path = Path(module_file)
        self.module = path.stem
        self.module_dir = path.parent
        self.toplevel = toplevel
        self.builds = dict(builds or {"default": {}})
        self.sims = tuple(sims)
        self.sources = sources
        self._entries: list[_Entry] = []

    def test(self, *builds: str, sims: Sequence[str] | None = None, args: Args | None = None,
             only: Callable[[str, str], bool] | None = None,
             deep: Callable[[str, str], bool] | None = None, **cocotb_kwargs: object):
        """`@cocotb.test(**cocotb_kwargs)`, run on `builds` (default: all) and `sims`, the
        pairs for which `only(sim, build)` holds if given. Pairs for which `deep(sim, build)`
        holds are marked `deep`: `make test-full` runs them, `make test` leaves them out (each
        is a long second run of a case that `make test` covers on another simulator or build)."""
        for b in builds:
            if b not in self.builds:
                raise KeyError(f"{self.module}: unknown build {b!r} (have {', '.join(self.builds)})")

        def decorate(fn):
            test = cocotb.test(**cocotb_kwargs)(fn)
            name = test.name.rsplit(".", 1)[-1]  # a test defined in a function: its own name
            self._entries.append(_Entry(name, tuple(builds or self.builds),
                                        tuple(sims or self.sims), args, only, deep))
            return test

        return decorate

    def cases(self) -> list:
        """pytest params, one per (simulator, build, cocotb test), ids `sim-build-test`."""
        out = []
        for e in self._entries:
            for sim in e.sims:
                for b in e.builds:
                    if e.only is not None and not e.only(sim, b):
                        continue
                    args = e.args(sim, b) if callable(e.args) else dict(e.args or {})
                    case = Case(sim, b, e.name, args)
                    marks = [pytest.mark.deep] if e.deep is not None and e.deep(sim, b) else []
                    out.append(pytest.param(case, id=case.id, marks=marks))
        if not out:
            raise RuntimeError(f"{self.module}: no cocotb tests registered")
        return out

    def run(self, case: Case) -> dict[str, str]:
        return runner.run(
            case.sim, self.toplevel, self.module,
            parameters=self.builds[case.build], testcase=case.test, name=case.build,
            args=case.args, module_dir=self.module_dir, sources=self.sources,
        )  # fmt: skip
