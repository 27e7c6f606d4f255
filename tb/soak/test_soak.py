# SPDX-License-Identifier: Apache-2.0
"""The noise soak (sim/soak.py, `make soak`) in short: the host library against the virtual
module at BER 1e-3, a few hundred seeded random calls, then the functional check with the
noise off. It asserts the soak's pass criteria (no call past its bound, no exception outside
BrainStemError, the reader thread alive, the link answering within 2 s after the noise, every
check after it passing); wrong values under noise are counted, not asserted.

Also, without a simulator, that the soak's bookkeeping notices what the criteria are about:
a foreign exception, a call past its bound, a wrong value, a failed check, and that a check
failing while the module stalled runs once more.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import time
from pathlib import Path

import pytest

from host_import import import_host_library

ROOT = Path(__file__).resolve().parents[2]
SEED = 16016  # fixed: a failure repeats (as far as the wall clock lets it); printed below

# One worker runs this file, tb/virtual and tb/host_virtual (the same virtual module binary):
# it builds once there, and no two virtual modules keep real time on the same cores at once.
pytestmark = pytest.mark.xdist_group("virtual")

brainstem_dio = import_host_library()
_spec = importlib.util.spec_from_file_location("bsd_soak", ROOT / "sim" / "soak.py")
soak = importlib.util.module_from_spec(_spec)
sys.modules["bsd_soak"] = soak
_spec.loader.exec_module(soak)


def test_soak_at_ber_1e3_passes() -> None:
    log: list[str] = []
    res = soak.run_soak(seed=SEED, baseline=30, calls=300, bers=[1e-3], log=log.append)
    text = soak.report(res)
    print("\n".join(log), text, sep="\n")  # shown with -rA or on failure
    quiet, noisy = res.phases
    assert quiet.calls >= 30 and noisy.calls >= 300, text
    # The quiet baseline is clean: every call as the shadow predicts (unless the machine stalled
    # the simulation: a packet stopping for 0.1 s is a lost byte to the library).
    if res.behind:
        assert quiet.outcomes[soak.WRONG] == 0 and not quiet.failures, f"seed {SEED}\n{text}"
    else:
        assert quiet.outcomes == {soak.OK: quiet.calls}, f"seed {SEED}\n{text}"
    # The noise was there (300 calls carry some 20 000 bits each way: about 20 flips each).
    assert noisy.flips[0] > 0 and noisy.flips[2] > 0, f"seed {SEED}\n{text}"
    assert len(res.checks) == 6 and res.failures == [], f"seed {SEED}\n{text}"  # the link + 5 checks


# ---------------------------------------------------------------- the bookkeeping

def test_a_phase_counts_each_kind_of_outcome() -> None:
    ph = soak.Phase("p")
    call = ph.call
    call("echo", lambda: b"x", lambda r: None)
    call("echo", lambda: b"y", lambda r: "echo y, not x")
    call("read", lambda: (_ for _ in ()).throw(brainstem_dio.CmdIndexErr(10)), lambda r: None,
         expect=brainstem_dio.CmdIndexErr)
    call("read", lambda: 1, lambda r: None, expect=brainstem_dio.CmdIndexErr)  # no error where one was due
    call("read", lambda: (_ for _ in ()).throw(brainstem_dio.CmdIndexErr(10)), lambda r: None)
    call("query", lambda: (_ for _ in ()).throw(brainstem_dio.Timeout("t")), lambda r: None)
    call("query", lambda: (_ for _ in ()).throw(KeyError("k")), lambda r: None)
    call("write", lambda: time.sleep(0.3), lambda r: None, timeout=0.01)  # bound: 0.01 + 0.5 + 0.5 s
    assert ph.outcomes == {soak.OK: 3, soak.WRONG: 2, "CmdIndexErr (10)": 1, "Timeout": 1,
                           "foreign KeyError": 1}
    assert ph.wrong == ["echo: echo y, not x", "read: no CmdIndexErr"]
    # 0.3 s is within the write's bound: the foreign exception is the one failure.
    assert ph.failures == ["an exception outside BrainStemError: query: KeyError: 'k'"]
    assert ph.slowest[2] == "write" and ph.slowest[0] > 20


def test_failures_name_what_failed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(soak, "GRACE_S", 0.0)
    monkeypatch.setattr(soak, "CALL_TIMEOUT", 0.0)
    ph = soak.Phase("BER 0.001")
    ph.call("write", lambda: time.sleep(0.05), lambda r: None, timeout=0.01)  # past its bound
    ph.call("query", lambda: (_ for _ in ()).throw(ValueError("v")), lambda r: None)
    ph.call("echo", lambda: b"?", lambda r: "wrong")  # counted, not a failure
    clean = soak.Phase("quiet")
    assert soak.Result([clean], [("a check", None)], [], []).failures == []
    failures = soak.Result([clean, ph], [("a check", None), ("the timers", "pin 3: Timeout")], [], []).failures
    assert [f.split(":")[0] for f in failures] == ["BER 0.001", "BER 0.001", "check failed"]
    assert "a call past its bound: write" in failures[0]
    assert "an exception outside BrainStemError: query: ValueError" in failures[1]
    assert failures[2] == "check failed: the timers: pin 3: Timeout"


class _Err:
    def __init__(self) -> None:
        self.lines: list[str] = []

    def __len__(self) -> int:
        return len(self.lines)

    def find(self, pattern: str, start: int = 0) -> list[str]:
        import re
        return [line for line in self.lines[start:] if re.search(pattern, line)]


class _Stub:
    """What Checks.check touches: the framing errors seen, the module's stderr, link counters."""

    def __init__(self) -> None:
        self.framing: list[str] = []
        self.v = type("V", (), {"err": _Err()})()
        stats = type("S", (), {"framing_errors": 0, "unsolicited": 0})()
        self.m = type("M", (), {"link": type("L", (), {"stats": stats})(), "drain": lambda self: []})()


@pytest.mark.parametrize("timeout_framing, stalled, retried", [
    (True, True, True),     # a partial packet dropped while the module stalled: run again
    (False, True, False),   # a failure without it stands (a lost timer start, say)
    (True, False, False),   # and so does one while the module kept real time
])
def test_a_check_runs_again_only_after_a_stall_cost_a_packet(timeout_framing: bool, stalled: bool,
                                                             retried: bool) -> None:
    stub = _Stub()
    checks = soak.Checks(stub)
    calls = []

    def flaky() -> str | None:
        calls.append(1)
        if len(calls) == 1:
            if timeout_framing:
                stub.framing.append("1.000: timeout (02 04)")
            if stalled:
                stub.v.err.lines.append("behind real time: x0.90, stalled 0.150 s")
            return "ResyncError: lost"
        return None

    checks.check("c", flaky)
    assert len(calls) == (2 if retried else 1)
    assert checks.results == [("c", None if retried else "ResyncError: lost")]
    assert len(checks.retried) == (1 if retried else 0)
