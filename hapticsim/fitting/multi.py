"""``method="multi"``: a union of 1..K superquadrics fitted to contacts with normals (SPEC §10).

The paper names decomposition into several superquadrics as its future work; published
multi-superquadric fitters start from dense point clouds. Here the data are a hand's sparse,
one-sided contacts, so every step leans on the normals and on what one part's contacts say about
the others' (a contact lies on the union's surface: outside every other part).

1. **One part**: nH on all contacts (:func:`hapticsim.fitting.fit`, the caller's seed): the
   one-part candidate, and the result whenever one part is chosen (then the fit *is* nH's).
2. **K parts**, K = 2, 3, ... while the criterion keeps improving (or the K asked for):
   starting segmentations of the contacts, each refined by alternation (*k-superquadrics*):

   - *starts*: k-means (scipy's ``kmeans2``, k-means++ seeding from the caller's generator) on
     the contacts' positions and normals (``[p / s, w n]``, s the data size, w
     :data:`NORMAL_FEATURE`), and the best (K-1)-part union with its worst-fitting part split
     in two by the same k-means on that part's contacts; when neither gives a union the
     guards admit, up to :data:`RETRY_STARTS` more k-means starts are tried before the count
     is given up;
   - each segment's part starts as nH on its contacts (:data:`PART_BUDGET` evaluations);
   - *alternation* (:data:`ROUNDS` rounds): every contact goes to the part that explains it
     best (the smallest normalised misfit, below), then every part is refined by nML's
     Levenberg-Marquardt (the likelihood of :mod:`hapticsim.fitting.likelihood`: orthogonal
     distances and normals, a robust loss, weak priors) on its contacts, with the *other*
     parts' contacts, moved out along their normals by two noise levels, as free-space points
     it must not swallow: this is the joint refinement of the union (each contact on the union's
     surface is outside every part but its own), done part by part because, with the
     assignment fixed, the union's residuals split that way. A part left with fewer than
     :data:`MIN_PART_CONTACTS` contacts ends the start. No part may reach farther than
     :data:`REACH` data sizes beyond the box of the contacts and of the one-part fit: nothing
     measured says a part is there (one-sided contacts leave a part's far side free, and a
     part has the freedom to fill it; the one-part fit has less). Points on that box's faces
     are free space in the refinements, and a union with a part that still has more than
     :data:`OUTSIDE_SHARE` of its volume outside it is refused. Nor may a part reach where
     nothing supports it: a side of a part along one of its axes is supported when the part is
     touched from there (a contact normal within 60 degrees of the direction), or when the
     part's end there lies inside another part (a bar's hidden end in the other bar) or within
     the contacts' box (:data:`SUPPORT_MARGIN`); an end on an unsupported side is retracted to
     :data:`CLIP_MARGIN` data sizes past the part's farthest contact along that axis (a
     hammer's handle whose butt nobody touched ends where its contacts end, rather than the
     union being refused, which kept half the hammers one part).
3. **The criterion** (a robust BIC): for a union U of K parts,
   ``cost(U) = sum_i min(z_i^2, CAP^2) + K P ln n``, ``P = 13`` parameters a part, with
   ``z_i^2 = (d_i / sigma_d)^2 + (|e_i| / sigma_n)^2``, ``d_i`` the contact's first-order signed
   distance to the union (the smallest over its parts) and ``e_i`` its normal's difference from
   that part's normal; sigma_d and sigma_n are the trimmed RMS of the residuals of the union
   with the most parts fitted so far (at least :data:`DISTANCE_FLOOR` of the data size and
   :data:`NORMAL_FLOOR` rad), or from the given noise. The union of least cost is the result: a
   part must explain about ``P ln n`` (74 for 300 contacts) squared noise levels of misfit
   that the others leave, or it is not worth its parameters; truncating at ``CAP`` keeps a few
   outliers from buying a part.

The result is a :class:`~hapticsim.fitting.result.FitResult` whose ``solid`` is the union
(always a :class:`~hapticsim.geometry.union.SuperquadricUnion`, of one part when one is chosen)
and whose ``superquadric`` is the one-part nH fit; ``selection`` holds every candidate's cost.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError
from hapticsim.fitting.least_squares import least_squares_run
from hapticsim.fitting.likelihood import TRIM, TRIM_FACTOR, Likelihood
from hapticsim.fitting.ml import MLOptions, ml_objective
from hapticsim.fitting.problem import Problem, problem_residuals
from hapticsim.geometry.eof import ContactSet
from hapticsim.geometry.superquadric import N_PARAMS, Superquadric

Array = NDArray[np.float64]

#: Most parts ``parts="auto"`` tries.
MAX_PARTS: int = 4
#: Fewest contacts a part keeps (a superquadric has 11 shape and pose parameters; a face needs a
#: few more to be told from noise).
MIN_PART_CONTACTS: int = 20
#: Evaluations of each segment's first nH fit.
PART_BUDGET: int = 1000
#: Evaluations of each part's refinement in a round.
REFINE_BUDGET: int = 250
#: Rounds of reassignment and refinement per start.
ROUNDS: int = 3
#: Further k-means starts a part count tries when none of its usual starts gave a union the
#: guards admit, before the search gives up on that count (a hammer's handle and head: a
#: k-means split that cuts the handle makes a part that leaves the box; explored by the
#: uncertainty policy, 300 contacts, 4 of 6 hammers stayed one part with the two starts alone,
#: IoU 0.52-0.56 against 0.98 split, and 3 of 6 with the retries; since untouched ends are
#: retracted rather than refused (:func:`_clip_unsupported`), 0 of 8, docs/objects.md).
RETRY_STARTS: int = 4
#: Weight of the normals against positions (in data sizes) in the k-means features.
NORMAL_FEATURE: float = 0.3
#: Normalised misfit at which a contact stops counting more (the criterion's truncation).
CAP: float = 4.0
#: Smallest distance noise level, as a share of the data size.
DISTANCE_FLOOR: float = 0.005
#: Smallest normal noise level [rad].
NORMAL_FLOOR: float = 0.05
#: How far the other parts' contacts are moved out along their normals, in distance noise
#: levels, before they become a part's free-space points.
FREE_OFFSET: float = 2.0
#: How far a part may reach beyond the box of the contacts and of the one-part fit, as a share
#: of the data size: farther, and nothing measured says it is there (a union is refused).
REACH: float = 0.15


@dataclass
class Candidate:
    """A union of parts fitted to the contacts, and the fit of each contact to it.

    Attributes:
        vectors: (K, 13) the parts' parameter vectors.
        owner: (n,) int, the part each contact was last assigned to.
        distance: (n,) the contacts' signed distances to the union [m] (min over its parts).
        normal: (n,) the length of each contact's normal difference from its nearest part's.
        how: how the candidate was found (for the selection record).
    """

    vectors: Array
    owner: NDArray[np.int64]
    distance: Array
    normal: Array
    how: str

    @property
    def parts(self) -> int:
        return int(self.vectors.shape[0])


class _Data:
    """The contacts, their compiled layout and the noise scales of the criterion."""

    def __init__(self, points: Array, normals: Array, free: Array | None,
                 noise: float | None, size_hint: float) -> None:  # fmt: skip
        self.points, self.normals, self.free = points, normals, free
        self.n = len(points)
        self.size = float(np.max(np.linalg.norm(points - points.mean(axis=0), axis=1)))
        self.contacts = ContactSet.from_arrays(points, normals)
        self.problem = Problem.ml(self.contacts, Likelihood(noise=1.0, length=1.0).settings())
        self.given = noise
        self.size_hint = size_hint
        self.evaluations = 0
        self.allowed: Array | None = None  # (2, 3): the box no part may leave
        self.walls: Array | None = None  # free-space points on its faces
        self.sigma_d = self.sigma_n = 0.0
        if noise is not None:
            self.sigma_d = max(noise * size_hint, DISTANCE_FLOOR * self.size)
            self.sigma_n = max(noise, NORMAL_FLOOR)

    def misfit(self, vectors: Array) -> tuple[Array, Array]:
        """Per part and contact: signed distances (K, n) [m] and normal differences (K, n)."""
        rows = problem_residuals(self.contacts, self.problem, vectors)
        n = self.n
        e = rows[:, n : 4 * n].reshape(len(vectors), 3, n)
        return rows[:, :n], np.linalg.norm(e, axis=1)

    def candidate(self, vectors: Array, owner: NDArray[np.int64], how: str) -> Candidate:
        d, e = self.misfit(vectors)
        nearest = np.argmin(d, axis=0)
        cols = np.arange(self.n)
        return Candidate(vectors, owner, d[nearest, cols], e[nearest, cols], how)

    def scales(self, reference: Candidate) -> tuple[float, float]:
        """Noise levels (distance [m], normal) of `reference`'s residuals by a trimmed RMS (the
        :data:`~hapticsim.fitting.likelihood.TRIM` share of the largest left out), floored; the
        given ones when the noise was given."""
        if self.given is not None:
            return self.sigma_d, self.sigma_n
        keep = max(1, int(round((1.0 - TRIM) * self.n)))
        d = np.sort(np.abs(reference.distance))[:keep]
        e = np.sort(reference.normal)[:keep]
        return (max(float(np.sqrt(np.mean(d**2) / TRIM_FACTOR)), DISTANCE_FLOOR * self.size),
                max(float(np.sqrt(np.mean(e**2) / (2.0 * TRIM_FACTOR))), NORMAL_FLOOR))  # fmt: skip

    def set_scales(self, reference: Candidate) -> None:
        """The criterion's noise levels from the residuals of `reference` (unless given)."""
        self.sigma_d, self.sigma_n = self.scales(reference)

    def cost(self, c: Candidate) -> float:
        z2 = (c.distance / self.sigma_d) ** 2 + (c.normal / self.sigma_n) ** 2
        return float(np.sum(np.minimum(z2, CAP**2)) + c.parts * N_PARAMS * np.log(self.n))


