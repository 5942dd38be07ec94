"""Example plug-ins: templates for a lab's own ``--fitter`` and ``--policy``.

- ``--fitter hapticsim.suites.examples:least_squares_fit``: plain least squares from the paper's
  initial estimate (method LS), a deliberately weaker fitter than nH; ``suite compare`` against
  the nH baseline shows which groups it loses.
- ``--policy hapticsim.suites.examples:AxisPolicy``: touches from the six axis directions in
  turn. It does not derive from :class:`hapticsim.envs.policies.Policy`: any class with the same
  three methods plugs in.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray


def least_squares_fit(points: NDArray[np.float64], normals: NDArray[np.float64]) -> Any:
    """Least squares from the paper's initial estimate, points only (method LS, SPEC §3).

    Args:
        points: (n, 3) float, contact points [m, world].
        normals: (n, 3) float, unit outward normals (ignored).

    Returns:
        the :class:`~hapticsim.fitting.FitResult` (its ``superquadric`` is the estimate).
    """
    from hapticsim.fitting import fit

    return fit(points, method="LS")


class AxisPolicy:
    """Touch from +x, -x, +y, -y, +z, -z in turn, with a random stroke direction.

    Args:
        env: the environment (its configuration is read: stroke length, finger count).
        rng: seed or generator of the stroke directions.
    """

    def __init__(self, env: Any, rng: np.random.Generator | int | None = None) -> None:
        base = env.unwrapped
        self.max_stroke = float(base.config.max_stroke)
        self.n_fingers = int(base.n_fingers)
        self.rng = np.random.default_rng(rng)

    def reset(self, rng: np.random.Generator | int | None = None) -> None:
        """Start an episode (reseed when `rng` is given)."""
        if rng is not None:
            self.rng = np.random.default_rng(rng)

    def __call__(self, obs: dict[str, np.ndarray]) -> NDArray[np.float32]:
        """The action of the next touch (uses only the touch count of `obs`)."""
        from hapticsim.envs.touch import encode_touch

        k = int(round(float(obs["touches"][0]))) % 6
        approach = np.zeros(3)
        approach[k // 2] = 1.0 if k % 2 == 0 else -1.0
        angle = float(self.rng.uniform(-np.pi, np.pi))
        return encode_touch(
            approach, angle, self.max_stroke, k % self.n_fingers, self.max_stroke, self.n_fingers
        )
