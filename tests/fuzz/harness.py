"""Run one ``hapticsim`` command line in this process and check the SPEC §6 contract on it.

The contract (issue 14's property): exit 0 with valid JSON on stdout, or exit 2 with exactly
one line on stderr (and nothing on stdout); never a traceback; no output file unless the run
succeeded, and never a temporary file left behind. ``suite compare`` may also exit 1 (a
regression) and prints a table unless given ``--json`` (SPEC §6).

:func:`run_cli` calls :func:`hapticsim.cli.main` with the file descriptors 1 and 2 redirected
to temporary files, so what C libraries (MuJoCo) print is caught as well as Python's writes,
warnings (all shown, filter "always") and log records.
"""

from __future__ import annotations

import contextlib
import io
import json
import logging
import os
import sys
import tempfile
import traceback
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from hapticsim.cli import main

#: Exit status of bad input (SPEC §6).
EXIT_BAD_INPUT = 2


@dataclass
class Outcome:
    """What one invocation did.

    Attributes:
        argv: the arguments after ``hapticsim``.
        code: exit status (``main``'s return value or SystemExit's code); None when an
            exception escaped ``main``.
        stdout, stderr: everything written to file descriptors 1 and 2.
        exception: the formatted traceback of an exception that escaped ``main``.
        created: files under the work directory that did not exist before the run.
        changed: files that existed before and were modified.
    """

    argv: list[str]
    code: int | None
    stdout: str
    stderr: str
    exception: str | None = None
    created: list[str] = field(default_factory=list)
    changed: list[str] = field(default_factory=list)

    def problems(self) -> list[str]:
        """Ways this outcome breaks the contract (empty when it keeps it)."""
        found = []
        if self.exception is not None:
            found.append(f"exception escaped main: {self.exception.strip().splitlines()[-1]}")
        if "Traceback (most recent call last)" in self.stderr + self.stdout:
            found.append("traceback printed")
        temporaries = [p for p in self.created if p.endswith(".tmp")]
        if temporaries:
            found.append(f"temporary files left: {temporaries}")
        # `suite compare` exits 1 on a regression (SPEC §6) and prints a table unless --json
        compare = self.argv[:2] == ["suite", "compare"]
        if self.code == 0 or (compare and self.code == 1):
            if compare and "--json" not in self.argv:
                if not self.stdout.strip():
                    found.append("suite compare printed no table")
            else:
                try:
                    json.loads(self.stdout)
                except ValueError:
                    found.append(f"exit 0 without valid JSON on stdout: {self.stdout[:200]!r}")
        elif self.code == EXIT_BAD_INPUT:
            lines = visible_lines(self.stderr)
            if len(lines) != 1:
                found.append(f"exit 2 with {len(lines)} lines on stderr: {lines[:5]}")
            if self.stdout:
                found.append(f"exit 2 with output on stdout: {self.stdout[:200]!r}")
        elif self.code is not None:
            found.append(f"exit status {self.code}: {self.stderr[-300:]!r}")
        if self.code not in (0, 1 if compare else 0) and (self.created or self.changed):
            found.append(f"failed run wrote files: {self.created + self.changed}")
        return found

    def to_dict(self) -> dict[str, object]:
        """JSON-ready summary (for the fuzz script's report)."""
        return {
            "argv": self.argv,
            "code": self.code,
            "stderr": self.stderr[-500:],
            "problems": self.problems(),
        }


def visible_lines(text: str) -> list[str]:
    """The lines a terminal would show: progress bars redrawn with carriage returns (tqdm)
    count as what they were last overwritten with; blank results are dropped."""
    shown = []
    for line in text.split("\n"):
        last = line.split("\r")[-1]
        if last.strip():
            shown.append(last)
    return shown


def _snapshot(root: Path) -> dict[str, tuple[int, int]]:
    """Relative path -> (size, mtime_ns) of every file under `root`."""
    out = {}
    for path in root.rglob("*"):
        if path.is_file():
            st = path.stat()
            out[str(path.relative_to(root))] = (st.st_size, st.st_mtime_ns)
    return out


@contextlib.contextmanager
def _captured_fds(into: dict[str, str]) -> Iterator[None]:
    """Redirect fds 1 and 2 (and sys.stdout/sys.stderr onto them) to two temporary files;
    on exit, store what was written as ``into["stdout"]`` and ``into["stderr"]``."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        for stream in (sys.stdout, sys.stderr, sys.__stdout__, sys.__stderr__):
            with contextlib.suppress(Exception):
                stream.flush()
        saved_fds = os.dup(1), os.dup(2)
        saved_streams = sys.stdout, sys.stderr
        os.dup2(out.fileno(), 1)
        os.dup2(err.fileno(), 2)
        sys.stdout = io.TextIOWrapper(open(1, "wb", closefd=False), write_through=True)
        sys.stderr = io.TextIOWrapper(open(2, "wb", closefd=False), write_through=True)
        try:
            yield
        finally:
            for stream in (sys.stdout, sys.stderr):
                stream.flush()
                stream.detach().close()  # the buffered writer; fds 1 and 2 stay open
            sys.stdout, sys.stderr = saved_streams
            os.dup2(saved_fds[0], 1)
            os.dup2(saved_fds[1], 2)
            os.close(saved_fds[0])
            os.close(saved_fds[1])
            for key, fh in (("stdout", out), ("stderr", err)):
                fh.seek(0)
                into[key] = fh.read().decode("utf-8", errors="replace")


def run_cli(argv: Sequence[str], cwd: Path) -> Outcome:
    """Run ``hapticsim ARGV`` in `cwd` in this process; see the module docstring."""
    argv = [str(a) for a in argv]
    before = _snapshot(cwd)
    old_cwd = Path.cwd()
    code: int | None = None
    exception = None
    # the last-resort handler prints log records on stderr, as in a fresh process
    saved_handler = logging.lastResort
    written: dict[str, str] = {}
    with _captured_fds(written):
        logging.lastResort = logging.StreamHandler(sys.stderr)
        logging.lastResort.setLevel(logging.WARNING)
        os.chdir(cwd)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("always")
                try:
                    code = main(argv)
                except SystemExit as exc:
                    code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
                except BaseException:  # noqa: BLE001 - the point is to catch everything
                    exception = traceback.format_exc()
        finally:
            os.chdir(old_cwd)
            logging.lastResort = saved_handler
    stdout, stderr = written["stdout"], written["stderr"]
    after = _snapshot(cwd)
    created = sorted(set(after) - set(before))
    changed = sorted(k for k in before if k in after and after[k] != before[k])
    return Outcome(list(argv), code, stdout, stderr, exception, created, changed)


__all__ = ["EXIT_BAD_INPUT", "Outcome", "run_cli", "visible_lines"]
