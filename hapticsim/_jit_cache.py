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
import sys
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent
#: The modules with ``cache=True`` functions, relative to the package.
COMPILED: tuple[str, ...] = (
    "geometry/_eof_compiled.py",
    "geometry/_rays_compiled.py",
    "fitting/_lm_compiled.py",
    "fitting/_ga_compiled.py",
    "geometry/_sampling_compiled.py",
)
_STAMP = "hapticsim-jit-sources.sha256"
_checked = False


def fingerprint() -> str:
    """SHA-256 of the compiled modules' sources (missing files count as empty)."""
    digest = hashlib.sha256()
    for name in COMPILED:
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
        for name in COMPILED:
            module = _PACKAGE / name
            for cached in (module.parent / "__pycache__").glob(f"{module.stem}.*.nb[ic]"):
                cached.unlink(missing_ok=True)
        stamp.parent.mkdir(exist_ok=True)
        stamp.write_text(current + "\n")
    except OSError:
        pass


def is_cold() -> bool:
    """True when the compiled kernels will be compiled on first use here: no cached index of the
    EOF kernel beside its source, in a package directory numba can write to (and no
    ``NUMBA_CACHE_DIR`` sending the cache elsewhere, where this cannot tell)."""
    pycache = _PACKAGE / "geometry" / "__pycache__"
    if os.environ.get("NUMBA_CACHE_DIR") or not os.access(pycache.parent, os.W_OK):
        return False
    return not any(pycache.glob("_eof_compiled.*.nbi"))


#: Shown on a terminal before the first compile of a fresh installation.
COLD_NOTE = (
    "hapticsim: compiling the fitter's kernels on first use (about 30-90 s on 2 cores; "
    "cached for later runs)"
)


def note_if_cold(stream=None) -> bool:  # noqa: ANN001 - a text stream
    """Print :data:`COLD_NOTE` on `stream` (default stderr) when it is a terminal and the cache
    is cold; returns whether it printed. Pipes and files (scripts, tests) get nothing."""
    stream = sys.stderr if stream is None else stream
    try:
        if not stream.isatty() or not is_cold():
            return False
        stream.write(COLD_NOTE + "\n")
        stream.flush()
    except (OSError, ValueError):
        return False
    return True
