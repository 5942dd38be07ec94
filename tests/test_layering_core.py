"""The core (geometry, data, metrics) stays free of the simulator (STYLE: layers point down)."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
CORE = ("geometry", "data", "metrics")
FORBIDDEN = {"mujoco", "gymnasium", "hapticsim.sim", "hapticsim.envs", "hapticsim.fitting"}


def _imports(path: Path) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
    return names


@pytest.mark.parametrize("package", CORE)
def test_core_sources_import_nothing_above_them(package: str) -> None:
    paths = sorted((REPO / "hapticsim" / package).glob("*.py"))
    assert paths, f"no sources found for hapticsim.{package}"  # else the loop checks nothing
    for path in paths:
        bad = {n for n in _imports(path) if any(n == f or n.startswith(f + ".") for f in FORBIDDEN)}
        assert not bad, f"{path.relative_to(REPO)} imports {sorted(bad)}"


def test_importing_the_core_does_not_load_mujoco() -> None:
    code = (
        "import sys, hapticsim.geometry, hapticsim.data, hapticsim.metrics;"
        "print('mujoco' in sys.modules)"
    )
    env = os.environ | {"PYTHONPATH": str(REPO)}
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "False"
