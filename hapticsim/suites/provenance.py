"""What produced a results file: versions, git commit, machine, engine, seeds, command."""

from __future__ import annotations

import datetime
import hashlib
import os
import platform
import subprocess
from importlib import metadata
from pathlib import Path
from typing import Any

from hapticsim._version import __version__

#: Distributions whose versions are recorded (those that can change a number).
PACKAGES: tuple[str, ...] = (
    "numpy", "scipy", "mujoco", "gymnasium", "trimesh", "manifold3d", "numba", "llvmlite",
    "threadpoolctl", "distributed", "dask",
)  # fmt: skip
#: What of the checkout can change a number: ``dirty`` means uncommitted changes here. Results
#: and docs do not count, so that regenerating committed baselines one after another does not
#: mark the later ones dirty.
CODE_PATHS: tuple[str, ...] = ("hapticsim", "models", "pyproject.toml")
#: How a case's seeds derive from the suite's root seed.
SEED_SCHEME: str = (
    "numpy SeedSequence(root, spawn_key=SHA-256 of the canonical JSON of the case's parameters "
    "as 4 x 32-bit words); data seed: the data parameters only, case seed: all parameters"
)


def package_versions() -> dict[str, str | None]:
    """Installed versions of :data:`PACKAGES` (None where not installed)."""
    out: dict[str, str | None] = {}
    for name in PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = None
    return out


def git_state() -> dict[str, Any] | None:
    """``{"commit", "dirty"}`` of the git checkout hapticsim is imported from, or None.

    ``dirty``: uncommitted changes to tracked files of :data:`CODE_PATHS` (the package, the
    MJCF models, the project file).

    None when hapticsim is not run from a checkout of its own repository (an installed wheel),
    or git is missing. A checkout of some other project that happens to contain the
    installation does not count.
    """
    package = Path(__file__).resolve().parents[1]  # the hapticsim package

    def git(*args: str) -> str | None:
        try:
            proc = subprocess.run(
                ["git", "-C", str(package), *args], capture_output=True, text=True, timeout=10
            )
        except (OSError, subprocess.SubprocessError):
            return None
        return proc.stdout.strip() if proc.returncode == 0 else None

    top = git("rev-parse", "--show-toplevel")
    if not top or Path(top).resolve() / "hapticsim" != package:
        return None
    commit = git("rev-parse", "HEAD")
    status = git(
        "status", "--porcelain", "--untracked-files=no", "--", *(f":/{p}" for p in CODE_PATHS)
    )
    return {"commit": commit, "dirty": bool(status)}


def machine() -> dict[str, Any]:
    """System, CPU model, core count, Python and code-generation targets of this machine."""
    cpu = platform.processor() or None
    fields: dict[str, str] = {}
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            key, _, value = line.partition(":")
            key = key.strip()
            if key in ("model name", "vendor_id", "cpu family", "model") and key not in fields:
                fields[key] = value.strip()
            if not line.strip():  # the first processor is enough
                break
    except OSError:
        pass
    cpu = fields.get("model name", cpu)
    # "AMD EPYC" names several generations: vendor, family and model tell them apart
    cpu_id = (
        f"{fields['vendor_id']} family {fields['cpu family']} model {fields['model']}"
        if {"vendor_id", "cpu family", "model"} <= fields.keys()
        else None
    )
    return {
        "system": f"{platform.system()} {platform.release()}",
        "architecture": platform.machine(),
        "cpu": cpu,
        "cpu_id": cpu_id,
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "codegen": codegen_target(),
    }


def codegen_target() -> dict[str, Any]:
    """The code-generation targets that decide a result's last digits on this machine.

    ``numba_cpu`` and ``numba_features`` (a SHA-256 prefix of the feature string): what numba
    compiles the kernels for (the host, or ``NUMBA_CPU_NAME`` / ``NUMBA_CPU_FEATURES``);
    ``numpy_simd``: the best of numpy's dispatched SIMD targets this CPU runs (its exp, log,
    sin, ... differ in the last bit between targets); ``blas``: the BLAS library and its kernel
    for this CPU (the order of a matrix product's sums). Two runs with the same code, packages
    and targets give the same bytes; across targets, results may differ in the last digits.
    """

    out: dict[str, Any] = {"numba_cpu": None, "numba_features": None, "numpy_simd": None,
                           "blas": None}  # fmt: skip
    try:
        from numba.core.registry import cpu_target

        _, name, features = cpu_target.target_context.codegen().magic_tuple()
        out["numba_cpu"] = name
        out["numba_features"] = hashlib.sha256(features.encode()).hexdigest()[:12]
    except Exception:  # noqa: BLE001 - provenance never fails a run
        pass
    try:
        from numpy._core import _multiarray_umath as umath

        found = umath.__cpu_features__
        usable = [t for t in umath.__cpu_dispatch__ if found.get(t)]
        out["numpy_simd"] = usable[-1] if usable else umath.__cpu_baseline__[-1]
    except Exception:  # noqa: BLE001
        pass
    try:
        from threadpoolctl import threadpool_info

        blas = [i for i in threadpool_info() if i.get("user_api") == "blas"]
        if blas:
            out["blas"] = f"{blas[0].get('internal_api')} {blas[0].get('architecture')}"
    except Exception:  # noqa: BLE001
        pass
    return out


def load_average() -> list[float] | None:
    """1, 5 and 15 minute load averages (None where the system has none)."""
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except OSError:
        return None


def provenance(
    engine: dict[str, Any], seed: int, command: list[str] | None, started: datetime.datetime
) -> dict[str, Any]:
    """The provenance record of a suite run.

    Args:
        engine: the executor's description (:meth:`hapticsim.parallel.Executor.describe`).
        seed: the suite's root seed.
        command: the command line, if run from one.
        started: when the run started (UTC).
    """

    return {
        "hapticsim": __version__,
        "git": git_state(),
        "packages": package_versions(),
        "machine": machine(),
        "engine": engine,
        "seeds": {"root": seed, "scheme": SEED_SCHEME},
        "command": command,
        "started": started.isoformat(timespec="seconds"),
    }


def manifest(command: list[str] | None = None) -> dict[str, Any]:
    """A SPEC §14 manifest of this process: the command, the commit, the date (UTC), the
    machine (CPU model, cores, code-generation targets) and the versions of the packages that
    shape the numbers (with torch where it is installed)."""
    packages = package_versions()
    try:
        packages["torch"] = metadata.version("torch")
    except metadata.PackageNotFoundError:
        pass
    git = git_state()
    return {
        "command": command,
        "hapticsim": __version__,
        "commit": None if git is None else git["commit"],
        "git": git,
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "machine": machine(),
        "packages": packages,
    }
