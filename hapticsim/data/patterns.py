"""Exploration patterns on a superquadric: stripes and patches (paper III-A, SPEC §5).

A pattern is a set of directions ``(eta, omega)`` in the body frame, rendered to contact points and
outward normals with the uniform (equidistant) parametrisation of paper eq. (6) by
:meth:`Superquadric.surface`. Angles are the spherical angles of eq. (6): latitude ``eta`` in
[-pi/2, pi/2] and longitude ``omega`` [rad]; longitudes may run over [-2 pi, 2 pi] so that a range
can cross ``omega = pi``.

- :class:`Stripe`: a line in (eta, omega) space with ``count`` equidistant points, the trace of a
  single fingertip following a contour.
- :class:`Patch`: ``count`` points drawn uniformly from a rectangle in (eta, omega) space, a local
  touch of a fingertip.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import as_generator, finite_array, positive_int
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.geometry.superquadric import superquadric_arg

Array = NDArray[np.float64]

#: Bounds of the latitude eta and of the longitude omega accepted by patterns [rad].
ETA_MAX: float = np.pi / 2
OMEGA_MAX: float = 2 * np.pi


def _angle_pair(value: Any, name: str) -> tuple[float, float]:
    arr = finite_array(value, name, (2,))
    return float(arr[0]), float(arr[1])


def _check_eta(values: Sequence[float], name: str) -> None:
    if any(abs(v) > ETA_MAX + 1e-12 for v in values):
        raise InvalidInputError(
            f"`{name}` latitudes eta must lie in [-pi/2, pi/2] rad, got {list(values)}"
        )


def _check_omega(values: Sequence[float], name: str) -> None:
    if any(abs(v) > OMEGA_MAX + 1e-12 for v in values):
        raise InvalidInputError(
            f"`{name}` longitudes omega must lie in [-2 pi, 2 pi] rad, got {list(values)}"
        )


class _Pattern:
    """What stripes and patches share: rendering their directions on a superquadric."""

    def angles(self, rng: np.random.Generator | int | None = None) -> tuple[Array, Array]:
        raise NotImplementedError

    def sample(
        self, sq: Superquadric, rng: np.random.Generator | int | None = None
    ) -> tuple[Array, Array]:
        """Contact points and outward unit normals of the pattern on `sq` (paper eq. 6).

        Returns:
            points_world (count, 3) [m] and normals_world (count, 3).
        """
        sq = superquadric_arg(sq, "sq")
        return sq.surface(*self.angles(rng), "uniform")


@dataclass(frozen=True)
class Stripe(_Pattern):
    """A stripe: ``count`` equidistant directions on a line in (eta, omega) space (paper III-A).

    Attributes:
        start: (eta, omega) of the first contact [rad].
        end: (eta, omega) of the last contact [rad]; with ``count == 1`` only ``start`` is used.
        count: number of contacts, >= 1.
    """

    start: tuple[float, float]
    end: tuple[float, float]
    count: int

    def __post_init__(self) -> None:
        start = _angle_pair(self.start, "start")
        end = _angle_pair(self.end, "end")
        _check_eta((start[0], end[0]), "start/end")
        _check_omega((start[1], end[1]), "start/end")
        object.__setattr__(self, "start", start)
        object.__setattr__(self, "end", end)
        object.__setattr__(self, "count", positive_int(self.count, "count"))

    def angles(self, rng: np.random.Generator | int | None = None) -> tuple[Array, Array]:
        """The directions of the stripe, deterministic (``rng`` is accepted and not used).

        Returns:
            eta (count,) and omega (count,) [rad].
        """
        s = np.linspace(0.0, 1.0, self.count) if self.count > 1 else np.zeros(1)
        eta = self.start[0] + s * (self.end[0] - self.start[0])
        omega = self.start[1] + s * (self.end[1] - self.start[1])
        return eta, omega


@dataclass(frozen=True)
class Patch(_Pattern):
    """A randomised patch: ``count`` directions uniform in an (eta, omega) rectangle (paper III-A).

    Attributes:
        eta: (low, high) latitude range [rad], within [-pi/2, pi/2].
        omega: (low, high) longitude range [rad], within [-2 pi, 2 pi].
        count: number of contacts, >= 1.
    """

    eta: tuple[float, float]
    omega: tuple[float, float]
    count: int

    def __post_init__(self) -> None:
        eta = _angle_pair(self.eta, "eta")
        omega = _angle_pair(self.omega, "omega")
        _check_eta(eta, "eta")
        _check_omega(omega, "omega")
        for name, (low, high) in (("eta", eta), ("omega", omega)):
            if low > high:
                raise InvalidInputError(
                    f"`{name}` must be (low, high) with low <= high, got {low, high}"
                )
        object.__setattr__(self, "eta", eta)
        object.__setattr__(self, "omega", omega)
        object.__setattr__(self, "count", positive_int(self.count, "count"))

    def angles(self, rng: np.random.Generator | int | None = None) -> tuple[Array, Array]:
        """Random directions of the patch: eta drawn first, then omega, each uniform.

        Returns:
            eta (count,) and omega (count,) [rad].
        """
        gen = as_generator(rng)
        eta = gen.uniform(self.eta[0], self.eta[1], self.count)
        omega = gen.uniform(self.omega[0], self.omega[1], self.count)
        return eta, omega


Pattern = Stripe | Patch


def sample_patterns(
    sq: Superquadric, patterns: Sequence[Pattern], rng: np.random.Generator | int | None = None
) -> tuple[Array, Array, NDArray[np.int64]]:
    """Render several patterns on `sq` and merge them into one data set, in pattern order.

    Args:
        sq: the surface to touch.
        patterns: stripes and patches; one generator draws all random directions in order.
        rng: seed or generator for the patches.

    Returns:
        points_world (n, 3) [m], normals_world (n, 3) unit, and pattern (n,) int, the index in
        `patterns` of each contact; ``n = sum(p.count for p in patterns)``.
    """
    sq = superquadric_arg(sq, "sq")
    if isinstance(patterns, (Stripe, Patch)) or not isinstance(patterns, Sequence):
        raise InvalidInputError(
            f"`patterns` must be a sequence of Stripe/Patch, got {type(patterns).__name__}"
        )
    if len(patterns) == 0:
        raise InvalidInputError("`patterns` must hold at least one Stripe or Patch, got none")
    gen = as_generator(rng)
    points, normals, ids = [], [], []
    for i, pattern in enumerate(patterns):
        if not isinstance(pattern, (Stripe, Patch)):
            raise InvalidInputError(
                f"`patterns[{i}]` must be a Stripe or a Patch, got {type(pattern).__name__}"
            )
        p, n = pattern.sample(sq, gen)
        points.append(p)
        normals.append(n)
        ids.append(np.full(pattern.count, i, dtype=np.int64))
    return np.concatenate(points), np.concatenate(normals), np.concatenate(ids)


__all__ = ["ETA_MAX", "OMEGA_MAX", "Patch", "Pattern", "Stripe", "sample_patterns"]
