# SPDX-License-Identifier: Apache-2.0
"""synth/depth.py's estimate on a netlist small enough to work out by hand: two flops, a LUT
between them packed with the second (it drives nothing else), a second LUT on the first's
enable."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import depth


def lut(i0: int | str, i3: int | str, o: int) -> dict:
    return {"type": "SB_LUT4", "connections": {"I0": [i0], "I1": ["0"], "I2": ["0"], "I3": [i3], "O": [o]},
            "port_directions": {"I0": "input", "I1": "input", "I2": "input", "I3": "input", "O": "output"}}


def ff(d: int | str, q: int, e: int | None = None) -> dict:
    conn = {"C": [1], "D": [d], "Q": [q]} | ({"E": [e]} if e else {})
    return {"type": "SB_DFFE" if e else "SB_DFF", "connections": conn,
            "port_directions": {k: "output" if k == "Q" else "input" for k in conn}}


def netlist(tmp_path: Path, cells: dict) -> Path:
    """The cells as a yosys JSON netlist of one top module."""
    net = tmp_path / "top.json"
    net.write_text(json.dumps({"modules": {"t": {"attributes": {"top": 1}, "cells": cells, "netnames": {}}}}))
    return net


def test_depth(tmp_path: Path, capsys) -> None:
    # a: Q 10, its D 11 from LUT x (I0 = a.Q), enable 12 from LUT y (I3 = b.Q); b: D 13 from LUT z
    cells = {"a": ff(11, 10, 12), "b": ff(13, 14), "x": lut(10, "0", 11), "y": lut("0", 14, 12),
             "z": lut(10, 14, 13), "w": lut(11, "0", 15)}
    net = netlist(tmp_path, cells)
    eps = {(n, p): (t, lv) for t, lv, n, p, _ in depth.Netlist(net).endpoints()}
    # a.D: x also drives w, so it is not packed: a route and a pass-through LUT before the flop
    assert eps[("a", "D")] == (depth.CLKQ + depth.ROUTE + depth.LUTD["I0"] + depth.ROUTE + depth.LUTD["I0"]
                               + depth.SETUP, 1)
    assert eps[("a", "E")] == (depth.CLKQ + depth.ROUTE + depth.LUTD["I3"] + depth.CEROUTE + depth.SETUP, 1)
    # b.D: z packed with b; its later input is I0 (a.Q and b.Q both arrive at clock-to-Q)
    assert eps[("b", "D")] == (depth.CLKQ + depth.ROUTE + depth.LUTD["I0"] + depth.SETUP, 1)
    assert depth.main([str(net), "--over", "0"]) == 0
    assert "over 0 ns: 3" in capsys.readouterr().out
    # --lone: a's D LUT also drives w, so a takes a logic cell of its own; b shares z's
    assert depth.main([str(net), "--lone"]) == 0
    assert capsys.readouterr().out.splitlines() == ["2 flops, 1 in a logic cell of their own:", "     1  a"]


def test_depth_bad_netlist(tmp_path: Path, capsys) -> None:
    bad = tmp_path / "top.json"
    bad.write_text("not json")
    other = tmp_path / "list.json"
    other.write_text("[]")
    for path in (bad, other, tmp_path / "missing.json"):
        with pytest.raises(SystemExit) as e:
            depth.main([str(path), "--lone"])
        assert e.value.code == 2
        assert "not a yosys JSON netlist" in capsys.readouterr().err


def test_lone_kinds(tmp_path: Path, capsys) -> None:
    # c: D constant; d and e: one LUT's output; f: D from a RAM; g: D from its own LUT
    ram = {"type": "SB_RAM40_4K", "connections": {"RDATA": [20]}, "port_directions": {"RDATA": "output"}}
    cells = {"c": ff("0", 21), "d": ff(22, 23), "e": ff(22, 24), "x": lut(23, "0", 22), "ram": ram,
             "f": ff(20, 25), "g": ff(26, 27), "y": lut(25, "0", 26)}
    net = netlist(tmp_path, cells)
    assert depth.main([str(net), "--lone"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "5 flops, 4 in a logic cell of their own:"
    assert sorted(line.split()[1] for line in out[1:]) == ["c", "d", "e", "f"]
