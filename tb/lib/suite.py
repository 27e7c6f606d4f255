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
(once for all cases that share them) and checks exactly that cocotb test: it fails if that
test failed, was skipped or did not run.

One simulator run serves every selected case of a group (same file, simulator, build and
knobs): the first case of the group to run starts the simulator on all of the group's
selected tests, and each case then reads its own test's result. Starting a simulator costs
about a second (cocotb, Python, the model), more than most block tests take, so one run per
test would spend most of the regression starting up. The cases carry the group as an
`xdist_group` mark, and `make test` runs pytest-xdist with `--dist loadgroup`, so a group
stays on one worker. conftest.py registers which cases of each group this session selected
(`select`); without that registration a case runs alone.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import cocotb
import pytest

import runner

# Per-case knobs: a fixed dict, or a function of (simulator, build name).
Args = Mapping[str, object] | Callable[[str, str], Mapping[str, object]]
# Which cases make test runs: a function of (simulator, build name, cocotb test name).
Quick = Callable[[str, str, str], bool]


def on(sim: str, *also: tuple[str, str]) -> Quick:
    """make test runs every test on every build it names once, on `sim`, and on the other
    simulator only the (test, build) pairs in `also`; make test-full runs them all on both
    simulators. One simulator per case halves the regression without dropping a behaviour:
    the other simulator's run repeats the same checks on the same build."""
    return lambda s, build, test: s == sim or (test, build) in also


@dataclass(frozen=True)
class Case:
    sim: str
    build: str
    test: str
    args: Mapping[str, object] = field(default_factory=dict)
    group: str = ""  # the cases one simulator run serves: file, simulator, build, knobs

    @property
    def id(self) -> str:
        return f"{self.sim}-{self.build}-{self.test}"


# {group: the cocotb tests of its selected cases, in run order}, filled by conftest.py.
_SELECTED: dict[str, list[str]] = {}
# {group or case id: (results, exit code, error, id of the case that started the run)}.
_RUNS: dict[str, tuple[dict[str, str], object, str | None, str]] = {}


def select(cases: Sequence[Case]) -> None:
    """Register the cases this session will run (pytest's final selection), by group."""
    _SELECTED.clear()
    for case in cases:
        names = _SELECTED.setdefault(case.group, [])
        if case.test not in names:
            names.append(case.test)


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
        quick: Quick | None = None,
    ) -> None:
        """`quick` (see `on`): the cases make test runs; the others are `deep`. None: all."""
        path = Path(module_file)
        self.module = path.stem
        self.module_dir = path.parent
        self.toplevel = toplevel
        self.builds = dict(builds or {"default": {}})
        self.sims = tuple(sims)
        self.sources = sources
        self.quick = quick
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
        """pytest params, one per (simulator, build, cocotb test), ids `sim-build-test`.
        Raises if the quick policy leaves a test no case in make test."""
        out = []
        for e in self._entries:
            in_quick = 0
            for sim in e.sims:
                for b in e.builds:
                    if e.only is not None and not e.only(sim, b):
                        continue
                    args = e.args(sim, b) if callable(e.args) else dict(e.args or {})
                    group = f"{self.module}-{sim}-{b}"
                    if args:
                        text = json.dumps(args, sort_keys=True)
                        group += "-" + hashlib.sha1(text.encode()).hexdigest()[:8]
                    case = Case(sim, b, e.name, args, group)
                    marks = [pytest.mark.xdist_group(group)]
                    if e.deep is not None and e.deep(sim, b) or self.quick is not None and not self.quick(sim, b, e.name):
                        marks.append(pytest.mark.deep)
                    else:
                        in_quick += 1
                    out.append(pytest.param(case, id=case.id, marks=marks))
            if not in_quick:
                raise RuntimeError(f"{self.module}: make test would run no case of {e.name} "
                                   "(its suite's quick policy leaves out all its simulators)")
        if not out:
            raise RuntimeError(f"{self.module}: no cocotb tests registered")
        return out

    def run(self, case: Case) -> str:
        """Check `case`'s cocotb test, running its group first if no run has served it yet;
        returns the test's result ('passed')."""
        selected = _SELECTED.get(case.group, [])
        key = case.group if case.test in selected else case.id  # unregistered: alone
        served_by = _RUNS[key][3] if key in _RUNS else None
        if served_by is None:
            results, exit_code, error = runner.run_tests(
                case.sim, self.toplevel, self.module, self.builds[case.build],
                selected if key == case.group else [case.test],
                name=case.build, args=case.args, module_dir=self.module_dir,
                sources=self.sources,
            )  # fmt: skip
            _RUNS[key] = (results, exit_code, error, case.id)
        results, exit_code, error, _ = _RUNS[key]
        where = f" (the simulator's log is in the output of case {served_by})" if served_by else ""
        if error:
            raise runner.RunError(error + where)
        mine = {n: s for n, s in results.items() if n == case.test or n.startswith(case.test + "/")}
        if not mine and exit_code:
            raise runner.RunError(f"{self.module}: the simulator exited with {exit_code} before "
                                  f"the cocotb test {case.test!r} ran{where}")
        runner.check_results(mine, self.module, [case.test])
        return next(iter(mine.values()))
