"""MuJoCo's warnings go to Python logging, never to ``MUJOCO_LOG.TXT`` in the working directory.

MuJoCo's default warning handler prints to stderr and appends to ``MUJOCO_LOG.TXT`` in the
current directory, e.g. when a simulation goes unstable. Importing this module (the simulator
and the scene builder do) installs a handler, unless the process already has one
(``mujoco.set_mju_user_warning``), that instead

- logs each message on the ``hapticsim.mujoco`` logger: at DEBUG level when it reports an
  unstable simulation (the simulator raises :class:`~hapticsim.errors.SimulationError` for it,
  quoting the message), at WARNING level otherwise (e.g. too many contacts);
- keeps the last few messages (:func:`take_last_warning`), so that an error can quote MuJoCo.
"""

from __future__ import annotations

import logging
from collections import deque

import mujoco

#: Logger of MuJoCo's warnings.
LOGGER = logging.getLogger("hapticsim.mujoco")
#: Words of MuJoCo's message for a bad state (mjWARN_BADQPOS, BADQVEL, BADQACC).
UNSTABLE_WORDS = "simulation is unstable"

_recent: deque[str] = deque(maxlen=8)


def _on_warning(message: str) -> None:
    text = " ".join(str(message).split())
    _recent.append(text)
    level = logging.DEBUG if UNSTABLE_WORDS in text else logging.WARNING
    LOGGER.log(level, "MuJoCo: %s", text)


def install() -> bool:
    """Install the handler unless one is installed already; True when it is ours."""
    current = mujoco.get_mju_user_warning()
    if current is None:
        mujoco.set_mju_user_warning(_on_warning)
        return True
    return current is _on_warning


def take_last_warning() -> str | None:
    """The most recent MuJoCo warning handled here (None if there is none); forgets them all,
    so that a later error never quotes a stale message."""
    last = _recent[-1] if _recent else None
    _recent.clear()
    return last


install()

__all__ = ["LOGGER", "UNSTABLE_WORDS", "install", "take_last_warning"]
