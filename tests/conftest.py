"""Session set-up of the tests: a fresh installation's kernels compile first, in parallel.

Without this, the first test that fits compiles the fitter's kernels in its own process, one
after another (about a minute on 2 cores), and pytest shows nothing meanwhile. Here a cold cache
is filled before the first test by one worker process per core
(:func:`hapticsim.fitting.kernels.start_background`), with a line every 10 s; a warm cache costs
nothing (the markers say so without loading anything).
"""

from __future__ import annotations

import sys

import pytest


def pytest_sessionstart(session: pytest.Session) -> None:
    from hapticsim.fitting import kernels

    methods = ("nH", "nML")
    if all(kernels.is_cached(p) for p in kernels.parts_for(methods)):
        return
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    say = sys.__stderr__.write if reporter is None else reporter.write_line  # past the capture
    background = kernels.start_background(methods, stream=_Lines(say))
    if background is not None:
        background.wait(say=say)


class _Lines:
    """A text stream handing each line to `say`."""

    def __init__(self, say) -> None:  # noqa: ANN001 - a callable taking a line
        self.say = say

    def write(self, text: str) -> None:
        for line in text.splitlines():
            self.say(line)

    def flush(self) -> None:
        pass
