# SPDX-License-Identifier: Apache-2.0
"""The repository stands alone and is laid out so that a block's RTL, tests and doc are found
from its name: licensed, every source file with its SPDX line, nothing that points outside
the repository, one module per RTL file named after it, a test folder per module."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
# Prose, the license itself, quoted third-party text and an empty marker file carry no line.
NO_SPDX = ("LICENSE", "host/brainstem_dio/py.typed")
NO_SPDX_PREFIX = ("docs/reference/",)
# The two contract tops; every other module is bsd_-prefixed so it cannot collide in a
# user's design.
TOPS = {"brainstem_dio", "brainstem_dio_uart"}


def tracked() -> list[str]:
    out = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True)
    return [f for f in out.stdout.splitlines() if (ROOT / f).is_file()]


def test_license_is_apache() -> None:
    text = (ROOT / "LICENSE").read_text()
    assert "Apache License" in text and "Version 2.0, January 2004" in text


def test_every_source_file_has_its_spdx_line() -> None:
    missing = [
        f for f in tracked()
        if not f.endswith(".md") and f not in NO_SPDX and not f.startswith(NO_SPDX_PREFIX)
        and "SPDX-License-Identifier: Apache-2.0" not in "".join((ROOT / f).open(errors="replace").readlines()[:3])
    ]  # fmt: skip
    assert not missing, f"no SPDX line in the first 3 lines of: {missing}"


def test_nothing_points_outside_the_repository() -> None:
    # The project's working copy sits beside a folder that users' clones do not have; the
    # pattern is assembled so that this file does not match itself.
    outside = r"\.\./" + "shared"
    out = subprocess.run(["git", "grep", "-n", "-e", outside, "--", ":!*.lock"], cwd=ROOT,
                         capture_output=True, text=True)
    assert out.returncode == 1 and not out.stdout, f"tracked files point outside:\n{out.stdout}"


def rtl_modules() -> dict[str, list[str]]:
    found = {}
    for path in sorted((ROOT / "rtl").glob("*.v")):
        text = re.sub(r"//.*", "", path.read_text())
        found[path.stem] = re.findall(r"^\s*module\s+(\w+)", text, flags=re.M)
    return found


def test_one_module_per_rtl_file_named_after_it() -> None:
    bad = {f: mods for f, mods in rtl_modules().items() if mods != [f]}
    assert not bad, f"files whose modules are not exactly the one named after the file: {bad}"


def test_modules_are_prefixed() -> None:
    bad = [m for m in rtl_modules() if m not in TOPS and not m.startswith("bsd_")]
    assert not bad, f"modules without the bsd_ prefix: {bad}"


@pytest.mark.parametrize("module", sorted(set(rtl_modules()) - {"bsd_protocol"}))
def test_every_module_has_its_test_folder(module: str) -> None:
    folder = ROOT / "tb" / module
    tests = sorted(p.name for p in folder.glob("test_*.py"))
    assert tests, f"rtl/{module}.v has no tests in tb/{module}/"
    if module not in TOPS:
        assert f"test_{module}.py" in tests, f"tb/{module}/ has no test_{module}.py"
