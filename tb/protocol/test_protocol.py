# SPDX-License-Identifier: Apache-2.0
"""The protocol table (tools/protocol.toml) against its generated files and the contract.

- The generated files (rtl/bsd_protocol.vh, sim/bsd_protocol.h, ...) are what
  tools/gen_protocol.py makes of the table now (`--check`), and `--check` does fail on a
  stale or missing file.
- The table says what docs/PROTOCOL.md says: every message of §2's table and every command
  of §3's table with the same number and name (and nothing the contract lacks), the command
  forms, the DIGCFG and DEVCODE layouts, the special numbers of the text, the GP 1.0
  parameter defaults of §1, and those defaults are rtl/brainstem_dio.v's.
"""

from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

ROOT = Path(__file__).resolve().parents[2]
GEN = ROOT / "tools" / "gen_protocol.py"
CONTRACT = ROOT / "docs" / "PROTOCOL.md"


def _generator() -> ModuleType:
    spec = importlib.util.spec_from_file_location("gen_protocol", GEN)
    assert spec and spec.loader
    mod = importlib.util.module_from_spec(spec)
    sys.modules["gen_protocol"] = mod  # dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


gen = _generator()
PROTO = gen.load(ROOT / gen.TABLE)


def run_gen(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(GEN), *args], capture_output=True, text=True, timeout=60)


# --- the generated files ------------------------------------------------------------------


def test_generated_files_are_up_to_date() -> None:
    run = run_gen("--check")
    assert run.returncode == 0, run.stderr + "\n(run `make protocol` and commit the generated files)"


def test_generated_files_say_so() -> None:
    for rel, _ in gen.OUTPUTS:
        head = (ROOT / rel).read_text(encoding="utf-8").splitlines()[:2]
        assert "SPDX-License-Identifier: Apache-2.0" in head[0], rel
        assert "tools/gen_protocol.py from tools/protocol.toml" in head[1] and "do not edit" in head[1], rel


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    """A copy of the table, the generator and the generated files."""
    for rel in [gen.TABLE, "tools/gen_protocol.py", *(p for p, _ in gen.OUTPUTS)]:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / rel, tmp_path / rel)
    return tmp_path


def test_check_fails_on_a_stale_file(tree: Path) -> None:
    assert run_gen("--check", "--root", str(tree)).returncode == 0
    vh = tree / "rtl" / "bsd_protocol.vh"
    vh.write_text(vh.read_text().replace("8'd26;", "8'd25;"))  # an edit by hand
    (tree / "host" / "brainstem_dio" / "protocol_table.py").unlink()
    run = run_gen("--check", "--root", str(tree))
    assert run.returncode == 1
    assert "rtl/bsd_protocol.vh (differs" in run.stderr and "host/brainstem_dio/protocol_table.py (missing)" in run.stderr
    assert "sim/bsd_protocol.h" not in run.stderr
    # regenerating repairs both
    assert run_gen("--root", str(tree), "-q").returncode == 0
    assert run_gen("--check", "--root", str(tree)).returncode == 0
    assert vh.read_text() == (ROOT / "rtl" / "bsd_protocol.vh").read_text()


@pytest.mark.parametrize("edit,error", [
    (("code = 27\nname = \"cmdDIG_IO\"", "code = 26\nname = \"cmdDIG_IO\""), "two commands with code 26"),
    (("stored = 0x1F", "stored = 0x3F"), "[digcfg]: stored = 0x3F"),
    (("max_n = 8 ", "max_n = 8\nmax_m = 9 "), "[packet]: unknown key(s) max_m"),
    (("[timer]", "[timer"), "protocol.toml: "),
])
def test_table_errors_are_reported(tree: Path, edit: tuple[str, str], error: str) -> None:
    toml = tree / gen.TABLE
    text = toml.read_text()
    assert edit[0] in text
    toml.write_text(text.replace(edit[0], edit[1], 1))
    run = run_gen("--check", "--root", str(tree))
    assert run.returncode == 2 and error in run.stderr, run.stderr


# --- the table against the contract ---------------------------------------------------------


def contract_sections() -> dict[str, str]:
    text = CONTRACT.read_text(encoding="utf-8")
    parts = re.split(r"^## (\d+)\. ", text, flags=re.M)
    return {num: body for num, body in zip(parts[1::2], parts[2::2])}


SEC = contract_sections()


def find(pattern: str, section: str) -> re.Match[str]:
    m = re.search(pattern, SEC[section])
    assert m, f"docs/PROTOCOL.md §{section} no longer says /{pattern}/: update this test with the contract"
    return m


def number(text: str) -> int:
    """A number as the contract writes it: 48_000_000, 625 000, 0x80, 5'b11110."""
    text = text.replace("_", "").replace(" ", "")
    m = re.fullmatch(r"(?:\d+)?'([bdh])([0-9a-fA-F]+)", text)
    if m:
        return int(m[2], {"b": 2, "d": 10, "h": 16}[m[1]])
    return int(text, 0)


def test_messages_are_the_contracts() -> None:
    rows = re.findall(r"^\| (\d+) \| ([a-zA-Z]+)\b[^|]*\|", SEC["2"], flags=re.M)
    assert len(rows) >= 8, rows
    contract = {int(code): name for code, name in rows}
    table = {m.code: m.name for m in PROTO.messages if m.scope == "core"}
    assert table == contract, "tools/protocol.toml's core messages differ from docs/PROTOCOL.md §2"
    # the serial wrapper's own messages are not the core's, and take no core code
    for m in PROTO.messages:
        if m.scope == "uart":
            assert m.code not in contract and m.name not in contract.values(), m


