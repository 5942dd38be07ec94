"""Keep numba's on-disk cache of hapticsim's compiled kernels consistent with their sources.

numba (``cache=True``) checks a cached function against the modification time of *its own*
source file only. hapticsim's compiled modules inline each other's functions (the EOF kernel into
least squares, the genetic algorithm and the metrics), so after an edit of one of them the others'
cached machine code would silently keep the old version. This module keeps one fingerprint of all
the compiled modules' sources beside their caches; when it changes, every cached file of those
modules is deleted before anything is loaded, and numba compiles afresh.

A fresh installation has no cache, so this only matters in a working tree (or an installation
whose sources were edited in place). Where the package directory cannot be written, numba keeps
its cache elsewhere (``NUMBA_CACHE_DIR``) and this check does nothing.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent
#: The modules with ``cache=True`` functions, relative to the package.
COMPILED: tuple[str, ...] = (
    "geometry/eof_compiled.py",
    "geometry/_rays_compiled.py",
    "fitting/_lm_compiled.py",
    "fitting/_ga_compiled.py",
    "fitting/_ml_compiled.py",
    "fitting/_problem_compiled.py",
    "geometry/_sampling_compiled.py",
)
#: Modules whose constants the kernels fold into their machine code (the parameter layout,
#: tolerances): a change there makes the cached code stale too.
FOLDED: tuple[str, ...] = ("geometry/layout.py", "constants.py")
_STAMP = "hapticsim-jit-sources.sha256"
_checked = False


def fingerprint() -> str:
    """SHA-256 of the compiled modules' sources and of the modules whose constants they fold
    in (missing files count as empty)."""
    digest = hashlib.sha256()
    for name in COMPILED + FOLDED:
        path = _PACKAGE / name
        digest.update(name.encode())
        digest.update(path.read_bytes() if path.is_file() else b"")
    return digest.hexdigest()


def ensure_fresh() -> None:
    """Delete the compiled modules' numba cache files if their sources changed (once per
    process; errors, e.g. a read-only directory, are ignored: numba then caches elsewhere)."""
    global _checked
    if _checked:
        return
    _checked = True
    try:
        stamp = _PACKAGE / "__pycache__" / _STAMP
        current = fingerprint()
        if stamp.is_file() and stamp.read_text().strip() == current:
            return
        # Every numba cache file beside the compiled modules, also those of a module renamed or
        # removed since (whose stale files nothing else would delete).
        for folder in sorted({(_PACKAGE / name).parent for name in COMPILED}):
            for cached in (folder / "__pycache__").glob("*.nb[ic]"):
                cached.unlink(missing_ok=True)
        for old in marker_dir().glob("hapticsim-ready-*"):
            old.unlink(missing_ok=True)
        stamp.parent.mkdir(exist_ok=True)
        stamp.write_text(current + "\n")
    except OSError:
        pass


def marker_dir() -> Path:
    """Where numba keeps the compiled modules' cache: ``NUMBA_CACHE_DIR`` or the package's own
    ``__pycache__`` (where :func:`ensure_fresh` keeps its stamp)."""
    custom = os.environ.get("NUMBA_CACHE_DIR")
    return Path(custom) if custom else _PACKAGE / "__pycache__"


def _marker(name: str, tag: str) -> Path:
    return marker_dir() / f"hapticsim-ready-{name}-{fingerprint()[:16]}-{tag}"


def is_marked(name: str, tag: str) -> bool:
    """Whether :func:`mark` recorded `name` as compiled into the cache for these sources and
    the code-generation target `tag`."""
    return _marker(name, tag).is_file()


def mark(name: str, tag: str) -> None:
    """Record that `name`'s kernels are in the cache (errors, e.g. read-only, are ignored)."""
    try:
        path = _marker(name, tag)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.touch()
    except OSError:
        pass
