# SPDX-License-Identifier: Apache-2.0
"""Tests of tools/fcov_report.py (merging functional-coverage files, the unreachable-bin list,
the report and its exit status) and of tb/lib/fcov.py's hit store and file names. No
simulator."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "tb" / "lib"))

import fcov  # noqa: E402
import fcov_report as rep  # noqa: E402


def doc(hits: dict[str, dict[str, int]], test: str = "t", sim: str = "verilator") -> dict:
    return {"format": fcov.FORMAT, "test": test, "sim": sim, "params": {}, "hits": hits}


def write(dirpath: Path, name: str, d: dict) -> None:
    (dirpath / name).write_text(json.dumps(d))


def test_hits_reject_bins_outside_the_definition():
    h = fcov.Hits()
    h.hit("latch", "rise", "fired")
    h.hit("latch", "rise", "fired")
    assert h.to_json()["latch"] == {"rise|fired": 2}
    with pytest.raises(ValueError):
        h.hit("latch", "up", "fired")
    with pytest.raises(ValueError):
        h.hit("latch", "rise")


def test_output_files_never_collide(tmp_path):
    h = fcov.Hits()
    h.hit("backpressure", "1", "0", "1")
    a = fcov.output_path(tmp_path, "test_x", "icarus", 11)
    b = fcov.output_path(tmp_path, "test_x", "icarus", 12)
    c = fcov.output_path(tmp_path, "test_y", "icarus", 11)
    assert len({a, b, c}) == 3
    assert fcov.output_path(tmp_path, "a/b c", "v", 1).name == "a_b_c-v-1.json"
    path = fcov.write_hits(h, tmp_path / "new", "test_x", "icarus", '{"clk_hz": 2}')
    got = json.loads(path.read_text())
    assert got["hits"]["backpressure"] == {"1|0|1": 1}
    assert got["params"] == {"clk_hz": 2} and got["format"] == fcov.FORMAT


def test_merge_sums_counts_over_runs():
    runs = rep.merge([
        ("a", doc({"latch": {"rise|fired": 2}, "timer": {"edge|0|timeout": 1}}, "t1", "icarus")),
        ("b", doc({"latch": {"rise|fired": 3, "fall|race": 1}}, "t2", "verilator")),
    ])
    assert runs.hits["latch"][("rise", "fired")] == 5
    assert runs.hits["latch"][("fall", "race")] == 1
    assert runs.hits["timer"][("edge", "0", "timeout")] == 1
    assert runs.files == 2 and runs.tests == {"t1", "t2"} and runs.sims == {"icarus", "verilator"}


@pytest.mark.parametrize("bad", [
    {"format": 99, "hits": {}},
    {"format": fcov.FORMAT},
    doc({"nosuch": {}}),
    doc({"latch": {"rise|nosuch": 1}}),
    doc({"latch": {"rise": 1}}),
    doc({"latch": {"rise|fired": -1}}),
    doc({"latch": {"rise|fired": True}}),
])
def test_merge_rejects_bad_files(bad):
    with pytest.raises(rep.InputError):
        rep.merge([("f", bad)])


def test_rules_match_and_unless():
    rules = rep.parse_rules({"rule": [
        {"coverpoint": "latch", "match": {"event": "race"}, "unless": {"trg": "rise"}, "reason": "r1"},
        {"coverpoint": "backpressure", "match": {"reply": "1", "timer": ["0", "1"]}, "reason": "r2"},
    ]})
    latch = ("trg", "event")
    assert rules[0].covers(latch, ("fall", "race"))
    assert not rules[0].covers(latch, ("rise", "race"))
    assert not rules[0].covers(latch, ("fall", "fired"))
    bp = ("reply", "timer", "heartbeat")
    assert rules[1].covers(bp, ("1", "0", "0")) and rules[1].covers(bp, ("1", "1", "1"))
    assert not rules[1].covers(bp, ("0", "1", "1"))
    assert "unless trg=rise" in rules[0].describe()


@pytest.mark.parametrize("rule", [
    {"coverpoint": "nosuch", "match": {"x": "1"}, "reason": "r"},
    {"coverpoint": "latch", "match": {"nosuch": "rise"}, "reason": "r"},
    {"coverpoint": "latch", "match": {"trg": "up"}, "reason": "r"},
    {"coverpoint": "latch", "match": {"trg": "rise"}},
    {"coverpoint": "latch", "match": {"trg": "rise"}, "reason": " "},
    {"coverpoint": "latch", "match": {}, "reason": "r"},
    {"coverpoint": "latch", "match": {"trg": []}, "reason": "r"},
    {"coverpoint": "latch", "match": {"trg": "rise"}, "reason": "r", "typo": 1},
])
def test_bad_rules_are_refused(rule):
    with pytest.raises(rep.InputError):
        rep.parse_rules({"rule": [rule]})


def test_summary_counts_unhit_and_wrongly_unreachable():
    rules = rep.parse_rules({"rule": [
        {"coverpoint": "latch", "match": {"trg": "fall", "event": "race"}, "reason": "r"},
    ]})
    runs = rep.merge([("a", doc({"latch": {"rise|fired": 1, "fall|race": 1, "rise|race": 0}}))])
    latch = {s.name: s for s in rep.summarize(runs, rules)}["latch"]
    assert (latch.bins, len(latch.unreachable), latch.reachable, latch.reachable_hit) == (6, 1, 5, 1)
    assert ("rise", "race") in latch.unhit  # a zero count is not a hit
    assert latch.unreachable_hit == [("fall", "race")]
    assert rep.failed(rep.summarize(runs, rules))


def _all_reachable(rules: list[rep.Rule]) -> dict[str, dict[str, int]]:
    empty = rep.merge([])
    return {s.name: {fcov.bin_key(b): 1 for b in s.unhit} for s in rep.summarize(empty, rules)}


def test_main_exit_status_table_and_write(tmp_path, capsys):
    rules_path = tmp_path / "rules.toml"
    rules_path.write_text('[[rule]]\ncoverpoint = "latch"\nmatch = { event = "race" }\nreason = "not sampled"\n')
    rules = rep.load_rules(rules_path)
    indir = tmp_path / "fcov"
    indir.mkdir()
    full = _all_reachable(rules)
    # Every reachable bin hit, split over two files.
    half = {k: dict(list(v.items())[: len(v) // 2]) for k, v in full.items()}
    rest = {k: dict(list(v.items())[len(v) // 2:]) for k, v in full.items()}
    write(indir, "a-1.json", doc(half, "a"))
    write(indir, "b-2.json", doc(rest, "b"))
    assert rep.main(["--in", str(indir), "--unreachable", str(rules_path), "--check"]) == 0
    out = capsys.readouterr().out
    assert "| latch | trg × event | 6 | 2 | 4 | 4 (100 %) | 0 |" in out
    assert "latch: event=race (2 bins): not sampled" in out
    assert "Merged from 2 simulator runs (2 tests" in out
    # --md writes the same table to a file.
    md = tmp_path / "fcov.md"
    assert rep.main(["--in", str(indir), "--unreachable", str(rules_path), "--md", str(md)]) == 0
    assert md.read_text() == out
    # One reachable bin fewer: --check fails, and names it.
    rest["latch"].popitem()
    write(indir, "b-2.json", doc(rest, "b"))
    capsys.readouterr()
    assert rep.main(["--in", str(indir), "--unreachable", str(rules_path), "--check"]) == 1
    assert "- latch: trg=" in capsys.readouterr().out
    # Without --check the same input is only reported.
    assert rep.main(["--in", str(indir), "--unreachable", str(rules_path)]) == 0


def test_main_bad_input_exits_2(tmp_path, capsys):
    assert rep.main(["--in", str(tmp_path / "none")]) == 2
    empty = tmp_path / "empty"
    empty.mkdir()
    assert rep.main(["--in", str(empty)]) == 2
    write(empty, "x.json", doc({}))
    (empty / "y.json").write_text("{not json")
    assert rep.main(["--in", str(empty)]) == 2
    (empty / "y.json").unlink()
    assert rep.main(["--in", str(empty), "--md", str(tmp_path / "no" / "such" / "f.md")]) == 2
    assert "error" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:
        rep.main([])
    assert e.value.code == 2
    with pytest.raises(SystemExit) as e:
        rep.main(["--in", str(empty), "--bogus"])
    assert e.value.code == 2


def test_the_project_list_is_valid_and_every_rule_matters():
    rules = rep.load_rules(rep.DEFAULT_RULES)
    assert rules
    for s in rep.summarize(rep.merge([]), rules):
        for r, n in s.rule_counts:
            assert n > 0, f"rule {r.describe()} covers no bin"
        assert s.reachable > 0