def _kmeans(features: Array, k: int, gen: np.random.Generator) -> NDArray[np.int64] | None:
    """Labels (n,) of k clusters of the rows of `features`, or None when one comes out empty."""
    from scipy.cluster.vq import kmeans2

    seed = int(gen.integers(2**31))
    _, labels = kmeans2(features, k, minit="++", seed=seed)
    counts = np.bincount(labels, minlength=k)
    return None if np.any(counts < MIN_PART_CONTACTS) else labels.astype(np.int64)


#: What fits one part: ``(points, normals, budget, generator) -> FitResult`` (nH; the driver's).
PartFit = Callable[[Array, Array, int, np.random.Generator], object]


def _part_fit(
    data: _Data, rows: NDArray[np.int64], gen: np.random.Generator, part_fit: PartFit
) -> Array | None:
    """nH on a segment's contacts, or None where they cannot make a part (too few, flat)."""
    try:
        result = part_fit(data.points[rows], data.normals[rows], PART_BUDGET, gen)
    except InvalidInputError:
        return None
    data.evaluations += int(result.evaluations)  # type: ignore[attr-defined]
    return result.superquadric.to_vector()  # type: ignore[attr-defined]


#: Share of a part's volume that may lie outside the allowed box (a thin tip poking through).
OUTSIDE_SHARE: float = 0.02
#: Free-space points per side of each face of the allowed box.
WALL_GRID: int = 8


