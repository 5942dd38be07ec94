"""Exploration strategies composed of patches and stripes (paper III-A, IV), by name.

Use :func:`get_strategy` (unknown names raise an error listing the choices) and
:func:`strategy_names`.
"""

from hapticsim.sim.strategies import library as _library  # noqa: F401  (registers)
from hapticsim.sim.strategies.registry import (
    STRATEGIES,
    Strategy,
    get_strategy,
    register,
    strategy_names,
)

__all__ = ["STRATEGIES", "Strategy", "get_strategy", "register", "strategy_names"]
