"""Initial estimates: the paper's (Section II-B) and seeds derived from the contact normals.

:func:`paper_initial` is the start of LS and nLS: the centroid, the principal axes of the
covariance and the half extents along them, an ellipsoid (eps1 = eps2 = 1), no taper.

For sparse, one-sided contacts the principal axes say little about the orientation of a box or a
cylinder (a corner patch and a few stripes have no reason to spread along the body axes), and the
centroid lies on the touched side. The normals say more: on a flat face they all point one way, so
the dominant normal directions are face normals, and the centre lies behind each face. The genetic
algorithm starts from :func:`seed_vectors`: every candidate frame (principal axes of the points,
of the normals, and frames built from the dominant normal directions), each of its three axes
taken as the body z axis (the solid is not symmetric under such a permutation), and a few shape
classes (ellipsoid, box, cylinder).
"""

from __future__ import annotations

import itertools

import numpy as np
from numpy.typing import NDArray

from hapticsim.geometry.layout import (
    N_PARAMS,
    SLICE_A,
    SLICE_CENTER,
    SLICE_EPS,
    SLICE_ROTVEC,
    SLICE_TAPER,
)
from hapticsim.geometry.rotations import matrix_to_rotvec, random_rotation
from hapticsim.geometry.superquadric import Superquadric

Array = NDArray[np.float64]

#: Shape classes of the seeds, (eps1, eps2): ellipsoid, box, cylinder (SPEC §1).
SEED_SHAPES: tuple[tuple[float, float], ...] = ((1.0, 1.0), (0.2, 0.2), (0.2, 1.0))
#: Orientations of the extra seeds of :func:`random_frame_seeds`: fixed, uniformly drawn once
#: (seed 0), so that every fit sees the same ones.
RANDOM_FRAMES: NDArray[np.float64] = random_rotation(np.random.default_rng(0), 24)
#: Half-angle of the cone of normals counted as one direction (face) [rad].
FACE_CONE: float = np.deg2rad(25.0)
#: Fewest contacts (as a fraction) that make a dominant normal direction.
FACE_MIN_FRACTION: float = 0.08


def _proper(frame: Array) -> Array:
    """The frame (columns) with its last column flipped if needed, so that det = +1."""
    frame = np.array(frame, dtype=np.float64)
    if np.linalg.det(frame) < 0:
        frame[:, 2] *= -1.0
    return frame


def principal_axes(points_world: Array) -> Array:
    """(3, 3) rotation whose columns are the principal axes of the points, spread ascending.

    The largest spread becomes the body z axis.
    """
    centred = points_world - points_world.mean(axis=0)
    _, vecs = np.linalg.eigh(centred.T @ centred)
    return _proper(vecs)


def extents(points_world: Array, rotation: Array) -> tuple[Array, Array]:
    """Centre [m] (3,) of the bounding box of the points in the frame, and its half sizes (3,)."""
    proj = points_world @ rotation
    lo, hi = proj.min(axis=0), proj.max(axis=0)
    return rotation @ ((lo + hi) / 2.0), (hi - lo) / 2.0


def paper_initial(points_world: Array) -> Superquadric:
    """The paper's initial estimate (II-B) of contacts (n, 3) [m].

    Centre at the centroid, rotation from the principal axes (largest spread on z), semi-axes
    half the spread of the contacts along each axis (at least 1e-3 of the largest), ellipsoid
    (eps1 = eps2 = 1), no taper.
    """
    rotation = principal_axes(points_world)
    _, half = extents(points_world, rotation)
    half = np.maximum(half, 1e-3 * max(float(half.max()), 1e-12))
    return Superquadric(a=half, eps=(1.0, 1.0), rotation=rotation, center=points_world.mean(0))


