"""Fitting a supertoroid (:class:`~hapticsim.geometry.supertoroid.Supertoroid`) to contacts with
normals: ``fit(..., method="supertoroid")``; and the rule that decides between a ring and a union
of superquadrics (``fit(..., method="multi", holes=True)``).

**The error of fit.** As the paper's EOF (SPEC §2) with the tube in the place of the
superquadric: in the body frame a contact has the tube coordinates ``u = r - hole`` (r the xy
superellipse radius, in units of a1, a2) and ``w = z / a3``, and ``t = (|u|^(2/eps1) +
|w|^(2/eps1))^(eps1/2)`` is 1 on the surface. D1 is the radial distance in the tube's
cross-section, ``|p_t| |1 - 1/t|`` with ``p_t = (u s, w a3)`` the point's offset from the tube's
centre line in metres (s the metres per unit of r at the point); D2 is ``||n - n'||^2`` with n'
the analytic normal. The residual of a contact is ``|D1| + lambda sigma D2`` (sigma the mean
of a1, a2, a3), its mean square the EOF.

**The search.** Trust-region least squares (scipy's ``least_squares``) over (log a, eps, log(hole
- 1), rotation vector, centre), from starts on each principal axis of the contacts as the ring's
axis, with the ring's radius and the tube's size from the contacts' spread about that axis and
eps = (1, 1) or (0.5, 0.5): each start takes a few steps, the two best go on to convergence,
and the better end by EOF is the fit.

**Rings in multi** (:func:`choose_holed`): multi's union, one ring on all contacts, the union
with the part that explains its contacts worst replaced by a ring fitted to them, and the union
with a ring added for the contacts it explains worst are scored by multi's robust criterion
(:mod:`hapticsim.fitting.multi`: ``sum min(z^2, CAP^2) + P ln n``, z the contact's distance to
the surface and its normal's chord over the noise levels of multi's record), with the distances
and normals of each solid's own :meth:`~hapticsim.geometry.solid.Solid.contact_errors`; P is 12
a ring and 13 a superquadric part. The smallest cost wins, and a candidate's ring must have at
least :data:`MIN_INNER_SHARE` of its contacts on its inner wall, facing the axis (a hole nothing
touched is not a hole), and lie mostly where the contacts are: no more than
:data:`RING_OUTSIDE_SHARE` of its volume beyond the contacts' box grown by multi's ``REACH``
data sizes (rings fitted to the few contacts a union explains worst, on hammers, had put 60-89 %
of their volume out there and won on cost; true rings touched on one side reach 2-11 %).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import EPS_MAX, EPS_MIN
from hapticsim.geometry.rotations import matrix_to_rotvec, rotvec_to_matrix
from hapticsim.geometry.solid import Solid
from hapticsim.geometry.supertoroid import (
    HOLE_MAX,
    HOLE_MIN,
    Supertoroid,
    body_normals,
    tube_coordinates,
)

Array = NDArray[np.float64]

#: Parameters of a supertoroid: a (3), eps (2), hole, rotation vector (3), centre (3).
N_TOROID_PARAMS: int = 12
#: Starting exponents tried from each axis.
START_EPS: tuple[tuple[float, float], ...] = ((1.0, 1.0), (0.5, 0.5))
#: Least-squares steps of every start before the best are kept, and the most of a kept one.
SCREEN_EVALUATIONS, MAX_EVALUATIONS = 25, 400
#: Starts continued to convergence.
KEPT_STARTS: int = 2
#: The share of contacts a ring needs on its inner wall to be chosen (:func:`inner_share`): a
#: hole that nothing touched is not a hole.
MIN_INNER_SHARE: float = 0.05
#: The fewest contacts a ring is fitted to (a part of the union, or what it explains worst).
MIN_RING_CONTACTS: int = 30
#: Largest share of a candidate ring's volume beyond the contacts' box grown by multi's
#: ``REACH`` (module docstring). Measured with the uncertainty policy (docs/objects.md): the
#: rings that won on cost where there is no hole (hammers) 0.60-0.89; true rings touched on one
#: side 0.02-0.11 (random rings), 0 (pybullet's torus); parts of a union keep 0.02 because
#: their refinement already has the box's faces as free space, a ring's fit has not.
RING_OUTSIDE_SHARE: float = 0.25


def _unpack(x: Array) -> Supertoroid:
    a = np.exp(x[0:3])
    eps = np.clip(x[3:5], EPS_MIN, EPS_MAX)
    hole = float(np.clip(1.0 + np.exp(x[5]), HOLE_MIN, HOLE_MAX))
    return Supertoroid(a, eps, hole, rotvec_to_matrix(x[6:9]), x[9:12])


def _pack(t: Supertoroid) -> Array:
    return np.concatenate([np.log(t.a), t.eps, [np.log(t.hole - 1.0)],
                           matrix_to_rotvec(t.rotation), t.center])  # fmt: skip


def toroid_residuals(t: Supertoroid, points: Array, normals: Array, lam: float = 0.5) -> Array:
    """(n,) ``|D1| + lambda sigma D2`` of each contact (module docstring) [m]."""
    return _residuals(t.a, t.eps, t.hole, t.rotation, t.center, points, normals, lam)


def _residuals(a: Array, eps: Array, hole: float, rotation: Array, center: Array, points: Array,
               normals: Array, lam: float) -> Array:  # fmt: skip
    """:func:`toroid_residuals` of raw parameters (the search's: no solid is made)."""
    b = (points - center) @ rotation
    a1, a2, a3 = a
    rho = np.hypot(b[:, 0], b[:, 1])
    r, u, w, f = tube_coordinates(b, a, eps, hole)
    scale = np.where(r > 1e-12, rho / np.maximum(r, 1e-12), 0.5 * (a1 + a2))  # m per unit of r
    tube = f ** (eps[0] / 2)
    offset = np.hypot(u * scale, w * a3)
    d1 = offset * np.abs(1.0 - 1.0 / np.maximum(tube, 1e-12))
    d2 = np.sum((normals @ rotation - body_normals(b, a, eps, hole)) ** 2, axis=1)
    return np.abs(d1) + lam * float(np.mean(a)) * d2


def _starts(points: Array) -> list[Array]:
    center = points.mean(axis=0)
    centered = points - center
    _, axes = np.linalg.eigh(centered.T @ centered)
    out = []
    for k in range(3):  # each principal axis as the ring's axis
        z = axes[:, k]
        x = axes[:, (k + 1) % 3]
        rot = np.column_stack([x, np.cross(z, x), z])
        height = centered @ z
        radial = np.linalg.norm(centered - height[:, None] * z, axis=1)
        ring = float(np.median(radial))
        # the tube's half-width: a quarter of the contacts' radial spread about the axis
        tube = max(0.25 * (np.percentile(radial, 95) - np.percentile(radial, 5)), 0.1 * ring)
        half = max(float(np.percentile(np.abs(height), 95)), 0.1 * ring)
        hole = float(np.clip(ring / max(tube, 1e-6), 1.3, HOLE_MAX / 2))
        for eps in START_EPS:
            start = Supertoroid([ring / hole, ring / hole, half], eps, hole, rot, center)
            out.append(_pack(start))
    return out


def fit_supertoroid(
    points: Array, normals: Array, lam: float = 0.5
) -> tuple[Supertoroid, float, int]:
    """The supertoroid of least EOF (module docstring).

    Args:
        points: (n, 3) contacts [m, world]; normals: (n, 3) outward unit normals.
        lam: weight of the normal term (SPEC §2's lambda).

    Returns:
        the fit, its EOF [m^2] and the residual evaluations used.
    """
    from scipy.optimize import least_squares

    lo = np.array([-np.inf] * 3 + [EPS_MIN, EPS_MIN, np.log(HOLE_MIN - 1.0)] + [-np.inf] * 6)
    hi = np.array([np.inf] * 3 + [EPS_MAX, EPS_MAX, np.log(HOLE_MAX - 1.0)] + [np.inf] * 6)

    def residuals(x: Array) -> Array:
        hole = float(np.clip(1.0 + np.exp(x[5]), HOLE_MIN, HOLE_MAX))
        return _residuals(np.exp(x[0:3]), np.clip(x[3:5], EPS_MIN, EPS_MAX), hole,
                          rotvec_to_matrix(x[6:9]), x[9:12], points, normals, lam)  # fmt: skip

    def run(x0: Array, evaluations: int) -> Any:
        return least_squares(residuals, np.clip(x0, lo + 1e-9, hi - 1e-9), bounds=(lo, hi),
                             method="trf", max_nfev=evaluations, x_scale="jac")  # fmt: skip

    # every start a few steps, then the most promising ones to convergence
    first = sorted((run(x0, SCREEN_EVALUATIONS) for x0 in _starts(points)),
                   key=lambda r: float(np.mean(r.fun**2)))  # fmt: skip
    used = sum(int(r.nfev) for r in first)
    best, best_eof = None, np.inf
    for screened in first[:KEPT_STARTS]:
        end = run(screened.x, MAX_EVALUATIONS)
        used += int(end.nfev)
        eof = float(np.mean(end.fun**2))
        if eof < best_eof:
            best, best_eof = _unpack(end.x), eof
    evaluations = used * (1 + N_TOROID_PARAMS)  # each step's Jacobian by forward differences
    assert best is not None
    return best, best_eof, evaluations


def _misfit(solid: Solid, points: Array, normals: Array, sigma_distance: float,
            sigma_normal: float) -> Array:  # fmt: skip
    """(n,) each contact's z^2 against a solid: distance and normal chord over their noise
    levels (multi's criterion)."""
    distance, angle = solid.contact_errors(points, normals)
    chord = 2.0 * np.sin(np.radians(angle) / 2.0)
    return (distance / sigma_distance) ** 2 + (chord / sigma_normal) ** 2


def holed_cost(solid: Solid, points: Array, normals: Array, sigma_distance: float,
               sigma_normal: float) -> float:  # fmt: skip
    """Multi's robust criterion of a candidate solid (module docstring): 13 parameters a
    superquadric part, 12 a ring."""
    return _cost(solid, _misfit(solid, points, normals, sigma_distance, sigma_normal))


def _cost(solid: Solid, z2: Array) -> float:
    """:func:`holed_cost` from the contacts' misfits `z2` (n,) against `solid`."""
    from hapticsim.fitting.multi import CAP
    from hapticsim.geometry.superquadric import N_PARAMS

    params = sum(N_TOROID_PARAMS if p.kind == "supertoroid" else N_PARAMS
                 for p in solid.components)  # fmt: skip
    return float(np.sum(np.minimum(z2, CAP**2)) + params * np.log(len(z2)))


def inner_share(ring: Supertoroid, points: Array, normals: Array) -> float:
    """The share of contacts on the ring's inner wall: nearer the axis than the tube's centre
    line, with normals facing the axis (their radial part below -0.5): where a hole was
    touched. (A cylinder's pin-hole ring has contacts near the axis on its caps, whose normals
    run along the axis.)"""
    b = ring.to_body(points)
    nb = np.asarray(normals) @ ring.rotation
    r = tube_coordinates(b, ring.a, ring.eps, ring.hole)[0]
    rho = np.maximum(np.hypot(b[:, 0], b[:, 1]), 1e-12)
    radial = (nb[:, 0] * b[:, 0] + nb[:, 1] * b[:, 1]) / rho
    return float(np.mean((r < ring.hole) & (radial < -0.5)))


def choose_holed(
    union: Any, points: Array, normals: Array, sigma_distance: float, sigma_normal: float,
    lam: float = 0.5,
) -> tuple[Solid, dict[str, Any]]:  # fmt: skip
    """The solid of least cost among multi's union and the candidates with a ring (module
    docstring); and the record of every candidate's cost and inner share.

    The candidates with a ring: one ring on all contacts; the union's part that explains its
    contacts worst (the largest summed misfit, with at least :data:`MIN_RING_CONTACTS` contacts
    nearest it) replaced by a ring fitted to those contacts; and the union with a ring added,
    fitted to the contacts it explains worst (their z^2 above ``(CAP / 2)^2``), where there are
    that many. A ring must have :data:`MIN_INNER_SHARE` of its own contacts on its inner wall and
    at most :data:`RING_OUTSIDE_SHARE` of its volume beyond the contacts' box (module
    docstring).

    Returns:
        the chosen solid, and ``{"costs": {name: cost}, "inner_share": {name: share},
        "outside_share": {name: share of the ring's volume beyond the box}, "chosen": name,
        "evaluations": the rings' residual evaluations}``.
    """
    from hapticsim.fitting.multi import CAP, REACH
    from hapticsim.geometry.union import SuperquadricUnion

    parts = tuple(union.components)
    rings: dict[str, tuple[Solid, Supertoroid, Array]] = {}
    used = 0

    def ring_on(mask: Array) -> Supertoroid:
        nonlocal used
        ring, _, evaluations = fit_supertoroid(points[mask], normals[mask], lam)
        used += evaluations
        return ring

    every = np.ones(len(points), dtype=bool)
    ring = ring_on(every)
    rings["supertoroid"] = (ring, ring, every)
    misfit = _misfit(union, points, normals, sigma_distance, sigma_normal)
    z2 = np.minimum(misfit, CAP**2)
    if len(parts) > 1:  # the part that explains its contacts worst (by their summed misfit)
        owner = union.part_of(points)
        k = int(np.argmax(np.bincount(owner, weights=z2, minlength=len(parts))))
        mine = owner == k
        if np.count_nonzero(mine) >= MIN_RING_CONTACTS:
            ring = ring_on(mine)
            others = parts[:k] + (ring,) + parts[k + 1:]
            rings[f"part {k} a ring"] = (SuperquadricUnion(others), ring, mine)
    worst = z2 > (CAP / 2) ** 2
    if np.count_nonzero(worst) >= MIN_RING_CONTACTS:
        ring = ring_on(worst)
        rings["a ring added"] = (SuperquadricUnion((*parts, ring)), ring, worst)
    costs = {"union": _cost(union, misfit)}
    inner: dict[str, float] = {}
    for name, (solid, ring, mine) in rings.items():
        costs[name] = holed_cost(solid, points, normals, sigma_distance, sigma_normal)
        inner[name] = inner_share(ring, points[mine], normals[mine])
    size = float(np.max(np.linalg.norm(points - points.mean(axis=0), axis=1)))
    lo, hi = points.min(axis=0) - REACH * size, points.max(axis=0) + REACH * size
    outside: dict[str, float] = {}
    for name, (_, ring, _) in rings.items():
        inside = ring.sample_interior(2000, np.random.default_rng(0))
        outside[name] = float(np.mean(np.any((inside < lo) | (inside > hi), axis=1)))
    fits = [n for n in rings
            if inner[n] >= MIN_INNER_SHARE and outside[n] <= RING_OUTSIDE_SHARE]  # fmt: skip
    eligible = ["union", *fits]
    name = min(eligible, key=lambda n: costs[n])
    chosen = union if name == "union" else rings[name][0]
    return chosen, {"costs": costs, "inner_share": inner, "outside_share": outside,
                    "chosen": name, "evaluations": used}  # fmt: skip


__all__ = ["MIN_INNER_SHARE", "MIN_RING_CONTACTS", "N_TOROID_PARAMS", "RING_OUTSIDE_SHARE",
           "choose_holed", "fit_supertoroid", "holed_cost", "inner_share",
           "toroid_residuals"]  # fmt: skip
