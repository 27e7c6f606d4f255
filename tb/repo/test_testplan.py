# SPDX-License-Identifier: Apache-2.0
"""The test plan (tools/testplan.toml -> docs/testplan.md) cannot go stale: the repository's
plan passes `tools/testplan.py --check`, and the checker catches each kind of mistake in a
small synthetic repository (a missing test, a section without a row, an unknown proof or bin,
a cocotb test in no row, a stale table). No simulator: everything is read with `ast`."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))

import testplan  # noqa: E402
from testplan import Layout  # noqa: E402

# ------------------------------------------------------------------- the repository's plan


def test_repository_plan_is_complete_and_docs_up_to_date():
    proc = subprocess.run([sys.executable, str(ROOT / "tools" / "testplan.py"), "--check"],
                          cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "up to date" in proc.stdout


def test_repository_doc_is_what_write_makes():
    lay = Layout()
    rows = testplan.load_plan(lay)
    ctx = testplan.load_context(lay)
    assert testplan.check(lay, rows, ctx) == []
    assert testplan.stale(lay, testplan.render(rows, ctx)) is None
    # Every row of the plan is a row of the table, in the plan's order.
    text = (ROOT / "docs" / "testplan.md").read_text(encoding="utf-8")
    table = [ln for ln in text.splitlines() if ln.startswith("| **")]
    assert [ln.split("**")[1] for ln in table] == [r.id for r in rows]


def test_repository_anchors_are_the_documents_parts():
    anchors = {a.name: a for a in testplan.load_anchors(Layout())}
    for sec in ("§1", "§2", "§3", "§4.1", "§4.2", "§5", "§6", "§7"):
        assert anchors[f"PROTOCOL {sec}"].required, sec
    assert not anchors["PROTOCOL §4"].required  # no text of its own: §4.1 and §4.2 carry it
    decisions = [a for a in anchors.values() if a.key.startswith("decision ")]
    assert [a.key for a in decisions] == [f"decision {n}" for n in range(1, len(decisions) + 1)]
    assert len(decisions) >= 13
    assert anchors["DESIGN Latencies"].required
    assert not anchors["DESIGN Decisions where the contract is silent"].required
    assert all(not a.required for a in anchors.values() if a.doc == "FPGA")


def test_repository_cocotb_tests_are_found_without_cocotb():
    found = testplan.find_tests(Layout())
    assert "test_rearm_meets_edge" in found.cocotb["tb/brainstem_dio/test_latch.py"]
    # Stacked decorators (@SUITE.test() then @cocotb.parametrize) count once.
    assert found.cocotb["tb/bsd_parser/test_bsd_parser.py"].count("test_inter_byte_timeout") == 1
    # The Suite's pytest entry is not a cocotb test; a Suite used inside a test function is not either.
    assert "test_latch_top" in found.entries["tb/brainstem_dio/test_latch.py"]
    assert "tb/runner/test_runner.py" not in found.cocotb
    assert "test_param_check" in found.pytest["tb/param_checks/test_param_checks.py"]
    assert "test_good_packets_back_to_back" in found.pytest["host/tests/test_host_framing.py"]
    jobs = testplan.formal_jobs(Layout())
    assert ("bsd_tick_gen", "prove_clk48m") in jobs


# --------------------------------------------------------------- a small synthetic repository

PROTOCOL = """# Contract
## 1. Top
Text of one.
## 2. Pins
### 2.1 Latch
Text.
### 2.2 Timer
Text.
"""

DESIGN = """# Design
## Latencies (clocks of `clk`)
Two clocks.
## Decisions
1. **First.** One. [tb/blk]
2. **Second.** Two.
"""

BLOCK_TESTS = '''# SPDX-License-Identifier: Apache-2.0
import cocotb
import pytest
from suite import Suite

SUITE = Suite(__file__, "blk")


@SUITE.test()
async def test_alpha(dut):
    """alpha"""


@SUITE.test("b")
@cocotb.parametrize(x=[0, 1])
async def test_beta(dut):
    """beta"""


async def helper(dut):
    pass


@pytest.mark.parametrize("case", SUITE.cases())
def test_blk(case):
    SUITE.run(case)
'''

PLAIN_TESTS = '''# SPDX-License-Identifier: Apache-2.0
import pytest


@pytest.mark.parametrize("n", [1, 2])
def test_table_one(n):
    assert n


def test_table_two():
    pass


class TestGroup:
    def test_inside(self):
        pass
'''

SBY = '''# a comment
[tasks]
prove
cover

[options]
prove: mode prove
'''

GOOD_ROWS = '''
[[row]]
id = "PROTOCOL §1"
title = "the top"
tests = ["tb/blk/test_blk.py::test_alpha", "tb/other/test_other.py::test_table_*"]
proofs = ["blk"]
bins = ["latch:event=race"]

[[row]]
id = "PROTOCOL §2.1 latch"
title = "latch"
tests = ["tb/blk/test_blk.py::test_beta", "tb/other/test_other.py::TestGroup::test_inside"]
proofs = ["blk/prove"]

[[row]]
id = "PROTOCOL §2.2"
title = "timer"
tests = ["tb/other/test_other.py::test_table_one[1]"]
bins = ["timer:outcome=timeout"]

[[row]]
id = "DESIGN Latencies"
title = "latencies"
tests = ["tb/other"]

[[row]]
id = "DESIGN decision 1"
title = "first"
tests = ["tb/blk/test_blk.py::test_alpha"]

[[row]]
id = "DESIGN decision 2"
title = "second"
proofs = ["blk/cover"]
'''

DOC = """# Test plan
Hand-written header.