def dominant_directions(normals_world: Array, max_count: int = 3) -> list[Array]:
    """Up to `max_count` dominant unit directions of the normals (greedy cone clustering).

    Repeatedly takes the normal with the most others within :data:`FACE_CONE`, the mean of that
    cone as a direction, and removes the cone's normals; stops when a cone holds fewer than
    :data:`FACE_MIN_FRACTION` of the contacts.
    """
    n = normals_world.shape[0]
    left = np.ones(n, dtype=bool)
    cos_cone = np.cos(FACE_CONE)
    dots = normals_world @ normals_world.T
    out: list[Array] = []
    while len(out) < max_count:
        close = (dots > cos_cone) & left[None, :] & left[:, None]
        support = close.sum(axis=1)
        best = int(np.argmax(support))
        if support[best] < max(3, FACE_MIN_FRACTION * n):
            break
        mean = normals_world[close[best]].sum(axis=0)
        out.append(mean / np.linalg.norm(mean))
        left &= normals_world @ out[-1] <= cos_cone
    return out


def normal_frames(normals_world: Array) -> list[Array]:
    """Candidate rotations from the normals: their principal axes, and frames of face directions.

    Two dominant directions (:func:`dominant_directions`) that are roughly orthogonal (within 30
    degrees) span a frame (Gram-Schmidt, third axis by cross product); and each dominant
    direction alone is taken as an axis, with the principal axis of the normals most orthogonal
    to it as the next one (a cylinder's flat end, a box touched on one face).
    """
    _, vecs = np.linalg.eigh(normals_world.T @ normals_world)
    frames = [_proper(vecs)]
    dirs = dominant_directions(normals_world)
    for i in range(len(dirs)):
        for j in range(i + 1, len(dirs)):
            c = float(dirs[i] @ dirs[j])
            if abs(c) < np.sin(np.deg2rad(30.0)):
                u = dirs[i]
                v = dirs[j] - c * u
                v /= np.linalg.norm(v)
                frames.append(np.stack([u, v, np.cross(u, v)], axis=1))
    for d in dirs:
        # One face direction with the two normal principal axes most orthogonal to it.
        others = sorted(range(3), key=lambda k: abs(float(vecs[:, k] @ d)))[:2]
        u = vecs[:, others[0]] - (vecs[:, others[0]] @ d) * d
        u /= np.linalg.norm(u)
        frames.append(np.stack([u, np.cross(d, u), d], axis=1))
    return frames


def _cube_rotations() -> Array:
    """The 24 proper signed permutation matrices (the rotations of a cube), (24, 3, 3)."""
    out = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1.0, -1.0), repeat=3):
            m = np.zeros((3, 3))
            m[list(perm), range(3)] = signs
            if np.linalg.det(m) > 0:
                out.append(m)
    return np.array(out)


_CUBE = _cube_rotations()
#: Frames closer than this, up to relabelling their axes, count as one [rad].
FRAME_TOLERANCE: float = np.deg2rad(10.0)


def distinct_frames(frames: list[Array]) -> list[Array]:
    """The frames (rotations), less each one that equals an earlier one up to a relabelling of
    its axes (a cube rotation) within :data:`FRAME_TOLERANCE`: the seeds try every axis as z and
    the solid is unchanged by the rest, so such a frame would only repeat seeds."""
    kept: list[Array] = []
    cos_tol = 1.0 + 2.0 * np.cos(FRAME_TOLERANCE)  # trace of a rotation by the tolerance
    for frame in frames:
        # trace(K^T F Q) over kept frames K and cube rotations Q: the closest relabelling.
        if not any(np.max(np.einsum("ij,qij->q", k.T @ frame, _CUBE.transpose(0, 2, 1))) > cos_tol
                   for k in kept):  # fmt: skip
            kept.append(frame)
    return kept


