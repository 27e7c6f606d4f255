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
import suite
from suite import Suite, on

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


def test_quick_policy_marks_the_other_simulator_deep() -> None:
    """on("icarus", pair): make test runs every case on Icarus and `pair` on Verilator too;
    the rest is `deep`; a test the policy would leave out of make test altogether is refused."""
    s = Suite(str(HERE / "runner_cases.py"), "runner_dut", {"a": {}, "b": {"X": 1}},
              quick=on("icarus", ("t", "b")))

    @s.test()
    async def t(dut) -> None:
        pass

    deep = {p.id: any(m.name == "deep" for m in p.marks) for p in s.cases()}
    assert deep == {"verilator-a-t": True, "verilator-b-t": False, "icarus-a-t": False,
                    "icarus-b-t": False}, deep
    groups = {p.id: [m.args[0] for m in p.marks if m.name == "xdist_group"] for p in s.cases()}
    assert groups["icarus-a-t"] == ["runner_cases-icarus-a"], groups

    @s.test("a", sims=["verilator"])
    async def verilator_only(dut) -> None:
        pass

    with pytest.raises(RuntimeError, match="no case of verilator_only"):
        s.cases()


def _group_cases(monkeypatch, selected: bool) -> list:
    import runner_group

    cases = [p.values[0] for p in runner_group.SUITE.cases()]
    monkeypatch.setattr(suite, "_SELECTED", {})
    monkeypatch.setattr(suite, "_RUNS", {})
    suite.select(cases if selected else [])
    return cases


def test_group_runs_once_and_judges_each_case(monkeypatch) -> None:
    """The first case of a group runs the group's selected tests in one simulator run; each
    case passes or fails on its own test's result."""
    import runner_group

    first, fails, last = _group_cases(monkeypatch, selected=True)
    calls: list[list[str]] = []
    real = runner.run_tests
    monkeypatch.setattr(runner, "run_tests", lambda *a, **k: calls.append(list(a[4])) or real(*a, **k))
    assert runner_group.SUITE.run(first) == "passed"
    with pytest.raises(runner.RunError, match="failed: fails"):
        runner_group.SUITE.run(fails)
    assert runner_group.SUITE.run(last) == "passed"
    assert calls == [["first", "fails", "last"]], calls


def test_unregistered_case_runs_alone(monkeypatch) -> None:
    import runner_group

    first, _, last = _group_cases(monkeypatch, selected=False)
    calls: list[list[str]] = []
    real = runner.run_tests
    monkeypatch.setattr(runner, "run_tests", lambda *a, **k: calls.append(list(a[4])) or real(*a, **k))
    assert runner_group.SUITE.run(last) == "passed"
    assert calls == [["last"]], calls


@pytest.mark.parametrize("outcome,match", [
    (({"first": "passed"}, 1, None), "exited with 1 before the cocotb test 'fails' ran .*case icarus-a-first"),
    (({}, 1, "the simulation ended without writing x"), "without writing x .*case icarus-a-first"),
])
def test_group_run_that_ended_early_fails_the_rest(monkeypatch, outcome, match) -> None:
    """A simulator that stopped during the group (a $fatal, a crash) fails every case whose
    test did not run, naming the case whose output holds the log."""
    import runner_group

    first, fails, _ = _group_cases(monkeypatch, selected=True)
    monkeypatch.setattr(runner, "run_tests", lambda *a, **k: outcome)
    if outcome[2] is None:
        assert runner_group.SUITE.run(first) == "passed"
    else:
        with pytest.raises(runner.RunError, match="without writing x"):
            runner_group.SUITE.run(first)
    with pytest.raises(runner.RunError, match=match):
        runner_group.SUITE.run(fails)


def test_build_name_clash_is_refused(tmp_path: Path) -> None:
    runner._claim(tmp_path, {"A": 1})
    runner._claim(tmp_path, {"A": 1})
    with pytest.raises(runner.RunError, match="different build names"):
        runner._claim(tmp_path, {"A": 2})