<!-- generated:testplan begin -->
<!-- generated:testplan end -->
"""


def make_repo(root: Path, rows: str = GOOD_ROWS) -> Layout:
    files = {
        "docs/PROTOCOL.md": PROTOCOL,
        "docs/DESIGN.md": DESIGN,
        "docs/testplan.md": DOC,
        "formal/blk.sby": SBY,
        "tb/blk/test_blk.py": BLOCK_TESTS,
        "tb/other/test_other.py": PLAIN_TESTS,
        "tools/testplan.toml": rows,
    }
    for rel, text in files.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text, encoding="utf-8")
    (root / "tb" / "lib").mkdir(parents=True, exist_ok=True)
    shutil.copy(ROOT / "tb" / "lib" / "fcov.py", root / "tb" / "lib" / "fcov.py")
    shutil.copy(ROOT / "tools" / "fcov_unreachable.toml", root / "tools" / "fcov_unreachable.toml")
    return Layout(root=root)


def errors_of(lay: Layout) -> list[str]:
    return testplan.check(lay, testplan.load_plan(lay), testplan.load_context(lay))


def one_error(lay: Layout, *needles: str) -> str:
    errs = errors_of(lay)
    assert len(errs) == 1, errs
    for n in needles:
        assert n in errs[0], errs[0]
    return errs[0]


def test_synthetic_good_plan_passes_and_write_makes_the_doc(tmp_path):
    lay = make_repo(tmp_path)
    assert errors_of(lay) == []
    # The empty region is stale until --write fills it; then --check passes.
    assert testplan.main(["--check", "--root", str(tmp_path)]) == 1
    assert testplan.main(["--write", "--root", str(tmp_path)]) == 0
    text = (tmp_path / "docs" / "testplan.md").read_text()
    assert text.startswith("# Test plan\nHand-written header.\n")
    assert "| **PROTOCOL §2.1 latch**<br>Latch | latch | `tb/blk/test_blk.py`: `test_beta`<br>" in text
    assert "`blk/prove`" in text and "`timer:outcome=timeout`" in text
    assert testplan.main(["--check", "--root", str(tmp_path)]) == 0
    # A hand edit inside the region is stale again.
    (tmp_path / "docs" / "testplan.md").write_text(text.replace("| latch |", "| edited |"))
    assert "stale" in (testplan.stale(lay, testplan.render(testplan.load_plan(lay), testplan.load_context(lay))) or "")
    assert testplan.main(["--check", "--root", str(tmp_path)]) == 1


def test_missing_cocotb_test_is_caught(tmp_path):
    lay = make_repo(tmp_path, GOOD_ROWS.replace("test_blk.py::test_beta", "test_blk.py::test_gamma"))
    errs = errors_of(lay)
    assert any("unknown test 'tb/blk/test_blk.py::test_gamma'" in e and "its tests: test_alpha, test_beta" in e
               for e in errs), errs
    # test_beta is now in no row, which is reported too.
    assert any(e.startswith("tb/blk/test_blk.py::test_beta: this cocotb test is in no row") for e in errs), errs
    assert len(errs) == 2


def test_missing_pytest_function_and_file_are_caught(tmp_path):
    lay = make_repo(tmp_path, GOOD_ROWS.replace("TestGroup::test_inside", "TestGroup::test_outside"))
    one_error(lay, "unknown test 'tb/other/test_other.py::TestGroup::test_outside'")
    lay = make_repo(tmp_path, GOOD_ROWS.replace("test_other.py::test_table_*", "test_other.py::test_tabel_*"))
    one_error(lay, "no test function of tb/other/test_other.py matches 'test_tabel_*'")
    lay = make_repo(tmp_path, GOOD_ROWS.replace('tests = ["tb/other"]', 'tests = ["tb/nothere/test_x.py"]'))
    one_error(lay, "no file or folder tb/nothere/test_x.py")


def test_a_cocotb_file_must_be_named_test_by_test(tmp_path):
    lay = make_repo(tmp_path, GOOD_ROWS.replace('tests = ["tb/other"]', 'tests = ["tb/blk/test_blk.py::test_blk"]'))
    one_error(lay, "test_blk is the file's pytest entry")
    lay = make_repo(tmp_path, GOOD_ROWS.replace('tests = ["tb/other"]', 'tests = ["tb/blk"]'))
    one_error(lay, "tb/blk holds cocotb tests")


def test_missing_section_row_is_caught(tmp_path):
    rows = GOOD_ROWS.replace('id = "PROTOCOL §2.2"', 'id = "PROTOCOL §2.1 timer too"')
    one_error(make_repo(tmp_path, rows), "docs/PROTOCOL.md:7: PROTOCOL §2.2 (Timer) has no row")
    rows = GOOD_ROWS.replace('id = "DESIGN decision 2"', 'id = "DESIGN decision 1 again"')
    one_error(make_repo(tmp_path, rows), "docs/DESIGN.md:6: DESIGN decision 2 (Second) has no row")
    rows = GOOD_ROWS.replace('id = "DESIGN Latencies"', 'id = "DESIGN decision 1 latencies"')
    one_error(make_repo(tmp_path, rows), "DESIGN Latencies (Latencies (clocks of clk)) has no row")


def test_a_row_for_no_section_is_caught(tmp_path):
    rows = GOOD_ROWS + '\n[[row]]\nid = "PROTOCOL §9"\ntitle = "gone"\nproofs = ["blk"]\n'
    one_error(make_repo(tmp_path, rows), "row 'PROTOCOL §9': names no heading or decision",
              "PROTOCOL §1, PROTOCOL §2, PROTOCOL §2.1")
    rows = GOOD_ROWS + '\n[[row]]\nid = "PROTOCOL §1"\ntitle = "again"\nproofs = ["blk"]\n'
    one_error(make_repo(tmp_path, rows), "row 'PROTOCOL §1': a second row with this id")


def test_unknown_proof_is_caught(tmp_path):
    lay = make_repo(tmp_path, GOOD_ROWS.replace('proofs = ["blk"]', 'proofs = ["bsd_parser"]'))
    one_error(lay, "unknown proof 'bsd_parser'", "formal/ has no job 'bsd_parser' (jobs: blk)")
    lay = make_repo(tmp_path, GOOD_ROWS.replace('"blk/prove"', '"blk/prove_deep"'))
    one_error(lay, "unknown proof 'blk/prove_deep': job blk has the tasks prove, cover")


def test_unknown_or_unreachable_bin_is_caught(tmp_path):
    lay = make_repo(tmp_path, GOOD_ROWS.replace('"latch:event=race"', '"latches"'))
    one_error(lay, "unknown bin 'latches': no coverpoint 'latches'")
    lay = make_repo(tmp_path, GOOD_ROWS.replace('"latch:event=race"', '"latch:event=missed"'))
    one_error(lay, "latch: event has no value missed")
    lay = make_repo(tmp_path, GOOD_ROWS.replace('"latch:event=race"', '"latch:edge=rise"'))
    one_error(lay, "'edge=rise' is not `axis=value` with an axis of latch")
    # N > 8 always gives serialError (tools/fcov_unreachable.toml): nothing reachable matches.
    lay = make_repo(tmp_path, GOOD_ROWS.replace('"latch:event=race"', '"command:cmd=none,n=9,outcome=reply"'))
    one_error(lay, "every bin it matches is unreachable")


def test_unmapped_cocotb_test_is_caught(tmp_path):
    lay = make_repo(tmp_path)
    path = tmp_path / "tb" / "blk" / "test_blk.py"
    path.write_text(path.read_text() + '\n\n@SUITE.test()\nasync def test_new(dut):\n    """new"""\n')
    one_error(lay, "tb/blk/test_blk.py::test_new: this cocotb test is in no row of tools/testplan.toml")


def test_row_without_test_or_proof_is_caught(tmp_path):
    rows = GOOD_ROWS.replace('proofs = ["blk/cover"]', 'bins = ["latch"]')
    one_error(make_repo(tmp_path, rows), "row 'DESIGN decision 2': no test and no proof checks it")


def test_bad_arguments_and_input_exit_2(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        testplan.main([])
    assert e.value.code == 2
    with pytest.raises(SystemExit) as e:
        testplan.main(["--check", "--write"])
    assert e.value.code == 2
    assert "not allowed with argument" in capsys.readouterr().err
    make_repo(tmp_path, GOOD_ROWS + "\n[[row]]\nid = 3\n")
    assert testplan.main(["--check", "--root", str(tmp_path)]) == 2
    assert "`id` must be a non-empty string" in capsys.readouterr().err
    make_repo(tmp_path, GOOD_ROWS.replace('title = "first"', 'title = "first"\nnote = "x"'))
    assert testplan.main(["--check", "--root", str(tmp_path)]) == 2
    assert "unknown key(s) note" in capsys.readouterr().err
    make_repo(tmp_path, "[[row]\n")
    assert testplan.main(["--check", "--root", str(tmp_path)]) == 2
    assert "tools/testplan.toml" in capsys.readouterr().err


def test_unreachable_bins_are_fcov_reports():
    """The checker reads tools/fcov_unreachable.toml as tools/fcov_report.py does."""
    import fcov_report  # noqa: PLC0415

    lay = Layout()
    points = testplan.coverpoints(lay)
    mine = testplan.unreachable_bins(lay, points)
    rules = fcov_report.load_rules(fcov_report.DEFAULT_RULES)
    for name, axes_def in points.items():
        axes = [a for a, _ in axes_def]
        ref = {b for b in testplan.bins_of(axes_def)
               if any(r.coverpoint == name and r.covers(axes, b) for r in rules)}
        assert mine[name] == ref, name


def test_a_proof_in_no_row_is_a_note_not_an_error(tmp_path, capsys):
    make_repo(tmp_path)
    (tmp_path / "formal" / "blk2.sby").write_text(SBY)
    assert testplan.main(["--write", "--root", str(tmp_path)]) == 0
    assert testplan.main(["--check", "--root", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "note: formal task in no row: blk2/prove" in out
    assert "note: coverpoint in no row: command" in out