def _frame_seeds(
    points_world: Array, normals_world: Array | None, rotations: Array
) -> tuple[Array, Array]:
    """Centres [m] (R, 3) and semi-axes [m] (R, 3) of boxes in R frames (R, 3, 3), pushed behind
    one-sided faces.

    Along each axis the contacts span [lo, hi]. Where the normals show only the face at hi
    (or lo), the body lies behind it: the semi-axis is at least the mean of the other two, and
    the centre sits that far inside the face.
    """
    proj = np.einsum("nj,rjk->rnk", points_world, rotations)  # (R, n, 3)
    lo, hi = proj.min(axis=1), proj.max(axis=1)
    span = hi - lo
    half = np.maximum(span / 2.0, 1e-3 * np.maximum(span.max(axis=1, keepdims=True), 1e-12))
    mid = (lo + hi) / 2.0
    if normals_world is not None:
        along = np.einsum("nj,rjk->rnk", normals_world, rotations)
        plus = np.any(along > np.cos(FACE_CONE), axis=1)
        minus = np.any(along < -np.cos(FACE_CONE), axis=1)
        for k in range(3):  # in turn: a deepened axis counts for the next ones
            others = (half.sum(axis=1) - half[:, k]) / 2.0  # mean of the other two
            depth = np.maximum(half[:, k], others)
            sided = plus[:, k] != minus[:, k]
            mid[:, k] = np.where(sided, np.where(plus[:, k], hi[:, k] - depth, lo[:, k] + depth),
                                 mid[:, k])  # fmt: skip
            half[:, k] = np.where(sided, depth, half[:, k])
    return np.einsum("rjk,rk->rj", rotations, mid), half


def seed_vectors(
    points_world: Array, normals_world: Array | None, initial: Superquadric | None = None
) -> Array:
    """Seed parameter vectors (k, 13) for the global search.

    Frames: the principal axes of the points and, with normals, :func:`normal_frames`, less those
    that repeat an earlier one (:func:`distinct_frames`). For each frame and each choice of its z
    axis (cyclic permutations of the columns, which keep det = +1), a box-like placement
    (:func:`_frame_seeds`) with each shape of :data:`SEED_SHAPES`, no taper. The paper's initial
    estimate comes first, and `initial` (a warm start) before it.
    """
    seeds = []
    if initial is not None:
        seeds.append(initial.to_vector())
    seeds.append(paper_initial(points_world).to_vector())
    frames = [principal_axes(points_world)]
    if normals_world is not None:
        frames += normal_frames(normals_world)
    # Each distinct frame with each of its axes as z (cyclic shifts of the columns, det = +1).
    rotations = np.array(
        [np.roll(frame, shift, axis=1) for frame in distinct_frames(frames) for shift in range(3)]
    )
    centers, halves = _frame_seeds(points_world, normals_world, rotations)
    rotvecs = matrix_to_rotvec(rotations)
    shapes = np.asarray(SEED_SHAPES, dtype=np.float64)
    block = np.empty((len(rotations), len(shapes), N_PARAMS))
    block[:, :, 0:3] = halves[:, None, :]
    block[:, :, 3:5] = shapes[None, :, :]
    block[:, :, 5:7] = 0.0
    block[:, :, 7:10] = rotvecs[:, None, :]
    block[:, :, 10:13] = centers[:, None, :]
    return np.concatenate([np.array(seeds), block.reshape(-1, N_PARAMS)])


def random_frame_seeds(
    points_world: Array, normals_world: Array | None, count: int = len(RANDOM_FRAMES)
) -> Array:
    """Seeds (count, 13) in orientations that do not come from the data: ellipsoids placed like
    :func:`_frame_seeds` in the first `count` of the fixed :data:`RANDOM_FRAMES`.

    On shapes whose contacts say little about the orientation (round, tapered, touched on one
    side) the data-derived frames can all lie far from the right basin; these cover the
    rotations evenly instead. Measured on the three hardest of 480 random tapered cases
    (``scripts/global_minimum.py``, 10 fits each at budget 7500): 24 of them cut the fits that
    missed the lowest EOF from 11 to 6 of 30.
    """
    rotations = RANDOM_FRAMES[:count]
    if not len(rotations):
        return np.zeros((0, N_PARAMS))
    centers, halves = _frame_seeds(points_world, normals_world, rotations)
    out = np.empty((len(rotations), N_PARAMS))
    out[:, SLICE_A], out[:, SLICE_EPS], out[:, SLICE_TAPER] = halves, 1.0, 0.0
    out[:, SLICE_ROTVEC], out[:, SLICE_CENTER] = matrix_to_rotvec(rotations), centers
    return out
