"""Files written atomically and JSON read with one-line errors (below every package).

Every file hapticsim writes goes to a temporary sibling first and is renamed into place, so a
failure (or Ctrl-C) never leaves a half-written file; unreadable, non-UTF-8 or malformed input
raises :class:`~hapticsim.errors.InvalidInputError` naming the file. ``geometry`` (superquadric
JSON) and ``data`` (contact files) both build on this module, which imports nothing of hapticsim
but its errors.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hapticsim.errors import InvalidInputError


def atomic_write(path: str | Path, write: Callable[[Any], None], mode: str) -> Path:
    """Call ``write(file)`` on a temporary sibling of `path` opened in `mode`, then rename it.

    A failure leaves no file (and no temporary) behind; errors become InvalidInputError.
    """
    path = check_output_path(path)
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as exc:
        raise InvalidInputError(f"cannot write {path}: {exc.strerror or exc}") from exc
    try:
        with os.fdopen(fd, mode) as fh:
            write(fh)
        os.replace(tmp, path)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise InvalidInputError(f"cannot write {path}: {exc.strerror or exc}") from exc
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def read_text(path: Path) -> str:
    """The text of a file; unreadable or non-UTF-8 files raise InvalidInputError."""
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise InvalidInputError(f"{path} is not a UTF-8 text file ({exc.reason})") from exc
    except OSError as exc:
        raise InvalidInputError(f"cannot read {path}: {exc.strerror or exc}") from exc


def check_output_path(path: str | Path, suffixes: tuple[str, ...] | None = None) -> Path:
    """Check, before any work is done, that `path` can be written: its directory exists, it is
    not a directory, and it ends in one of `suffixes` (any suffix when None).

    Raises:
        InvalidInputError: naming the path and the problem.
    """
    path = Path(path)
    if suffixes is not None and path.suffix.lower() not in suffixes:
        raise InvalidInputError(f"output file must end in one of {suffixes}, got {path.name!r}")
    if path.is_dir():
        raise InvalidInputError(f"cannot write {path}: it is a directory")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InvalidInputError(f"cannot write {path}: directory {parent} does not exist")
    return path


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write `text` to `path` via a temporary file and rename."""
    return atomic_write(path, lambda fh: fh.write(text), "w")


def write_json(path: str | Path, data: Any) -> Path:
    """Write `data` as indented JSON (atomic)."""
    return write_text_atomic(path, json.dumps(data, indent=2) + "\n")


def read_json(path_or_text: str | Path) -> Any:
    """Parse JSON from a file path, or from a string that starts with ``{`` or ``[``."""
    text: str
    if isinstance(path_or_text, str) and path_or_text.lstrip()[:1] in ("{", "["):
        text, where = path_or_text, "JSON text"
    else:
        path = Path(path_or_text)
        if not path.is_file():
            raise InvalidInputError(f"file not found: {path}")
        text, where = read_text(path), str(path)
    if not text.strip():
        raise InvalidInputError(f"{where} is empty")
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise InvalidInputError(
            f"{where} is not valid JSON: {exc.msg} at line {exc.lineno}"
        ) from exc
