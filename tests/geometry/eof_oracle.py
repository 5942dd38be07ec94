"""Test oracle: the vectorised numpy error-of-fit kernel (SPEC §2, paper eqs. 7-9).

This was hapticsim's EOF before the compiled kernel (``hapticsim/geometry/eof_compiled.py``)
replaced it; it stays here, outside the package, only so that the tests can check the compiled
kernel against an independent implementation (the two agree to 1e-10 relative). Its own
description follows.

Error of fit of contact data to superquadrics (SPEC §2, paper eqs. 7-9), vectorised.

One call evaluates a whole population: the pose and shape arrays carry leading batch
dimensions ``...`` that broadcast against the (n, 3) contacts.

Speed: the batch is flattened to P superquadrics and
evaluated as (P, n) blocks. One small matrix product moves points and normals of all P bodies into
their body frames at once (homogeneous coordinates fold in the centre), the inside-outside
function is evaluated once in the log domain (:func:`functions.log_inside_outside_terms`) and
shared by the radial distance D1 and the model normal, and the normal distance uses
``|n - n'|^2 = 2 - 2 n.n'`` for unit vectors. Large populations are processed in blocks of
``_BLOCK`` bodies so the temporaries stay in cache.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import DEFAULT_LAMBDA, MIN_TAPER_FACTOR
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import functions as fn

Array = NDArray[np.float64]

#: Ways of measuring the contact distance D1 (see :func:`contact_residuals`).
DISTANCES: tuple[str, ...] = ("untapered", "tapered")
#: Bodies per block: (P, n) temporaries of ~100 x 150 doubles stay in the L2 cache.
_BLOCK = 128


def contact_residuals(
    points_world: Array,
    normals_world: Array | None,
    a: Array,
    eps: Array,
    taper: Array,
    rotation: Array,
    center: Array,
    lam: float = DEFAULT_LAMBDA,
    distance: str = "untapered",
) -> Array:
    """Per-contact residuals ``r_i = |D1_i| + lambda * sigma * D2_i`` (paper eq. 9).

    ``sum(r_i^2) / n`` is the EOF. Without normals, ``r_i = |D1_i|``.

    Args:
        points_world: (n, 3) float, contact points [m].
        normals_world: (n, 3) float normals (normalised here), or None.
        a: (..., 3) [m]; eps: (..., 2); taper: (..., 2); rotation: (..., 3, 3); center: (..., 3).
        lam: weight lambda of the normal term.
        distance: how D1 is measured, one of :data:`DISTANCES`. ``"untapered"`` (SPEC §2):
            ``|p| |1 - s|`` with p the untapered body-frame point and ``s = F(p)^(-eps1/2)``.
            ``"tapered"``: the world distance between the contact and the same ray's surface
            point ``s p`` mapped back through the taper. The two agree without taper; with it,
            the untapered distance shrinks by about the taper factor ``1 + t z / a3`` where the
            solid is wide, which rewards extreme tapers on noisy data.

    Returns:
        (..., n) float residuals [m].
    """
    if distance not in DISTANCES:
        raise InvalidInputError(f"`distance` must be one of {DISTANCES}, got {distance!r}")
    points = np.asarray(points_world, dtype=np.float64)
    a = np.asarray(a, dtype=np.float64)
    eps = np.asarray(eps, dtype=np.float64)
    taper = np.asarray(taper, dtype=np.float64)
    rotation = np.asarray(rotation, dtype=np.float64)
    center = np.asarray(center, dtype=np.float64)
    batch = np.broadcast_shapes(
        a.shape[:-1], eps.shape[:-1], taper.shape[:-1], rotation.shape[:-2], center.shape[:-1]
    )
    count = int(np.prod(batch, dtype=np.int64))

    def flat(x: Array, tail: tuple[int, ...]) -> Array:
        return np.ascontiguousarray(np.broadcast_to(x, batch + tail).reshape((count, *tail)))

    homog = contacts_homogeneous(points, normals_world)
    r = population_residuals(
        homog,
        normals_world is not None,
        flat(a, (3,)),
        flat(eps, (2,)),
        flat(taper, (2,)),
        flat(rotation, (3, 3)),
        flat(center, (3,)),
        lam,
        tapered=distance == "tapered",
    )
    return r.reshape((*batch, points.shape[0]))


def error_of_fit(
    points_world: Array,
    normals_world: Array | None,
    a: Array,
    eps: Array,
    taper: Array,
    rotation: Array,
    center: Array,
    lam: float = DEFAULT_LAMBDA,
    distance: str = "untapered",
) -> Array:
    """EOF ``D = mean(r_i^2)`` (SPEC §2), shape ``...`` of the parameters [m^2].

    Arguments as :func:`contact_residuals`.
    """
    r = contact_residuals(
        points_world, normals_world, a, eps, taper, rotation, center, lam, distance
    )
    return np.mean(r**2, axis=-1)


def contacts_homogeneous(points_world: Array, normals_world: Array | None) -> Array:
    """Contacts as one (4, n) or (4, 2n) homogeneous block for :func:`population_residuals`.

    Points get a 1 in the fourth row, normals (normalised to unit length) a 0, so one matrix
    product applies rotation and translation to the points and only the rotation to the normals.

    Args:
        points_world: (n, 3) float [m]; normals_world: (n, 3) float or None.

    Returns:
        (4, n) float, or (4, 2n) with the normals in the last n columns.
    """
    points = np.asarray(points_world, dtype=np.float64)
    n = points.shape[0]
    cols = n if normals_world is None else 2 * n
    homog = np.zeros((4, cols))
    homog[:3, :n] = points.T
    homog[3, :n] = 1.0
    if normals_world is not None:
        normals = np.asarray(normals_world, dtype=np.float64)
        homog[:3, n:] = (normals / np.linalg.norm(normals, axis=1, keepdims=True)).T
    return homog


def population_residuals(
    homog: Array,
    with_normals: bool,
    a: Array,
    eps: Array,
    taper: Array,
    rotation: Array,
    center: Array,
    lam: float = DEFAULT_LAMBDA,
    workspace: ResidualWorkspace | None = None,
    tapered: bool = False,
) -> Array:
    """Residuals of eq. (9) for a flat population of P superquadrics (the fast path).

    Args:
        homog: contacts from :func:`contacts_homogeneous`, (4, n) or (4, 2n).
        with_normals: whether ``homog`` holds normals in its last n columns.
        a: (P, 3) [m]; eps: (P, 2); taper: (P, 2); rotation: (P, 3, 3); center: (P, 3) [m].
        lam: weight lambda of the normal term.
        tapered: measure D1 on the tapered solid (``distance="tapered"`` of
            :func:`contact_residuals`) instead of in the untapered frame (SPEC §2).
        workspace: reusable temporaries; pass one when calling repeatedly (a fitter does), so
            no large array is allocated per call. Not thread-safe: one per thread.

    Returns:
        (P, n) float residuals [m] (a new array).
    """
    count = a.shape[0]
    n = homog.shape[1] // 2 if with_normals else homog.shape[1]
    work = ResidualWorkspace() if workspace is None else workspace
    out = np.empty((count, n))
    for start in range(0, count, _BLOCK):
        sl = slice(start, min(start + _BLOCK, count))
        _residual_block(
            homog, n, with_normals, a[sl], eps[sl], taper[sl], rotation[sl], center[sl], lam,
            work.buffers(sl.stop - sl.start, n), out[sl], tapered,
        )  # fmt: skip
    return out


class ResidualWorkspace:
    """Preallocated temporaries of :func:`population_residuals`, reused across calls.

    Allocating a dozen fresh (P, n) arrays per call costs as much as the arithmetic (the C
    allocator hands large blocks back to the system and page-faults them in again).
    """

    #: Most block shapes kept (a fitter alternates a few: 1 vector, 13 for a Jacobian, ...).
    MAX_SHAPES = 6

    def __init__(self) -> None:
        self._bufs: dict[tuple[int, int], tuple[Array, Array, Array]] = {}

    def buffers(self, count: int, n: int) -> tuple[Array, Array, Array]:
        """(body (2, 3P, n), terms (7, P, n), scratch (8, P, n)) for P bodies and n contacts."""
        key = (count, n)
        if key not in self._bufs:
            if len(self._bufs) >= self.MAX_SHAPES:
                self._bufs.pop(next(iter(self._bufs)))
            self._bufs[key] = (
                np.empty((2, 3 * count, n)),
                np.empty((7, count, n)),
                np.empty((8, count, n)),
            )
        return self._bufs[key]


def _residual_block(
    homog: Array,
    n: int,
    with_normals: bool,
    a: Array,
    eps: Array,
    taper: Array,
    rotation: Array,
    center: Array,
    lam: float,
    buffers: tuple[Array, Array, Array],
    out: Array,
    tapered: bool,
) -> None:
    """:func:`population_residuals` for one block of P bodies into `out` (P, n)."""
    count = a.shape[0]
    body2d, terms, scratch = buffers
    # Row j*P + k of `pose` maps a homogeneous world contact to coordinate j of body k:
    # p_body_j = R[:, j] . (x - x0); x, y, z and the normals come out as contiguous (P, n).
    pose = np.empty((3, count, 4))
    pose[:, :, :3] = rotation.transpose(2, 0, 1)
    pose[:, :, 3] = -np.einsum("ki,kij->jk", center, rotation)
    pose2d = pose.reshape(3 * count, 4)
    np.matmul(pose2d, homog[:, :n], out=body2d[0])
    x, y, z = body2d[0].reshape(3, count, n)
    if with_normals:
        np.matmul(pose2d[:, :3], homog[:3, n:], out=body2d[1])
        mx, my, mz = body2d[1].reshape(3, count, n)
    fx, fy, xs, ys, lu, lv, lw, t0 = scratch

    e1, e2 = eps[:, 0:1], eps[:, 1:2]
    inv_a = 1.0 / a
    taper_a3 = taper * inv_a[:, 2:3]  # t / a3
    # Untaper (paper eq. 2): divide x, y by 1 + t z / a3 (clipped beyond an apex).
    for f, t, coord, sym in ((fx, taper_a3[:, 0:1], x, xs), (fy, taper_a3[:, 1:2], y, ys)):
        np.multiply(z, t, out=f)
        f += 1.0
        if f.min() < MIN_TAPER_FACTOR:
            np.maximum(f, MIN_TAPER_FACTOR, out=f)
        np.divide(coord, f, out=sym)
    fn.log_abs_scaled(xs, inv_a[:, 0:1], out=lu)
    fn.log_abs_scaled(ys, inv_a[:, 1:2], out=lv)
    fn.log_abs_scaled(z, inv_a[:, 2:3], out=lw)
    fn.log_inside_outside_terms(lu, lv, lw, e1, e2, out=terms)
    # Is any x, y or z exactly 0 (then its log is at the floor)? Only then look for zeros.
    zeros = with_normals and bool(scratch[4:7].min() < fn.LOG_ZERO)
    log_f = terms[fn.TERM_LOG_F]

    # D1 = |p| |1 - F^(-eps1/2)| (SPEC §2), p the untapered point.
    d1 = out
    np.multiply(log_f, -0.5 * e1, out=d1)
    np.exp(d1, out=d1)
    d1 -= 1.0
    norm = t0  # lu, lv, lw are free from here on
    if tapered:
        # The ray's surface point q = s p (untapered) maps back through the taper, so the world
        # distance is |1 - s| |(x_s (1 + t_x z (1 + s) / a3), y_s (1 + t_y z (1 + s) / a3), z)|.
        np.add(d1, 2.0, out=lu)  # 1 + s, as d1 holds s - 1 here
        lu *= z
        for k, (sym, square) in enumerate(((xs, norm), (ys, lw))):
            np.multiply(lu, taper_a3[:, k : k + 1], out=lv)
            lv += 1.0
            lv *= sym
            np.multiply(lv, lv, out=square)
        norm += lw
    else:
        np.multiply(xs, xs, out=norm)
        np.multiply(ys, ys, out=lu)
        norm += lu
    np.multiply(z, z, out=lu)
    norm += lu
    np.sqrt(norm, out=norm)
    np.abs(d1, out=d1)
    d1 *= norm
    if not with_normals:
        return

    # Model normal J_t^-T grad F (eqs. 3-4) in the body frame, unnormalised.
    shares = fn.gradient_shares(terms, out=scratch[4:7])  # over lu, lv, lw
    nx, ny, nz = normal = (scratch[2], scratch[3], scratch[7])  # over xs, ys, |p|
    fn.tapered_normals(shares, x, y, z, fx, fy, a, taper, normal, terms[6], zeros)
    # D2 = |m - n'|^2 = 2 - 2 m.n' / |n'| for the unit data normal m (eq. 8).
    dot, length, t1 = scratch[4], scratch[5], scratch[6]
    np.multiply(nx, mx, out=dot)
    np.multiply(ny, my, out=t1)
    dot += t1
    np.multiply(nz, mz, out=t1)
    dot += t1
    np.multiply(nx, nx, out=length)
    np.multiply(ny, ny, out=t1)
    length += t1
    np.multiply(nz, nz, out=t1)
    length += t1
    np.sqrt(length, out=length)
    length += 1e-300
    dot /= length
    np.subtract(1.0, dot, out=dot)
    np.abs(dot, out=dot)  # >= 0 up to rounding
    dot *= (2.0 * lam / 3.0) * np.sum(a, axis=1, keepdims=True)  # 2 lambda sigma
    d1 += dot
