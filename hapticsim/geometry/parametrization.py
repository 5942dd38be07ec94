"""Surface parametrisations of the symmetric superquadric: natural (eq. 1) and uniform (eq. 6).

Angles: latitude ``eta`` in [-pi/2, pi/2] [rad], longitude ``omega`` in [-pi, pi] [rad]. Both
functions return untapered body-frame points; :meth:`Superquadric.surface` applies tapering and
the pose.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import ChoiceError
from hapticsim.geometry.functions import radial_scale, signed_power

Array = NDArray[np.float64]
Parametrization = Literal["natural", "uniform"]
PARAMETRIZATIONS: tuple[str, ...] = ("natural", "uniform")


def natural(eta: Array, omega: Array, a: Array, eps: Array) -> Array:
    """Natural parametrisation, paper eq. (1).

    ``chi = (a1 c(eta)^e1 c(omega)^e2, a2 c(eta)^e1 s(omega)^e2, a3 s(eta)^e1)`` with signed powers.

    Args:
        eta: (n,) float latitudes [rad].
        omega: (n,) float longitudes [rad].
        a: (3,) semi-axes [m].
        eps: (2,) exponents.

    Returns:
        (n, 3) float, untapered body-frame surface points [m].
    """
    eta, omega = np.broadcast_arrays(np.asarray(eta, float), np.asarray(omega, float))
    e1, e2 = float(eps[0]), float(eps[1])
    ce = signed_power(np.cos(eta), e1)
    return np.stack(
        [
            a[0] * ce * signed_power(np.cos(omega), e2),
            a[1] * ce * signed_power(np.sin(omega), e2),
            a[2] * signed_power(np.sin(eta), e1),
        ],
        -1,
    )


def uniform(eta: Array, omega: Array, a: Array, eps: Array) -> Array:
    """Uniform (equidistant, spherical-angle) parametrisation of Bardin, paper eq. (6).

    ``chi' = rho (a1 cos eta cos omega, a2 cos eta sin omega, a3 sin eta)`` with ``rho`` the factor
    that puts the point on the surface (``rho = F(direction)^(-eps1/2)``).

    Returns:
        (n, 3) float, untapered body-frame surface points [m].
    """
    eta, omega = np.broadcast_arrays(np.asarray(eta, float), np.asarray(omega, float))
    a = np.asarray(a, dtype=np.float64)
    d = np.stack(
        [
            a[0] * np.cos(eta) * np.cos(omega),
            a[1] * np.cos(eta) * np.sin(omega),
            a[2] * np.sin(eta),
        ],
        -1,
    )
    return d * radial_scale(d, a, np.asarray(eps, dtype=np.float64))[..., None]


def parametrize(
    eta: Array, omega: Array, a: Array, eps: Array, parametrization: str = "uniform"
) -> Array:
    """Dispatch to :func:`natural` or :func:`uniform` by name."""

    if parametrization == "natural":
        return natural(eta, omega, a, eps)
    if parametrization == "uniform":
        return uniform(eta, omega, a, eps)
    raise ChoiceError("parametrization", parametrization, PARAMETRIZATIONS)
