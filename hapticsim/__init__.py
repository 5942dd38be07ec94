"""hapticsim: a physics-simulated haptic exploration testbed.

A multi-fingered MuJoCo hand touches objects meshed from superquadrics; contact points and normals
feed a robust superquadric fitter (genetic algorithm + least squares, Bierbaum et al.); volume
metrics score the estimate against the known truth; a Gymnasium environment
(``hapticsim/HapticExplore-v0``, registered on import) lets exploration strategies plug in.

Top-level names: :class:`Superquadric`, :func:`fit`, :func:`score`, :class:`HapticsimError`.
"""

from __future__ import annotations

from typing import Any

from hapticsim._version import __version__
from hapticsim.errors import HapticsimError, InvalidInputError, SimulationError
from hapticsim.geometry import Superquadric

__all__ = [
    "HapticsimError",
    "InvalidInputError",
    "SimulationError",
    "Superquadric",
    "__version__",
    "fit",
    "score",
]


def __getattr__(name: str) -> Any:
    # Lazy so that `import hapticsim.geometry` stays light (no scipy import).
    if name == "fit":
        from hapticsim.fitting import fit

        return fit
    if name == "score":
        from hapticsim.metrics import score

        return score
    raise AttributeError(f"module 'hapticsim' has no attribute {name!r}")


def _register_envs() -> None:
    """Register the Gymnasium environments (Gymnasium 1.4 reads no entry points)."""
    try:
        import gymnasium  # noqa: F401 - registering needs it; the rest of hapticsim does not

        from hapticsim.envs.registration import register_envs
    except ImportError:  # gymnasium missing: hapticsim works, without its environments
        return
    register_envs()


_register_envs()
