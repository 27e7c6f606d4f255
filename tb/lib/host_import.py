# SPDX-License-Identifier: Apache-2.0
"""The host library `brainstem_dio` (host/, installed editable) for the tests under tb/.

tb/ is on sys.path (its conftest's folder), and tb/brainstem_dio/ (the top's tests) would be
taken for a namespace package of that name: import the library with tb/ out of the way.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path
from types import ModuleType

TB = Path(__file__).resolve().parents[1]


def import_host_library() -> ModuleType:
    mod = sys.modules.get("brainstem_dio")
    if mod is not None and getattr(mod, "__file__", None) is None:
        del sys.modules["brainstem_dio"]
    saved = sys.path[:]
    sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != TB]
    try:
        return importlib.import_module("brainstem_dio")
    finally:
        sys.path[:] = saved