def _box_walls(box: Array) -> Array:
    """(6 WALL_GRID^2, 3) points on the faces of a box (2, 3): free space that keeps every part
    inside it while it is refined (the box is then checked again)."""
    lo, hi = box
    t = (np.arange(WALL_GRID) + 0.5) / WALL_GRID
    u, v = (g.ravel() for g in np.meshgrid(t, t))
    out = []
    for axis in range(3):
        a, b = [k for k in range(3) if k != axis]
        for side in (lo[axis], hi[axis]):
            face = np.empty((len(u), 3))
            face[:, axis] = side
            face[:, a] = lo[a] + u * (hi[a] - lo[a])
            face[:, b] = lo[b] + v * (hi[b] - lo[b])
            out.append(face)
    return np.concatenate(out)


#: How far beyond the contacts' box an untouched side of a part may end, in data sizes.
SUPPORT_MARGIN: float = 0.1
#: A part is touched from a side of one of its axes when one of its contacts' normals is within
#: 60 degrees of that direction (cosine above this).
SIDE_COSINE: float = 0.5


#: How far an untouched end of a part may reach beyond that part's farthest contact along its
#: axis, in data sizes, when the end is neither inside the contacts' box nor in another part.
CLIP_MARGIN: float = 0.1
#: Smallest semi-axis a retracted part keeps, in data sizes.
MIN_HALF: float = 0.01


