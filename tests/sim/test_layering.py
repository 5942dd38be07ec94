"""Dependencies point down: nothing below ``sim`` imports mujoco (STYLE layout)."""

from __future__ import annotations

import subprocess
import sys

import pytest


@pytest.mark.parametrize(
    "module", ["hapticsim.fitting", "hapticsim.geometry", "hapticsim.data", "hapticsim.metrics"]
)
def test_module_does_not_import_mujoco(module: str) -> None:
    code = f"import sys, {module}; sys.exit(1 if 'mujoco' in sys.modules else 0)"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, f"{module} imports mujoco: {proc.stderr[-500:]}"
