# SPDX-License-Identifier: Apache-2.0
"""The host library as a user gets it: a wheel built from host/, installed into a fresh venv
outside the repository, whose `brainstem-dio` command talks to a fake module (about 15 s)."""

from __future__ import annotations

import os
import random
import re
import shutil
import subprocess
import sys
import venv
from pathlib import Path

from host_fake import FakeServer

ROOT = Path(__file__).resolve().parents[2]


def pinned(name: str) -> str:
    """`name==version` as requirements.txt pins it."""
    for line in (ROOT / "requirements.txt").read_text().splitlines():
        if line.split("==")[0].strip().lower() == name:
            return line.strip()
    raise AssertionError(f"requirements.txt does not pin {name}")


def run(argv: list[str], cwd: Path, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    proc = subprocess.run(argv, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout, check=False)
    assert proc.returncode == 0, f"{' '.join(argv)} exited {proc.returncode}:\n{proc.stdout}\n{proc.stderr}"
    return proc


def test_wheel_installs_and_its_cli_runs(tmp_path: Path) -> None:
    # Build from a copy of the package's files: nothing of the repository is on the path later.
    src = tmp_path / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / "host" / name, src / name)
    shutil.copytree(ROOT / "host" / "brainstem_dio", src / "brainstem_dio",
                    ignore=shutil.ignore_patterns("__pycache__"))
    dist = tmp_path / "dist"
    # No isolation: the build backend is the pinned setuptools of the project's venv (offline).
    run([sys.executable, "-m", "build", "--wheel", "--no-isolation", "--outdir", str(dist), str(src)], tmp_path)
    wheels = list(dist.glob("brainstem_dio-*.whl"))
    assert len(wheels) == 1, wheels
    # The library's one dependency, as pinned (pip's cache, else the index).
    run([sys.executable, "-m", "pip", "download", "-q", "--no-deps", "--only-binary=:all:", "-d", str(dist),
         pinned("pyserial")], tmp_path)

    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=True)
    bin_dir = env_dir / "bin"
    run([str(bin_dir / "python"), "-m", "pip", "install", "-q", "--no-index", "--find-links", str(dist),
         str(wheels[0])], tmp_path)
    where = run([str(bin_dir / "python"), "-c", "import brainstem_dio; print(brainstem_dio.__file__)"], tmp_path)
    assert Path(where.stdout.strip()).is_relative_to(env_dir), where.stdout

    cli = str(bin_dir / "brainstem-dio")
    assert "Talk to a BrainStem 1.0 digital I/O module" in run([cli, "--help"], tmp_path).stdout

    # One real command against a fake module behind socket://: every pin is an input after
    # power-up, so `read` prints each pin's level.
    seed = random.randrange(1 << 30)
    print(f"levels seed {seed}")
    levels = random.Random(seed).randrange(1, 31)  # pins 0..4, not all the same
    server = FakeServer(levels=levels)
    try:
        for pin in range(5):
            out = run([cli, "read", server.url, str(pin)], tmp_path, timeout=30).stdout
            assert re.fullmatch(rf"{levels >> pin & 1}\s*", out), (pin, out)
    finally:
        server.close()
