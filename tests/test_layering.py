"""Every package imports only the layers below it (STYLE.md: dependencies point down).

The table is the layout of STYLE.md; the root modules (``errors``, ``constants``, ``_validate``,
``_jit_cache``, ``_files``) and the executor layer ``parallel`` sit below ``geometry`` and import
no package of hapticsim; ``suites`` runs experiments and sits on top. Lazy imports inside
functions count too: an upward import anywhere makes a circle.
"""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PACKAGE = REPO / "hapticsim"
ROOT = {"errors", "constants", "_validate", "_files", "_jit_cache", "_version", "parallel"}
#: Package -> the hapticsim packages it may import (besides the root modules).
ALLOWED: dict[str, set[str]] = {
    "geometry": set(),
    "data": {"geometry"},
    "metrics": {"geometry"},
    "fitting": {"geometry"},
    # the vision estimate and the tactile skin: no simulator
    "perception": {"geometry"},
    "sim": {"geometry", "data", "perception"},
    "envs": {"geometry", "data", "metrics", "fitting", "perception", "sim"},
    # one trial: explore (a strategy, or a policy in the environment) -> estimate -> score
    "exploration": {"geometry", "data", "metrics", "fitting", "perception", "sim", "envs"},
    "experiments": {"geometry", "data", "metrics", "fitting", "perception", "sim", "envs"},
    # the benchmark protocol: runs policies in the environment, reads plug-ins as suites do
    "bench": {"geometry", "data", "metrics", "fitting", "perception", "sim", "envs", "suites"},
    "suites": {
        "geometry", "data", "metrics", "fitting", "perception", "sim", "envs", "exploration",
        "experiments",
    },
    # reads run directories (plain files): no simulator, no environments
    "viewer": {"geometry", "data", "metrics", "fitting"},
}


#: Packages below ``sim`` that must never import the simulator or the environment API.
CORE = ("geometry", "data", "metrics", "fitting", "perception")
CORE_FORBIDDEN = {"mujoco", "gymnasium"}


def _imports(path: Path) -> set[str]:
    """Absolute module names imported anywhere in `path`."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module == "hapticsim" and node.level == 0:
            names |= {f"hapticsim.{alias.name}" for alias in node.names}  # its submodules
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
    return names


def _hapticsim_imports(path: Path) -> set[str]:
    """Top-level hapticsim modules/packages imported anywhere in `path`."""
    return {m.split(".")[1] for m in _imports(path) if m.startswith("hapticsim.")}


@pytest.mark.parametrize("package", sorted(ALLOWED))
def test_package_imports_only_layers_below(package: str) -> None:
    paths = sorted((PACKAGE / package).rglob("*.py"))
    assert paths, f"no sources found for hapticsim.{package}"  # else the loop checks nothing
    allowed = ALLOWED[package] | ROOT | {package}
    for path in paths:
        bad = _hapticsim_imports(path) - allowed
        assert not bad, f"{path.relative_to(REPO)} imports hapticsim.{sorted(bad)}"


@pytest.mark.parametrize("module", sorted(ROOT))
def test_root_modules_import_no_package(module: str) -> None:
    single = PACKAGE / f"{module}.py"
    paths = [single] if single.is_file() else sorted((PACKAGE / module).rglob("*.py"))
    assert paths, f"no sources found for hapticsim.{module}"
    for path in paths:
        bad = _hapticsim_imports(path) - ROOT
        assert not bad, f"{path.relative_to(REPO)} imports hapticsim.{sorted(bad)}"


def test_every_package_is_in_the_table() -> None:
    packages = {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").is_file()}
    known = set(ALLOWED) | ROOT
    assert packages <= known, f"add {sorted(packages - known)} to ALLOWED"


@pytest.mark.parametrize("package", CORE)
def test_core_never_imports_the_simulator(package: str) -> None:
    for path in sorted((PACKAGE / package).rglob("*.py")):
        bad = {n for n in _imports(path) if n.split(".")[0] in CORE_FORBIDDEN}
        assert not bad, f"{path.relative_to(REPO)} imports {sorted(bad)}"


@pytest.mark.parametrize("package", CORE)
def test_importing_the_core_does_not_load_mujoco(package: str) -> None:
    code = f"import sys, hapticsim.{package}; sys.exit(1 if 'mujoco' in sys.modules else 0)"
    env = os.environ | {"PYTHONPATH": str(REPO)}
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120
    )
    assert proc.returncode == 0, f"hapticsim.{package} loads mujoco: {proc.stderr[-500:]}"


@pytest.mark.parametrize("package", sorted(ALLOWED) + ["parallel"])
def test_no_package_imports_the_package_root(package: str) -> None:
    # The root (hapticsim/__init__) registers the environments and re-exports the top names:
    # a layer that imports it depends on everything above it.
    for path in sorted((PACKAGE / package).rglob("*.py")):
        assert "hapticsim" not in _imports(path), f"{path.relative_to(REPO)} imports hapticsim"



#: What the installed package never imports: the lab beside it, and the training stacks it
#: serves (they are extras the lab's training glue needs).
LAB_ONLY = {"lab", "stable_baselines3", "sb3_contrib", "ray", "torch"}


def test_the_installed_package_never_imports_the_lab_or_training_stacks() -> None:
    paths = sorted(PACKAGE.rglob("*.py"))
    assert paths
    for path in paths:
        bad = {n for n in _imports(path) if n.split(".")[0] in LAB_ONLY}
        assert not bad, f"{path.relative_to(REPO)} imports {sorted(bad)}"
