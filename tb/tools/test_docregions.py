# SPDX-License-Identifier: Apache-2.0
"""Tests of tools/docregions.py, which fills the generated regions of docs/*.md."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools"))

from docregions import RegionError, fill, fill_file, regions  # noqa: E402

DOC = """# Title
hand-written
<!-- generated:a begin -->
old a
<!-- generated:a end -->
between
<!-- generated:b begin -->
<!-- generated:b end -->
tail
"""


def test_fill_replaces_only_named_regions():
    out = fill(DOC, {"a": "new a\nline 2\n"})
    assert out == DOC.replace("old a\n", "new a\nline 2\n")
    out = fill(DOC, {"b": "B"})
    assert "<!-- generated:b begin -->\nB\n<!-- generated:b end -->" in out
    assert "old a" in out  # region a untouched


def test_fill_empty_body_and_idempotent():
    out = fill(DOC, {"a": ""})
    assert "<!-- generated:a begin -->\n<!-- generated:a end -->" in out
    assert fill(fill(DOC, {"a": "x"}), {"a": "x"}) == fill(DOC, {"a": "x"})


def test_regions_in_order():
    assert regions(DOC) == ["a", "b"]


@pytest.mark.parametrize("bad, message", [
    (DOC.replace("<!-- generated:a end -->\n", ""), "region 'a' begins|no `generated:a end`|inside"),
    (DOC.replace("<!-- generated:a begin -->\n", ""), "without its begin"),
    (DOC + "<!-- generated:a begin -->\n<!-- generated:a end -->\n", "second"),
])
def test_malformed(bad, message):
    with pytest.raises(RegionError, match=message):
        fill(bad, {"b": "x"})


def test_quoted_marker_is_text():
    doc = "see `<!-- generated:a begin -->` below\n" + DOC
    out = fill(doc, {"a": "x"})
    assert out == "see `<!-- generated:a begin -->` below\n" + DOC.replace("old a\n", "x\n")
    with pytest.raises(RegionError, match="no region marker for 'c'"):
        fill("only `<!-- generated:c begin -->` quoted\n", {"c": "x"})


def test_missing_region_named():
    with pytest.raises(RegionError, match="no region marker for 'c'"):
        fill(DOC, {"c": "x"})


def test_fill_file(tmp_path):
    p = tmp_path / "doc.md"
    p.write_text(DOC)
    assert fill_file(p, {"a": "x"})
    assert not fill_file(p, {"a": "x"})
    with pytest.raises(RegionError, match="no such file"):
        fill_file(tmp_path / "absent.md", {"a": "x"})
