# SPDX-License-Identifier: Apache-2.0
"""Fill marked regions of a hand-written document, leave everything else alone.

A region is delimited by two marker lines (HTML comments, invisible in rendered Markdown):

    <!-- generated:area begin -->
    ... replaced on every run ...
    <!-- generated:area end -->

`fill(text, {"area": body})` replaces what lies between the markers of each named region
with `body` and returns the new text; regions of the document that are not named are left
as they are (so several generators can share one document). A marker is a line of its own
(a marker quoted inside a line of text is just text). Every named region must occur exactly
once, begin before end, not nested; anything else raises RegionError with the line number,
before anything is written.

    from docregions import fill_file
    fill_file(Path("docs/benchmarks.md"), {"test-time": table})

`python tools/docregions.py FILE` lists the regions of FILE.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

__all__ = ["RegionError", "fill", "fill_file", "regions"]

_NAME = r"[A-Za-z0-9][A-Za-z0-9_.-]*"
_MARKER = re.compile(rf"<!--\s*generated:({_NAME})\s+(begin|end)\s*-->")


class RegionError(ValueError):
    """A marker is missing, duplicated, nested or out of order."""


def _markers(text: str, where: str) -> dict[str, tuple[int, int]]:
    """name -> (index of the begin line, index of the end line), lines counted from 0."""
    found: dict[str, dict[str, int]] = {}
    open_name: str | None = None
    for i, line in enumerate(text.splitlines()):
        hit = _MARKER.fullmatch(line.strip())
        if not hit:
            continue   # a marker quoted inside a line of text is text
        name, kind = hit.groups()
        seen = found.setdefault(name, {})
        if kind in seen:
            raise RegionError(f"{where}:{i + 1}: second `generated:{name} {kind}` marker "
                              f"(the first is on line {seen[kind] + 1})")
        if kind == "begin":
            if open_name is not None:
                raise RegionError(f"{where}:{i + 1}: region {name!r} begins inside region {open_name!r}")
            open_name = name
        else:
            if open_name != name:
                raise RegionError(f"{where}:{i + 1}: `generated:{name} end` without its begin marker before it")
            open_name = None
        seen[kind] = i
    if open_name is not None:
        raise RegionError(f"{where}: region {open_name!r} has no `generated:{open_name} end` marker")
    return {name: (m["begin"], m["end"]) for name, m in found.items()}


def regions(text: str, where: str = "<text>") -> list[str]:
    """The names of the regions in `text`, in document order."""
    marks = _markers(text, where)
    return sorted(marks, key=lambda n: marks[n][0])


def fill(text: str, bodies: dict[str, str], where: str = "<text>") -> str:
    """`text` with the content of each region named in `bodies` replaced by its body."""
    marks = _markers(text, where)
    missing = [name for name in bodies if name not in marks]
    if missing:
        raise RegionError(f"{where}: no region marker for {', '.join(repr(n) for n in missing)}; "
                          f"add `<!-- generated:NAME begin -->` and `<!-- generated:NAME end -->` "
                          f"lines (regions present: {', '.join(regions(text, where)) or 'none'})")
    lines = text.splitlines(keepends=True)
    newline = "\r\n" if lines and lines[0].endswith("\r\n") else "\n"
    # Replace from the bottom up so the line numbers of the regions above stay valid.
    for name in sorted(bodies, key=lambda n: -marks[n][0]):
        begin, end = marks[name]
        body = bodies[name].strip("\n")
        new = [ln + newline for ln in body.split("\n")] if body else []
        lines[begin + 1:end] = new
    return "".join(lines)


def fill_file(path: Path, bodies: dict[str, str]) -> bool:
    """Fill the regions of the file at `path`; True if its text changed."""
    path = Path(path)
    try:
        old = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise RegionError(f"{path}: no such file (it is hand-written; the generator only fills "
                          f"its marked regions)") from None
    new = fill(old, bodies, where=str(path))
    if new != old:
        path.write_text(new, encoding="utf-8")
    return new != old


def main() -> None:
    import argparse
    ap = argparse.ArgumentParser(description="List the generated regions of a document.")
    ap.add_argument("file", type=Path)
    args = ap.parse_args()
    try:
        for n in regions(args.file.read_text(encoding="utf-8"), str(args.file)):
            print(n)
    except (OSError, RegionError) as e:
        sys.exit(f"error: {e}")


if __name__ == "__main__":
    main()
