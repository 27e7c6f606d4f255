# SPDX-License-Identifier: Apache-2.0
"""The runner (tb/lib/runner.py): a pytest case fails naming the cocotb tests that failed, and
fails when no cocotb test ran (a file without tests, a filter that matches none, a build on
which every test is skipped)."""

from __future__ import annotations

from pathlib import Path

import pytest

import runner

HERE = Path(__file__).resolve().parent
SOURCES = [HERE / "runner_dut.v"]


def run(sim: str, module: str, **kw) -> dict[str, str]:
    return runner.run(sim, "runner_dut", module, module_dir=HERE, sources=SOURCES, **kw)


@pytest.mark.parametrize("sim", runner.SIMULATORS)
def test_failing_cocotb_test_fails_the_case_by_name(sim: str) -> None:
    with pytest.raises(AssertionError, match=r"runner_cases on .*: cocotb tests failed: counts_wrong \(seed \d+\)$"):
        run(sim, "runner_cases")


def test_passing_tests_pass_and_the_seed_is_printed(monkeypatch, capsys) -> None:
    monkeypatch.setenv("COCOTB_RANDOM_SEED", "1234")
    assert run("icarus", "runner_cases", testcase="counts") == {"counts": "passed"}
    assert "COCOTB_RANDOM_SEED=1234" in capsys.readouterr().out


@pytest.mark.parametrize("module, testcase", [("runner_empty", None), ("runner_cases", "no_such_test")])
def test_no_cocotb_test_run_fails(module: str, testcase: str | None) -> None:
    with pytest.raises(AssertionError, match="no cocotb test ran|ended without results"):
        run("icarus", module, testcase=testcase)


def test_a_test_runs_on_its_builds_only() -> None:
    assert run("icarus", "runner_builds", name="a", args={"knob": 3}) == {"only_on_a": "passed"}
    with pytest.raises(AssertionError, match="no cocotb test ran"):
        run("icarus", "runner_builds", name="b")


def test_cases_marks_the_other_simulator_and_deep_builds_deep() -> None:
    got = {p.id: bool(p.marks) for p in runner.cases(["x", "y"], quick="icarus", deep=["y"])}
    assert got == {"verilator-x": True, "verilator-y": True, "icarus-x": False, "icarus-y": True}
    assert [p.id for p in runner.cases(["x"], only=lambda sim, build: sim == "icarus")] == ["icarus-x"]
