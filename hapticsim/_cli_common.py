"""What the ``hapticsim`` command line's modules share: the parser class whose errors are one
line, the argparse types, the JSON printer and the exit statuses."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any, NoReturn

from hapticsim._validate import did_you_mean
from hapticsim.constants import MAX_INT

EXIT_BAD_INPUT = 2
#: Exit status after Ctrl-C (128 + SIGINT, as a shell reports it).
EXIT_INTERRUPTED = 130


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose errors are one line on stderr, exit status 2; ``lazy_epilog``
    (a callable) builds the epilog only when the help is shown."""

    lazy_epilog: Any = None

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")

    def _check_value(self, action: argparse.Action, value: Any) -> None:
        # argparse's "invalid choice" message, with the choice one edit away
        if action.choices is not None and value not in action.choices:

            choices = ", ".join(map(repr, action.choices))
            raise argparse.ArgumentError(
                action,
                f"invalid choice: {value!r}{did_you_mean(value, action.choices)} "
                f"(choose from {choices})",
            )
        super()._check_value(action, value)

    def format_help(self) -> str:
        if self.lazy_epilog is not None and self.epilog is None:
            self.epilog = self.lazy_epilog()
        return super().format_help()


def _parts(text: str) -> int | str:
    """argparse type of ``--parts``: ``auto`` or an int from 1."""
    if text == "auto":
        return text
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be an int >= 1 or 'auto', got {text!r}")
    return value


def _positive_float(text: str) -> float:
    """argparse type of ``--scale``: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number > 0, got {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
    return value


def _seed(text: str) -> int:
    """argparse type of ``--seed``: an int in [0, 2**62] (``numpy.random.default_rng`` takes any
    int >= 0; the bound is the one every integer argument has, :data:`constants.MAX_INT`)."""

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, got {text!r}") from None
    if not 0 <= value <= MAX_INT:
        raise argparse.ArgumentTypeError(f"must be an integer in [0, {MAX_INT}], got {text!r}")
    return value


def _positive_int(text: str) -> int:
    """argparse type of counts (``--episodes``, ``--touches``, ``--workers``): an int >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}")
    return value


def _print_json(data: Any) -> None:
    sys.stdout.write(json.dumps(data, indent=2) + "\n")
    sys.stdout.flush()
