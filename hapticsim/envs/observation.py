"""The observation codec of ``HapticExplore-v0``: the fit entry (13 normalised numbers) and
the bound every scaled entry is clipped to.

The fit's numbers follow the parameter layout of :meth:`Superquadric.to_vector` (the
``SLICE_*`` names of :mod:`hapticsim.geometry.superquadric`), each normalised: semi-axes and
centre by the observation's length scale, the exponents' range [0.1, 2] onto [-1, 1], the rotation
vector by pi.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import EPS_MAX, EPS_MIN
from hapticsim.geometry import N_PARAMS, Superquadric
from hapticsim.geometry.superquadric import (
    SLICE_A,
    SLICE_CENTER,
    SLICE_EPS,
    SLICE_ROTVEC,
    SLICE_TAPER,
)

Array = NDArray[np.float64]

#: Bound of the scaled coordinates in the observation (points, fit); values are clipped to it.
OBS_BOUND: float = 10.0
#: Middle and half-width of the exponents' range (normalised onto [-1, 1]).
_EPS_MID: float = 0.5 * (EPS_MAX + EPS_MIN)
_EPS_HALF: float = 0.5 * (EPS_MAX - EPS_MIN)


def encode_fit(estimate: Superquadric | None, origin: Array, scale: float) -> NDArray[np.float32]:
    """The 13 normalised fit parameters of the observation (zeros without an estimate).

    Order of :meth:`Superquadric.to_vector`: ``a / scale``, ``(eps - 1.05) / 0.95`` (so [0.1, 2]
    maps to [-1, 1]), taper, ``rotvec / pi``, ``(center - origin) / scale``.

    Args:
        estimate: the fit, or None.
        origin: (3,) float, the object-centred frame's origin [m, world].
        scale: the observation's length scale [m].
    """
    if estimate is None:
        return np.zeros(N_PARAMS, np.float32)
    v = estimate.to_vector()
    out = np.concatenate(
        [
            v[SLICE_A] / scale,
            (v[SLICE_EPS] - _EPS_MID) / _EPS_HALF,
            v[SLICE_TAPER],
            v[SLICE_ROTVEC] / np.pi,
            (v[SLICE_CENTER] - origin) / scale,
        ]
    )
    return np.clip(out, -OBS_BOUND, OBS_BOUND).astype(np.float32)


def decode_fit(fit_obs: Any, scale: float) -> Superquadric:
    """The estimate, in the object-centred frame, from the observation's ``"fit"`` entry.

    Args:
        fit_obs: (13,) float, as made by :func:`encode_fit`.
        scale: the observation's length scale [m] (``config.obs_scale``).

    Returns:
        the superquadric with its centre relative to the object-centred frame's origin [m].
    """
    v = np.asarray(fit_obs, dtype=np.float64)
    vec = np.concatenate(
        [np.maximum(v[SLICE_A] * scale, 1e-6),
         np.clip(v[SLICE_EPS] * _EPS_HALF + _EPS_MID, EPS_MIN, EPS_MAX),
         np.clip(v[SLICE_TAPER], -1, 1), v[SLICE_ROTVEC] * np.pi, v[SLICE_CENTER] * scale]
    )  # fmt: skip
    return Superquadric.from_vector(vec)


__all__ = ["OBS_BOUND", "decode_fit", "encode_fit"]
