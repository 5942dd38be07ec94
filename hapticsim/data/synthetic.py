"""Synthetic haptic exploration data sets of the paper (Section III-A, SPEC §5).

A data set merges stripes and patches (:mod:`hapticsim.data.patterns`) placed like the fingertips
of a hand during a short exploration after a first touch, then adds Gaussian noise
(:mod:`hapticsim.data.noise`). Patterns are given in the body frame by the spherical angles of the
uniform parametrisation (eq. 6): in scaled coordinates ``(x/a1, y/a2, z/a3)`` a direction
``(eta, omega)`` is ``(cos eta cos omega, cos eta sin omega, sin eta)``, so the face centres of a
box are at ``omega = 0, pi/2, ...`` (``eta = 0``) and ``eta = +-pi/2``, and its corners at
``omega = +-pi/4, +-3pi/4``, ``eta = +-atan(1/sqrt 2)``, whatever the semi-axes and the taper.

Prismatic bodies (``eps1 < 0.5``: boxes, cylinders), a grasp-like exploration:

- thumb: a patch on the corner (-x, -y, +z), covering the three faces that meet there;
- index, middle, ring fingers: three parallel stripes sweeping the opposite side face +x from
  bottom to top, crossing its lower and upper edges onto the faces -z and +z;
- little finger: a slanted stripe from the +x face around the vertical edge onto the +y face,
  rising as it goes.

Every pair of opposite faces is touched on both sides, so the extents are determined, and the
side faces are touched over a range of heights (the thumb's corner against the fingers' sweep),
so the taper is too. Most of the surface is never touched: the -x and -y faces are only touched
near the thumb's corner, and neither the bottom face nor the other corners are explored.

Round bodies (``eps1 >= 0.5``, the ellipsoid): patches only, a thumb on the -x side opposed by
index and middle fingertips on the +x side, one above and one below the equator.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import as_generator, finite_float, positive_int
from hapticsim.constants import MAX_CONTACTS
from hapticsim.data.io import Contacts
from hapticsim.data.noise import add_noise
from hapticsim.data.patterns import Patch, Pattern, Stripe, sample_patterns
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import N_PARAMS, Superquadric
from hapticsim.geometry.superquadric import superquadric_arg
from hapticsim.geometry.union import SuperquadricUnion

Array = NDArray[np.float64]

#: Smallest data set: one contact per model parameter (13).
MIN_COUNT: int = N_PARAMS
#: eps1 below which a body counts as prismatic (flat faces and edges, paper III-A).
PRISMATIC_EPS1: float = 0.5
#: Latitude of a box corner in the uniform parametrisation: atan(1/sqrt(2)) [rad].
CORNER_ETA: float = float(np.arctan(1.0 / np.sqrt(2.0)))

_D = np.pi / 180.0  # one degree [rad]

# (name, weight, factory(count) -> pattern). Weights set each pattern's share of the contacts.
_PRISMATIC: tuple[tuple[str, float, Any], ...] = (
    (
        "thumb_corner",
        0.34,
        lambda n: Patch(
            eta=(CORNER_ETA - 20 * _D, CORNER_ETA + 20 * _D),
            omega=(-135 * _D - 22 * _D, -135 * _D + 22 * _D),
            count=n,
        ),
    ),
    ("index_stripe", 0.17, lambda n: Stripe((-62 * _D, -17 * _D), (62 * _D, -17 * _D), n)),
    ("middle_stripe", 0.17, lambda n: Stripe((-62 * _D, 0.0), (62 * _D, 0.0), n)),
    ("ring_stripe", 0.17, lambda n: Stripe((-62 * _D, 17 * _D), (62 * _D, 17 * _D), n)),
    ("little_stripe", 0.15, lambda n: Stripe((-35 * _D, 25 * _D), (20 * _D, 115 * _D), n)),
)
_ROUND: tuple[tuple[str, float, Any], ...] = (
    ("thumb_patch", 0.34, lambda n: Patch((-25 * _D, 30 * _D), (150 * _D, 210 * _D), n)),
    ("index_patch", 0.33, lambda n: Patch((10 * _D, 55 * _D), (-30 * _D, 30 * _D), n)),
    ("middle_patch", 0.33, lambda n: Patch((-55 * _D, -10 * _D), (0.0, 65 * _D), n)),
)


def _allocate(count: int, weights: list[float]) -> list[int]:
    """Split `count` by `weights` (largest remainder, ties to the earlier pattern)."""
    share = count * np.asarray(weights) / np.sum(weights)
    base = np.floor(share).astype(int)
    order = np.argsort(-(share - base), kind="stable")
    base[order[: count - int(base.sum())]] += 1
    return [int(b) for b in base]


def is_prismatic(truth: Superquadric) -> bool:
    """True for bodies with flat faces and edges (``eps1 < 0.5``): stripes and a corner patch."""
    return bool(superquadric_arg(truth, "truth").eps[0] < PRISMATIC_EPS1)


def paper_patterns(truth: Superquadric, count: int = 150) -> tuple[tuple[str, Pattern], ...]:
    """The named exploration patterns of :func:`paper_dataset` for a body (module docstring).

    Args:
        truth: the body; its eps1 selects the prismatic or the round layout.
        count: total number of contacts, >= 13, split over the patterns by fixed shares.

    Returns:
        ``(name, pattern)`` pairs; the pattern id of a contact is the index in this tuple.
    """
    layout = _PRISMATIC if is_prismatic(truth) else _ROUND
    n = positive_int(count, "count", minimum=MIN_COUNT, maximum=MAX_CONTACTS)
    counts = _allocate(n, [w for _, w, _ in layout])
    return tuple((name, make(k)) for (name, _, make), k in zip(layout, counts, strict=True))


def paper_dataset(
    truth: Superquadric,
    noise: float = 0.1,
    rng: np.random.Generator | int | None = None,
    count: int = 150,
) -> Contacts:
    """A synthetic exploration data set of `truth` with noise (paper III-A, SPEC §5).

    The patterns are those of :func:`paper_patterns`, rendered with the uniform parametrisation
    (eq. 6) in the body frame of `truth` and posed with it; then point noise of std
    ``noise * mean(a)`` [m] and normal noise of std ``noise`` are added (SPEC §5). One generator
    draws the patch directions first, then the point noise, then the normal noise: the same seed
    gives the same arrays, bit for bit.

    Args:
        truth: the true superquadric.
        noise: relative noise level sigma_N, finite and >= 0 (paper default 0.1).
        rng: seed or generator.
        count: number of contacts, >= 13 (paper default 150).

    Returns:
        Contacts with noisy ``points`` (count, 3) [m, world] and unit ``normals`` (count, 3), and
        in ``extra``: ``points_clean`` and ``normals_clean`` (on the surface of `truth`) and
        ``pattern`` (count,) int, the index of the contact's pattern in :func:`paper_patterns`.
    """
    truth = superquadric_arg(truth, "truth")
    sigma = finite_float(noise, "noise", low=0.0)
    if isinstance(count, (int, np.integer)) and not isinstance(count, bool) and count < MIN_COUNT:
        raise InvalidInputError(
            f"`count` must be >= {MIN_COUNT} (one contact per model parameter), got {count}"
        )
    patterns = [p for _, p in paper_patterns(truth, count)]
    gen = as_generator(rng)
    points_clean, normals_clean, pattern = sample_patterns(truth, patterns, gen)
    points, normals = add_noise(points_clean, normals_clean, sigma, float(np.mean(truth.a)), gen)
    return Contacts(
        points=points,
        normals=normals,
        extra={"points_clean": points_clean, "normals_clean": normals_clean, "pattern": pattern},
    )


def synthetic_dataset(
    truth: Any,
    noise: float = 0.1,
    rng: np.random.Generator | int | None = None,
    count: int = 150,
) -> Contacts:
    """A synthetic data set of a superquadric (:func:`paper_dataset`) or of a union of them.

    A union's contacts are the paper's patterns on each of its parts, each part's share of the
    contacts in proportion to its surface area outside the other parts; a contact that lands
    inside another part (where the union has no surface) is dropped, and more are drawn until
    `count` are left, of which `count` are kept at random (in pattern order). The noise is that
    of SPEC §5 at the union's :attr:`~hapticsim.geometry.solid.Solid.size`. ``extra`` adds
    ``part`` (n,) int, the part each contact was drawn on; ``pattern`` numbers the patterns of
    part k from ``k * 5``.

    Args:
        truth: a :class:`~hapticsim.geometry.Superquadric` or a
            :class:`~hapticsim.geometry.union.SuperquadricUnion`.
        noise, rng, count: as :func:`paper_dataset`.

    Raises:
        InvalidInputError: another kind of solid (meshes: explore them with the hand), or bad
            arguments.
    """

    if isinstance(truth, Superquadric):
        return paper_dataset(truth, noise, rng, count)
    if not isinstance(truth, SuperquadricUnion):
        raise InvalidInputError(
            "synthetic contacts are drawn on superquadrics and unions of them (the paper's "
            f"patterns), got {type(truth).__name__}: explore a mesh with the hand instead"
        )
    if not all(isinstance(p, Superquadric) for p in truth.parts):
        raise InvalidInputError(
            "synthetic contacts are drawn on superquadrics (the paper's patterns): this union has "
            "a ring part; explore it with the hand instead"
        )
    sigma = finite_float(noise, "noise", low=0.0)
    n = positive_int(count, "count", minimum=MIN_COUNT, maximum=MAX_CONTACTS)
    gen = as_generator(rng)
    parts = truth.parts
    # each part's visible share of the surface, from a surface sample of the union
    _, visible = _visible_parts(truth, gen)
    weights = np.maximum(np.bincount(visible, minlength=len(parts)), 1).astype(float)
    factor = 1.0
    while True:
        counts = _allocate(int(np.ceil(n * factor)), list(weights))
        chunks = []
        for k, (part, c) in enumerate(zip(parts, counts, strict=True)):
            if c < 1:
                continue
            patterns = [p for _, p in paper_patterns(part, max(c, MIN_COUNT))]
            pts, nrm, pat = sample_patterns(part, patterns, gen)
            keep = np.ones(len(pts), dtype=bool)
            for j, other in enumerate(parts):
                if j != k:
                    keep &= other.outside(pts)
            chunks.append((pts[keep], nrm[keep], pat[keep] + 5 * k, np.full(keep.sum(), k)))
        total = sum(len(c[0]) for c in chunks)
        if total >= n:
            break
        factor *= 1.5 * n / max(total, 1)
    pts, nrm, pat, part = (np.concatenate([c[i] for c in chunks]) for i in range(4))
    pick = np.sort(gen.choice(len(pts), size=n, replace=False))
    points_clean, normals_clean = pts[pick], nrm[pick]
    points, normals = add_noise(points_clean, normals_clean, sigma, truth.size, gen)
    return Contacts(
        points=points,
        normals=normals,
        extra={"points_clean": points_clean, "normals_clean": normals_clean,
               "pattern": pat[pick], "part": part[pick]},  # fmt: skip
    )


def _visible_parts(truth: Any, gen: np.random.Generator) -> tuple[Array, NDArray[np.int64]]:
    """A surface sample of a union and the part each point lies on."""
    pts, _ = truth.sample_surface(4000, gen)
    return pts, truth.part_of(pts)


__all__ = [
    "CORNER_ETA",
    "MIN_COUNT",
    "PRISMATIC_EPS1",
    "is_prismatic",
    "paper_dataset",
    "paper_patterns",
    "synthetic_dataset",
]
