"""Named exploration strategies.

A strategy is a function ``strategy(explorer, count, rng) -> None`` that runs patterns on an
:class:`~hapticsim.sim.explorer.Explorer` until its recorder holds `count` contacts (the
recorder's capacity) or there is nothing left to do.
"""

from __future__ import annotations

from collections.abc import Callable
from types import MappingProxyType

import numpy as np

from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.sim.explorer import Explorer

Strategy = Callable[[Explorer, int, np.random.Generator], None]

_REGISTRY: dict[str, Strategy] = {}
#: Read-only view of the registered strategies by name.
STRATEGIES = MappingProxyType(_REGISTRY)


def register(name: str) -> Callable[[Strategy], Strategy]:
    """Decorator that registers a strategy under a name."""

    def wrap(fn: Strategy) -> Strategy:
        if name in _REGISTRY:
            raise InvalidInputError(f"strategy {name!r} is already registered")
        _REGISTRY[name] = fn
        return fn

    return wrap


def strategy_names() -> tuple[str, ...]:
    """Names of the registered strategies, sorted."""
    return tuple(sorted(_REGISTRY))


def get_strategy(name: str) -> Strategy:
    """The strategy registered under `name`.

    Raises:
        InvalidInputError: unknown name; the message lists the choices.
    """
    if not isinstance(name, str) or name not in _REGISTRY:
        raise ChoiceError("strategy", name, strategy_names())
    return _REGISTRY[name]


__all__ = ["STRATEGIES", "Strategy", "get_strategy", "register", "strategy_names"]