def _clip_unsupported(data: _Data, vectors: Array, owner: NDArray[np.int64]) -> Array:
    """The parts with every unsupported end retracted (a copy of `vectors`).

    A part's side along one of its axes is supported when one of its contacts' normals is
    within 60 degrees of that direction (:data:`SIDE_COSINE`), or when the part's end there
    lies inside another part (a bar's hidden end in the other bar) or within the contacts' box
    (:data:`SUPPORT_MARGIN` data sizes more). Else nothing measured says how far the part reaches
    there (one-sided contacts: a hammer's handle whose butt was never touched), and the end is
    moved in to :data:`CLIP_MARGIN` data sizes past the part's farthest contact along that
    axis, the opposite end staying where it is (the semi-axis shrinks by half the retraction
    and the centre moves by the other half)."""
    if data.allowed is None or len(vectors) < 2:
        return vectors
    margin = SUPPORT_MARGIN * data.size
    lo, hi = data.points.min(axis=0) - margin, data.points.max(axis=0) + margin
    shapes = [Superquadric.from_vector(v) for v in vectors]
    out = vectors.copy()
    for k, part in enumerate(shapes):
        mine = owner == k
        cos = data.normals[mine] @ part.rotation  # normals in the part's axes
        local = (data.points[mine] - part.center) @ part.rotation
        others = [o for j, o in enumerate(shapes) if j != k]
        half, shift, moved = part.a.copy(), np.zeros(3), False
        for axis in range(3):
            for sign in (1.0, -1.0):
                if np.any(sign * cos[:, axis] > SIDE_COSINE):
                    continue
                tip = np.zeros(3)
                tip[axis] = 0.98 * sign * part.a[axis]
                end = part.to_world(tip[None, :])
                if np.all((end >= lo) & (end <= hi)):
                    continue
                if any(bool(o.contains(end)[0]) for o in others):
                    continue
                reach = float(np.max(sign * local[:, axis])) + CLIP_MARGIN * data.size
                cut = part.a[axis] - max(reach, -part.a[axis] + 2.0 * MIN_HALF * data.size)
                if cut > 0.0:
                    half[axis] -= 0.5 * cut
                    shift[axis] -= 0.5 * sign * cut
                    moved = True
        if moved:
            out[k] = replace(part, a=half, center=part.center + part.rotation @ shift).to_vector()
    return out


