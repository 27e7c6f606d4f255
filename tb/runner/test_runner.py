# SPDX-License-Identifier: Apache-2.0
"""The runner (tb/lib/runner.py) fails a run that did not run what it was asked to run.

cocotb 2.1 only warns when its test filter matches nothing and leaves a results file with no
test in it; without these checks a renamed cocotb test would let its pytest case pass while
running nothing.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import runner
from suite import Suite

HERE = Path(__file__).resolve().parent
SOURCES = [HERE / "runner_dut.v"]


def run(sim: str, module: str, testcase=None) -> dict[str, str]:
    return runner.run(sim, "runner_dut", module, testcase=testcase, module_dir=HERE,
                      sources=SOURCES)


@pytest.mark.parametrize("sim", runner.SIMULATORS)
def test_named_test_runs(sim: str) -> None:
    assert run(sim, "runner_cases", "counts") == {"counts": "passed"}


@pytest.mark.parametrize("sim", runner.SIMULATORS)
def test_renamed_test_fails_the_run(sim: str) -> None:
    with pytest.raises(runner.RunError, match="'count' did not run"):
        run(sim, "runner_cases", "count")  # a prefix of a real test's name


def test_filter_matches_whole_names_only() -> None:
    """cocotb_tools' own testcase filter would also run `counts_wrong` for `wrong`."""
    with pytest.raises(runner.RunError, match="'wrong' did not run"):
        run("icarus", "runner_cases", "wrong")


def test_module_without_tests_fails() -> None:
    with pytest.raises(runner.RunError, match="without writing"):
        run("icarus", "runner_empty")


def test_skipped_or_failed_test_fails_the_check() -> None:
    """A named test that was skipped (cocotb runs a skip=True test only when named, so this
    comes from a results file) or failed fails the run; an unnamed skip does not."""
    with pytest.raises(runner.RunError, match="'skipped' was skipped"):
        runner.check_results({"skipped": "skipped"}, "m", ["skipped"])
    with pytest.raises(runner.RunError, match="failed: b"):
        runner.check_results({"a": "passed", "b": "failed"}, "m", None)
    with pytest.raises(runner.RunError, match="no cocotb test ran in m"):
        runner.check_results({}, "m", None)
    runner.check_results({"a": "passed", "s": "skipped"}, "m", None)


def test_failing_test_fails_the_run() -> None:
    # cocotb's runner itself stops a pytest caller with SystemExit when a test failed.
    with pytest.raises((runner.RunError, SystemExit)):
        run("icarus", "runner_cases", "counts_wrong")


def test_parametrized_test_runs_every_variant() -> None:
    results = run("icarus", "runner_cases", "counts_each")
    assert len(results) == 2 and set(results.values()) == {"passed"}, results


def test_suite_lists_exactly_its_tests() -> None:
    suite = Suite(str(HERE / "runner_cases.py"), "runner_dut", {"a": {}, "b": {"X": 1}})

    @suite.test("b", sims=["icarus"])
    async def only_b(dut) -> None:
        pass

    @suite.test()
    async def everywhere(dut) -> None:
        pass

    ids = [p.id for p in suite.cases()]
    assert ids == ["icarus-b-only_b", "verilator-a-everywhere", "verilator-b-everywhere",
                   "icarus-a-everywhere", "icarus-b-everywhere"], ids
    with pytest.raises(KeyError, match="unknown build 'c'"):
        suite.test("c")


def test_build_name_clash_is_refused(tmp_path: Path) -> None:
    runner._claim(tmp_path, {"A": 1})
    runner._claim(tmp_path, {"A": 1})
    with pytest.raises(runner.RunError, match="different build names"):
        runner._claim(tmp_path, {"A": 2})
