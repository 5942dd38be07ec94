"""Argument checks shared by the experiment configs (internal)."""

from __future__ import annotations

from collections.abc import Sequence

from hapticsim._validate import positive_int
from hapticsim.constants import MAX_CONTACTS, MAX_RUNS
from hapticsim.errors import InvalidInputError


def check_common(count: int, runs: int, seed: int, methods: Sequence[str]) -> None:
    """Checks shared by the figure configs."""
    from hapticsim.fitting.methods import METHODS

    positive_int(count, "count", maximum=MAX_CONTACTS)
    positive_int(runs, "runs", maximum=MAX_RUNS)
    positive_int(seed, "seed", minimum=0)
    if not methods:
        raise InvalidInputError("`methods` must not be empty")
    for method in methods:
        if method not in METHODS:
            raise InvalidInputError(
                f"`methods` must be drawn from {', '.join(METHODS)}, got {method!r}"
            )


def check_bodies(bodies: Sequence[str], name: str) -> None:
    from hapticsim.data.bodies import BODY_NAMES

    for body in bodies:
        if body not in BODY_NAMES:
            raise InvalidInputError(
                f"`{name}` must be drawn from {', '.join(BODY_NAMES)}, got {body!r}"
            )


def check_noise(noise: float, name: str) -> None:
    if not (isinstance(noise, (int, float)) and 0 <= noise < float("inf")):
        raise InvalidInputError(f"`{name}` must be a finite float >= 0, got {noise!r}")