def _inside_allowed(data: _Data, vectors: Array) -> bool:
    """True when no part has more than :data:`OUTSIDE_SHARE` of its volume outside the allowed
    box (:data:`REACH`; 2000 seeded interior samples a part)."""
    if data.allowed is None:
        return True
    lo, hi = data.allowed
    for v in vectors:
        inside = Superquadric.from_vector(v).sample_interior(2000, rng=0)
        out = np.any((inside < lo) | (inside > hi), axis=1)
        if np.mean(out) > OUTSIDE_SHARE:
            return False
    return True


def _alternate(data: _Data, vectors: Array, how: str) -> Candidate | None:
    """Rounds of reassignment and per-part refinement from the parts `vectors` (module
    docstring); None when a part runs out of contacts."""
    k = len(vectors)
    vectors = vectors.copy()
    owner = np.zeros(data.n, dtype=np.int64)
    for _ in range(ROUNDS):
        d, e = data.misfit(vectors)
        # the noise levels of this union's own residuals (or the given ones)
        sigma_d, sigma_n = data.scales(data.candidate(vectors, owner, how))
        z2 = (d / sigma_d) ** 2 + (e / sigma_n) ** 2
        owner = np.argmin(z2, axis=0)
        counts = np.bincount(owner, minlength=k)
        if np.any(counts < MIN_PART_CONTACTS):
            return None
        offset = FREE_OFFSET * sigma_d
        noise = sigma_d / max(data.size_hint, 1e-9)
        for j in range(k):
            mine = owner == j
            free = data.points[~mine] + offset * data.normals[~mine]
            for extra in (data.free, data.walls):
                if extra is not None:
                    free = np.concatenate([free, extra])
            objective = ml_objective(data.points[mine], data.normals[mine], REFINE_BUDGET,
                                     noise, free, _OPTIONS)  # fmt: skip
            least_squares_run(objective, vectors[j])
            vectors[j] = objective.best_vector
            data.evaluations += objective.evaluations
    vectors = _clip_unsupported(data, vectors, owner)
    if not _inside_allowed(data, vectors):
        return None
    return data.candidate(vectors, owner, how)


#: nML's likelihood settings for the refinements (its defaults: robust loss, weak taper prior).
_OPTIONS = MLOptions()


def _features(data: _Data) -> Array:
    """The rows k-means clusters: positions in data sizes and :data:`NORMAL_FEATURE` normals."""
    return np.hstack([data.points / data.size, NORMAL_FEATURE * data.normals])


def _starts(data: _Data, k: int, best: Candidate | None, gen: np.random.Generator) -> list:
    """Starting segmentations for k parts: (labels, how) pairs (module docstring)."""
    features = _features(data)
    out = []
    labels = _kmeans(features, k, gen)
    if labels is not None:
        out.append((labels, "k-means"))
    if best is not None and best.parts == k - 1:
        z2 = (best.distance / data.sigma_d) ** 2 + (best.normal / data.sigma_n) ** 2
        worst = int(np.argmax(np.bincount(best.owner, weights=z2, minlength=best.parts)))
        rows = np.flatnonzero(best.owner == worst)
        if len(rows) >= 2 * MIN_PART_CONTACTS:
            split = _kmeans(features[rows], 2, gen)
            if split is not None:
                labels = best.owner.copy()
                labels[rows[split == 1]] = k - 1
                out.append((labels, f"split part {worst} of the {k - 1}-part union"))
    return out