def test_commands_are_the_contracts() -> None:
    rows = re.findall(r"^\| (0x[0-9A-F]+|\d+)(?: \((0x[0-9A-F]+)\))? \| (cmd\w+) \| ([^|]*)\|", SEC["3"], flags=re.M)
    assert len(rows) >= 8, rows
    contract = {}
    for code, hexcode, name, forms in rows:
        assert not hexcode or number(hexcode) == number(code), f"§3: {code} is not {hexcode}"
        contract[number(code)] = name
        cmd = PROTO.command(name) if name in {c.name for c in PROTO.commands} else None
        assert cmd is not None, f"{name} (§3) is missing from tools/protocol.toml"
        ns = [int(n) for n in re.findall(r"N=(\d+)", forms)]
        if ns:  # the forms column: N=3 set ... · N=2 query ...
            assert (cmd.min_n, cmd.max_n) == (min(ns), max(ns)), name
    assert {c.code: c.name for c in PROTO.commands} == contract
    debug = find(r"cmdDEBUG \| host → core `23, d1 \.\. d\(N-1\)`, any N from (\d+) to (\d+)", "3")
    c = PROTO.command("cmdDEBUG")
    assert (c.min_n, c.max_n) == (int(debug[1]), int(debug[2]))
    for name, sender in (("cmdDEV_VAL", "core"), ("cmdMSG", "core")):
        find(rf"\| {name} \| core → host only", "3")
        assert PROTO.command(name).sender == sender


def test_packet_numbers_are_the_contracts() -> None:
    assert PROTO.max_n == int(find(r"N ≤ (\d+)\.", "2")[1])
    m = find(r"address = (0x[0-9A-F]+) \((\d+)\) and N = 0: the host's resync probe", "2")
    assert PROTO.resync_addr == number(m[1]) == int(m[2])
    m = find(r"Messages \(errors\) are `A, (\d+), (0x[0-9A-F]+), code`", "2")
    assert PROTO.msg_n == int(m[1]) and PROTO.command("cmdMSG").code == number(m[2])


def bits(layout: str) -> dict[str, tuple[int, int]]:
    """`[7] FIXED | [6:5] 0 | [4] TMODE` -> {"FIXED": (7, 7), "0": (6, 5), "TMODE": (4, 4)}."""
    out = {}
    for hi, lo, name in re.findall(r"\[(\d+)(?::(\d+))?\] (\w+)", layout):
        out[name] = (int(hi), int(lo or hi))
    return out


def test_digcfg_and_devcode_are_the_contracts() -> None:
    layout = bits(find(r"\*\*DIGCFG byte\*\*: `([^`]*)`", "3")[1])
    layout.pop("0")
    assert {f: (b, b) for f, b in PROTO.digcfg_bits.items()} == layout
    hi, lo = (int(x) for x in find(r"stores bits (\d+):(\d+)", "3").groups())
    assert PROTO.digcfg_stored == (1 << (hi + 1)) - (1 << lo)
    assert PROTO.digcfg_reset == number(find(r"Every pin: DIGCFG = (0x[0-9A-F]+) \(input", "6")[1])
    layout = bits(find(r"A `DEVCODE` byte is `([^`]*)`", "3")[1])
    assert layout == {"HOST": (PROTO.devcode_bits["HOST"],) * 2, "RFLX": (PROTO.devcode_bits["RFLX"],) * 2,
                      "pin": PROTO.devcode_pin}


def test_heartbeat_and_time_are_the_contracts() -> None:
    m = find(r"sends `A, 2, 0, (\d+)` and `A, 2, 0, (\d+)`\s+alternately, one every HB_RATE × ([\d.]+) ms", "3")
    assert (PROTO.hb_up, PROTO.hb_down) == (int(m[1]), int(m[2]))
    assert PROTO.hb_unit_ticks * 1000 / PROTO.tick_hz == pytest.approx(float(m[3]), abs=1e-12)
    m = find(r"answers each\s+with `A, 2, 0, (\d+)` / `A, 2, 0, (\d+)`", "3")
    assert (int(m[1]), int(m[2])) == (PROTO.hb_up + PROTO.hb_answer_offset, PROTO.hb_down + PROTO.hb_answer_offset)
    assert PROTO.tick_hz == number(find(r"([\d ]+) ticks per second", "4")[1])
    assert PROTO.timer_max_ticks == number(find(r"Timeout: ([\d ]+) ticks", "4")[1])
    assert PROTO.dev_id_limit == int(find(r"every device ID below (\d+)", "1")[1])


def test_defaults_are_the_contracts_and_the_rtls() -> None:
    rows = re.findall(r"^\| `([A-Z_]+)` \| ([^|]+?) \|", SEC["1"], flags=re.M)
    contract = {name: number(value) for name, value in rows if name.isupper() and name in gen.PARAMETERS}
    assert set(contract) == set(gen.PARAMETERS), "§1's parameter table changed"
    assert PROTO.defaults == contract
    rtl = (ROOT / "rtl" / "brainstem_dio.v").read_text(encoding="utf-8")
    header = rtl[rtl.index("module brainstem_dio"):rtl.index(") (")]
    found = {name: number(value) for name, value in re.findall(r"parameter\b[^=\n]*?\b([A-Z_]+)\s*=\s*([^,\n]+?)\s*(?:,|\n|$)", header)}
    assert {k: found.get(k) for k in gen.PARAMETERS} == PROTO.defaults, "rtl/brainstem_dio.v's defaults"
