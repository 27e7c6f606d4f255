# SPDX-License-Identifier: Apache-2.0
"""Tests of tools/coverage.py's parsing, merging, metrics and waiver checks (no simulator)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
# Loaded under a name of its own: `coverage` is also coverage.py's package name.
_spec = importlib.util.spec_from_file_location("bsd_coverage_tool", ROOT / "tools" / "coverage.py")
assert _spec is not None and _spec.loader is not None
coverage = importlib.util.module_from_spec(_spec)
sys.modules["bsd_coverage_tool"] = coverage   # dataclasses look their module up
_spec.loader.exec_module(coverage)
Point, UsageError, merge, module_reports = coverage.Point, coverage.UsageError, coverage.merge, coverage.module_reports
overall, parse_dat, parse_waivers = coverage.overall, coverage.parse_dat, coverage.parse_waivers
stale_waivers, write_dat = coverage.stale_waivers, coverage.write_dat

TARGETS = coverage.TARGETS


def rec(file: str, line: int, col: int, kind: str, comment: str, count: int, span: str = "",
        hier: str = "top") -> str:
    module = Path(file).stem
    fields = [("f", str(ROOT / file)), ("l", str(line)), ("n", str(col)), ("t", kind),
              ("page", f"v_{kind}/{module}"), ("o", comment)]
    if span:
        fields.append(("S", span))
    fields.append(("h", hier))
    return "C '" + "".join(f"\x01{k}\x02{v}" for k, v in fields) + f"' {count}"


def dat(*records: str) -> str:
    return "# SystemC::Coverage-3\n" + "\n".join(records) + "\n"


# Run A: the block alone; run B: the same module inside a top (another hierarchy).
RUN_A = dat(
    rec("rtl/m.v", 10, 5, "line", "block", 7, "10"),
    rec("rtl/m.v", 11, 9, "branch", "if", 3, "11-13"),
    rec("rtl/m.v", 11, 10, "branch", "else", 0),
    rec("rtl/m.v", 4, 20, "toggle", "q[0]:0->1", 2),
    rec("rtl/m.v", 4, 20, "toggle", "q[0]:1->0", 0),
    rec("tb/x/tb.v", 3, 1, "line", "block", 0, "3"),   # not rtl/: never counted
)
RUN_B = dat(
    rec("rtl/m.v", 11, 10, "branch", "else", 5, hier="top.u_m"),
    rec("rtl/m.v", 4, 20, "toggle", "q[0]:1->0", 0, hier="top.u_m"),
    rec("rtl/m.v", 4, 20, "toggle", "q[1]:0->1", 1, hier="top.u_m"),
)


def test_parse_reads_fields_and_relativizes_paths() -> None:
    pts = parse_dat(RUN_A)
    assert len(pts) == 6
    p = Point("m", "rtl/m.v", 11, 9, "branch", "if", "11-13")
    assert pts[p] == 3
    assert p.lines() == [11, 12, 13]
    tog = next(q for q in pts if q.kind == "toggle" and q.comment == "q[0]:0->1")
    assert tog.signal == "q[0]" and pts[tog] == 2


def test_parameterized_copies_are_one_module() -> None:
    """Verilator names a module built with other parameters `m__N7`: it is still `m`."""
    text = rec("rtl/m.v", 10, 5, "line", "block", 1, "10").replace("v_line/m", "v_line/m__N7_Tb")
    assert [p.module for p in parse_dat(dat(text))] == ["m"]


def test_parse_rejects_garbage() -> None:
    with pytest.raises(ValueError, match="line 2"):
        parse_dat("# SystemC::Coverage-3\nnot a record\n")


def test_merge_adds_counts_across_instances() -> None:
    merged = merge([parse_dat(RUN_A), parse_dat(RUN_B)])
    assert merged[Point("m", "rtl/m.v", 11, 10, "branch", "else")] == 5
    assert merged[Point("m", "rtl/m.v", 4, 20, "toggle", "q[0]:1->0")] == 0
    assert merged[Point("m", "rtl/m.v", 4, 20, "toggle", "q[1]:0->1")] == 1
    assert len(merged) == 7     # the hierarchy is no part of a point


def test_write_dat_round_trips() -> None:
    merged = merge([parse_dat(RUN_A), parse_dat(RUN_B)])
    assert parse_dat(write_dat(merged)) == merged


def test_metrics_per_module_only_rtl() -> None:
    reports = module_reports(merge([parse_dat(RUN_A), parse_dat(RUN_B)]), [])
    assert list(reports) == ["m"]
    m = reports["m"].metrics
    assert (m["line"].covered, m["line"].total) == (4, 4)     # lines 10, 11, 12, 13
    assert (m["branch"].covered, m["branch"].total) == (2, 2)
    assert (m["toggle"].covered, m["toggle"].total) == (2, 3)
    assert [w for w, _ in m["toggle"].missed] == ["`q[0]:1->0`"]
    assert reports["m"].status(TARGETS) == "below"
    assert not overall(reports, TARGETS, [])


def test_a_line_is_missed_only_when_no_point_on_it_ran() -> None:
    pts = parse_dat(dat(rec("rtl/m.v", 20, 9, "branch", "if", 0, "20-22"),
                        rec("rtl/m.v", 20, 10, "branch", "else", 4)))
    lm = module_reports(pts, [])["m"].metrics["line"]
    assert (lm.covered, lm.total) == (1, 3)
    assert [w for w, _ in lm.missed] == ["line 21", "line 22"]


WAIVERS = '[m]\n"q[0]" = "q[0] is  constant\\nafter reset"\n'


def test_a_named_exception_passes_a_module_below_target() -> None:
    waivers = parse_waivers(WAIVERS)
    assert waivers[0].reason == "q[0] is constant after reset"
    reports = module_reports(merge([parse_dat(RUN_A), parse_dat(RUN_B)]), waivers)
    assert reports["m"].status(TARGETS) == "named"
    assert stale_waivers(reports, waivers) == []
    assert overall(reports, TARGETS, [])
    text = coverage.markdown(reports, TARGETS, 2, [])
    assert "every exception named" in text and "q[0] is constant after reset" in text


def test_a_waiver_that_matches_nothing_is_stale() -> None:
    waivers = parse_waivers(WAIVERS + '"q[1]" = "r"\n"z*" = "r"\n')
    reports = module_reports(merge([parse_dat(RUN_A), parse_dat(RUN_B)]), waivers)
    stale = stale_waivers(reports, waivers)
    assert [w.signal for w in stale] == ["q[1]", "z*"]    # q[1] rose, and no z was missed
    assert not overall(reports, TARGETS, stale)


def test_a_waiver_names_only_toggle_points() -> None:
    """Lines and branches are excluded in the source (coverage_off), never by a waiver."""
    pts = parse_dat(dat(rec("rtl/m.v", 10, 5, "line", "block", 0, "10")))
    waivers = parse_waivers('[m]\n"*" = "r"\n')
    assert module_reports(pts, waivers)["m"].metrics["line"].missed == [("line 10", None)]


@pytest.mark.parametrize("text,message", [
    ('m = "r"', "not a \\[module\\] table"),
    ('[m]\n"q" = ""', "not a non-empty string"),
    ('[m]\n"q" = 3', "not a non-empty string"),
    ("[m", "waivers"),
])
def test_bad_waivers_are_refused(text: str, message: str) -> None:
    with pytest.raises(UsageError, match=message):
        parse_waivers(text)


def test_bad_arguments_exit_non_zero(capsys: pytest.CaptureFixture[str]) -> None:
    for argv in (["--jobs", "0"], ["--bogus"], ["--no-run", "x"]):
        with pytest.raises(SystemExit) as stop:
            coverage.main(argv)
        assert stop.value.code == 2
    assert "at least 1" in capsys.readouterr().err


def test_no_data_is_an_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert coverage.main(["--no-run", "--dat", str(tmp_path), "--out", str(tmp_path / "o")]) == 2
    assert "no coverage data" in capsys.readouterr().err


def test_report_from_files(tmp_path: Path) -> None:
    """The whole report path over two data files: exit 1 below target, 0 with the waiver,
    the merged file and the annotated source written."""
    (tmp_path / "dat").mkdir()
    (tmp_path / "dat" / "a.dat").write_text(RUN_A)
    (tmp_path / "dat" / "b.dat").write_text(RUN_B)
    (tmp_path / "w.toml").write_text(WAIVERS)
    base = ["--no-run", "--dat", str(tmp_path / "dat"), "--out", str(tmp_path / "o")]
    assert coverage.main(base + ["--waivers", str(tmp_path / "none.toml")]) == 1
    assert coverage.main(base + ["--waivers", str(tmp_path / "w.toml")]) == 0
    assert len(parse_dat((tmp_path / "o" / "merged.dat").read_text())) == 6
    assert "q[0] is constant after reset" in (tmp_path / "o" / "summary.md").read_text()
    src = (ROOT / "rtl" / "m.v").is_file()   # rtl/m.v does not exist: an empty annotation
    assert (tmp_path / "o" / "src" / "m.v.txt").read_text() == "" and not src


def test_toggle_patterns_take_brackets_literally() -> None:
    match = coverage.glob_match
    assert match("cnt_q[15]", "cnt_q[1*]") and match("cnt_q[1]", "cnt_q[1*]") and match("a_b", "a?b")
    assert not match("cnt_q[2]", "cnt_q[1*]") and not match("cnt_q1", "cnt_q[1*]")


def test_toggle_misses_are_listed_by_signal() -> None:
    items = [f"`d[{i}]:0->1`" for i in range(6)] + [f"`d[{i}]:1->0`" for i in range(6)]
    items += ["`q:1->0`", "`r[2]:0->1`", "`r[2]:1->0`"]
    assert coverage._compact(items) == "`d` (6 bits), `q (1->0)`, `r[2]`"


def test_annotated_source_marks_uncovered_lines(tmp_path: Path) -> None:
    pts = parse_dat(dat(rec("rtl/bsd_sync.v", 3, 1, "line", "block", 4, "3"),
                        rec("rtl/bsd_sync.v", 4, 1, "line", "block", 0, "4")))
    coverage.write_sources(module_reports(pts, []), tmp_path)
    lines = (tmp_path / "bsd_sync.v.txt").read_text().splitlines()
    assert lines[2].startswith("         4     3 ") and lines[3].startswith("!        0     4 ")
    assert lines[0].startswith(" " * 15 + "1 ")