def multi_search(
    points: Array,
    normals: Array,
    single: Superquadric,
    gen: np.random.Generator,
    part_fit: PartFit,
    parts: int | None = None,
    noise: float | None = None,
    free: Array | None = None,
) -> tuple[list[Array], dict]:
    """The parts of the chosen union and the selection record (module docstring).

    Args:
        points, normals: (n, 3) contacts [m, world] and unit normals.
        single: the one-part nH fit of all contacts.
        gen: the generator of the k-means seeds and the parts' nH fits.
        part_fit: what fits one part (nH: :func:`hapticsim.fitting.fit`'s).
        parts: the number of parts to fit, or None to choose up to :data:`MAX_PARTS`.
        noise: the relative sensor noise sigma_N (SPEC §5), or None to estimate the criterion's
            noise levels from the residuals.
        free: (f, 3) free-space points every part must leave empty, or None.

    Returns:
        the parts' parameter vectors, and ``{"parts", "criterion", "candidates": [{"parts",
        "cost", "how", "seconds"}], "sigma_distance", "sigma_normal", "evaluations"}``.
    """
    data = _Data(points, normals, free, noise, float(np.mean(single.a)))
    one = data.candidate(single.to_vector()[None, :], np.zeros(data.n, np.int64), "nH")
    outline = single.surface_mesh(16)[0]
    box = np.stack([np.minimum(points.min(axis=0), outline.min(axis=0)),
                    np.maximum(points.max(axis=0), outline.max(axis=0))])  # fmt: skip
    data.allowed = box + np.array([[-1.0], [1.0]]) * REACH * data.size
    data.walls = _box_walls(data.allowed)
    if data.given is None:
        data.set_scales(one)
    # the criterion compares every part count at the same refinement: nH's part refined as the
    # parts of the unions are (the result of one part stays nH's own)
    fence, data.allowed, data.walls = (data.allowed, data.walls), None, None
    refined = _alternate(data, single.to_vector()[None, :], "nH, refined for the criterion")
    data.allowed, data.walls = fence
    top = MAX_PARTS if parts is None else parts
    top = min(top, data.n // MIN_PART_CONTACTS)
    chosen = [refined if refined is not None else one]  # the best of each part count, in order
    records = [{"parts": 1, "how": "nH", "seconds": 0.0}]
    for k in range(2, top + 1):
        start = time.perf_counter()
        data.set_scales(chosen[-1])
        found = []
        starts = _starts(data, k, chosen[-1], gen)
        retries = 0
        while starts:
            labels, how = starts.pop(0)
            vectors = [_part_fit(data, np.flatnonzero(labels == j), gen, part_fit)
                       for j in range(k)]  # fmt: skip
            if all(v is not None for v in vectors):
                c = _alternate(data, np.array(vectors), how)
                if c is not None:
                    found.append(c)
            if not starts and not found and retries < RETRY_STARTS:
                retries += 1  # none admitted yet: another k-means start
                labels = _kmeans(_features(data), k, gen)
                if labels is not None:
                    starts.append((labels, f"k-means, retry {retries}"))
        if not found:
            break
        data.set_scales(min(found, key=lambda c: float(np.sum(c.distance**2))))
        best_k = min(found, key=data.cost)
        chosen.append(best_k)
        records.append({"parts": k, "how": best_k.how, "seconds": time.perf_counter() - start})
        costs = [data.cost(c) for c in chosen]
        if parts is None and int(np.argmin(costs)) != len(chosen) - 1:
            break  # the new part count does not pay: more parts will not either
    if data.sigma_d == 0.0:  # only one part was fitted: scales from its residuals
        data.set_scales(one)
    costs = [data.cost(c) for c in chosen]
    for rec, cost in zip(records, costs, strict=True):
        rec["cost"] = cost
    pick = len(chosen) - 1 if parts is not None else int(np.argmin(costs))
    result = chosen[pick] if pick else one
    if parts is not None and result.parts != parts:
        raise InvalidInputError(
            f"cannot fit {parts} parts to {data.n} contacts: at most {result.parts} parts keep "
            f"{MIN_PART_CONTACTS} contacts each"
        )
    return list(result.vectors), {
        "parts": result.parts,
        "criterion": f"robust BIC: sum min(z^2, {CAP:g}^2) + K 13 ln n (fitting/multi.py)",
        "candidates": records,
        "sigma_distance": data.sigma_d,
        "sigma_normal": data.sigma_n,
        "evaluations": data.evaluations,
    }


__all__ = ["MAX_PARTS", "MIN_PART_CONTACTS", "Candidate", "multi_search"]
