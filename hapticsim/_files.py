"""Files written atomically and JSON read with one-line errors (below every package).

Every file hapticsim writes goes to a temporary sibling first and is renamed into place, so a
failure (or Ctrl-C) never leaves a half-written file; unreadable, non-UTF-8 or malformed input
raises :class:`~hapticsim.errors.InvalidInputError` naming the file. ``geometry`` (superquadric
JSON) and ``data`` (contact files) both build on this module, which imports nothing of hapticsim
but its errors.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import tempfile
import threading
from collections.abc import Callable, Iterator
from contextvars import ContextVar, Token
from pathlib import Path
from typing import Any

from hapticsim.errors import InvalidInputError


def atomic_write(path: str | Path, write: Callable[[Any], None], mode: str) -> Path:
    """Call ``write(file)`` on a temporary sibling of `path` opened in `mode`, then rename it.

    A failure leaves no file (and no temporary) behind; errors become InvalidInputError. Inside
    an :class:`OutputSet` the rename waits for the set to be committed.
    """
    path = check_output_path(path)
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as exc:
        raise InvalidInputError(f"cannot write {path}: {exc.strerror or exc}") from exc
    with contextlib.suppress(OSError):  # mkstemp makes 0600; give what open() would have
        os.fchmod(fd, _file_mode(path))
    staging = _OUTPUT_SET.get()
    try:
        with os.fdopen(fd, mode) as fh:
            write(fh)
        if staging is not None:
            staging._stage(path, Path(tmp))
        else:
            os.replace(tmp, path)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise InvalidInputError(f"cannot write {path}: {exc.strerror or exc}") from exc
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def _process_umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


#: The process's umask, read once at import (reading it means setting it).
_UMASK = _process_umask()


def _file_mode(path: Path) -> int:
    """The permission bits ``open(path, "w")`` would leave: an existing file's own, else
    0666 less the umask."""
    try:
        return path.stat().st_mode & 0o7777
    except OSError:
        return 0o666 & ~_UMASK


_OUTPUT_SET: ContextVar[OutputSet | None] = ContextVar("hapticsim_output_set", default=None)


class OutputSet:
    """The files of one run, which appear together or not at all.

    Inside ``with OutputSet():`` every :func:`atomic_write` (and so every writer of hapticsim)
    leaves its file under a temporary name; when the block ends normally they are all renamed
    into place, with Ctrl-C held back until the last rename, and when it ends in an exception
    (Ctrl-C included) they are all removed. A run that fails half-way through writing its
    outputs therefore leaves none of them (files of an earlier run stay as they were).

    :meth:`source` gives where a file written inside the set can be read before the commit.
    """

    def __init__(self) -> None:
        self._staged: dict[Path, Path] = {}  # final path -> temporary file
        self._token: Token[OutputSet | None] | None = None

    def __enter__(self) -> OutputSet:
        if _OUTPUT_SET.get() is not None:
            raise RuntimeError("output sets do not nest")
        self._token = _OUTPUT_SET.set(self)
        return self

    def __exit__(self, exc_type: Any, exc: Any, tb: Any) -> None:
        assert self._token is not None
        _OUTPUT_SET.reset(self._token)
        if exc_type is None:
            self._commit()
        else:
            self._discard()

    def _stage(self, path: Path, tmp: Path) -> None:
        key = path.resolve()
        old = self._staged.pop(key, None)
        if old is not None:
            old.unlink(missing_ok=True)
        self._staged[key] = tmp

    def source(self, path: str | Path) -> Path:
        """Where the content of `path` is now: its temporary file if staged here, else itself."""
        return self._staged.get(Path(path).resolve(), Path(path))

    def _discard(self) -> None:
        for tmp in self._staged.values():
            tmp.unlink(missing_ok=True)
        self._staged.clear()

    def _commit(self) -> None:
        done: list[Path] = []
        with _sigint_held():
            try:
                for final, tmp in self._staged.items():
                    os.replace(tmp, final)
                    done.append(final)
            except OSError as exc:
                for final in done:  # all or nothing
                    final.unlink(missing_ok=True)
                self._discard()
                raise InvalidInputError(f"cannot write {final}: {exc.strerror or exc}") from exc
        self._staged.clear()


@contextlib.contextmanager
def _sigint_held() -> Iterator[None]:
    """Hold back Ctrl-C (SIGINT) during the block and raise it after (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if caught:  # now do what the previous handler would have done
        if callable(previous):
            previous(signal.SIGINT, None)  # Python's default raises KeyboardInterrupt
        elif previous == signal.SIG_DFL:
            raise KeyboardInterrupt


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


def read_toml(path: Path, where: str, error: type[Exception] = InvalidInputError) -> dict:
    """A TOML file's table; `error` ``"{where}: not valid TOML (...)"`` or ``"cannot read it
    (...)"`` otherwise."""
    import tomllib

    try:
        return tomllib.loads(Path(path).read_text())
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{where}: not valid TOML ({exc})") from exc
    except (OSError, UnicodeDecodeError) as exc:
        reason = getattr(exc, "strerror", None) or exc
        raise error(f"{where}: cannot read it ({reason})") from exc


def named_toml(
    value: str | Path, names: tuple[str, ...], directory: Path, argument: str, kind: str,
    error: type[Exception] = InvalidInputError,
) -> Path:  # fmt: skip
    """The TOML file a name or a path gives: a shipped name (``directory/NAME.toml``) or a
    ``.toml`` path (the hands' and skins' loader).

    Args:
        value: a name of `names` or a path.
        names: the shipped names.
        directory: where the shipped files lie.
        argument: the argument in messages (``"hand"``).
        kind: what a file holds, in messages (``"hand description"``).
        error: the exception to raise (a subclass of :class:`InvalidInputError`).

    Returns:
        the file's resolved path.

    Raises:
        `error`: a path that does not exist, or neither a shipped name nor a ``.toml`` path
        (listing the names, with the nearest).
    """
    from hapticsim.errors import ChoiceError

    if isinstance(value, str) and value in names:
        path = directory / f"{value}.toml"
    elif isinstance(value, (str, Path)) and Path(value).suffix.lower() == ".toml":
        path = Path(value).expanduser()
        if not path.is_file():
            raise error(f"{kind} {str(path)!r} not found")
    else:
        raise error(str(ChoiceError(argument, value, names, f"or a .toml {kind}")))
    return path.resolve()


def write_bytes_atomic(path: str | Path, data: bytes) -> Path:
    """Write bytes through a temporary sibling file and a rename."""
    return atomic_write(path, lambda fh: fh.write(data), "wb")


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
