"""Shape with pose tracking: ``nH+track`` and ``multi+track`` (SPEC §12).

A free object moves while it is explored; its contacts, recorded in the world, then describe an
object that was in a different place at each of them. The tracking fit estimates the shape in the
object's own frame (where it stood at the first contact) jointly with the object's rigid motion
at every contact:

- the unknowns: the superquadric's 13 parameters and the object's trajectory: a pose at a knot
  every :data:`KNOT_SPACING` contacts (a rotation vector about the naive fit's centre ``c`` and
  the translation of that centre, ``x_world = R (x_object - c) + c + t``), each contact's pose
  interpolated linearly between its two knots; the first knot is the identity: it fixes the
  object's frame (a pose per contact, tried first, let every contact's pose take up its own
  residual: on an 8 mm slide it found 0.4 mm);
- the residuals: each contact's EOF residual (paper eq. 9, the contact and its normal carried
  into the object's frame by its pose) over the contact scale ``sigma_c`` (the naive fit's RMS
  residual, at least :data:`MIN_CONTACT_SCALE`); and the *motion prior*, each knot's change
  from the previous knot's over its scale per axis (:class:`MotionPrior`): an object in a cradle
  or a clamp slides and turns about the vertical far more readily than it lifts or tilts. Both
  are robust (soft-L1: quadratic up to one scale, then linear), so that the pushes that move an
  object in jumps cost what a jump costs, not its square, and a contact taken while the object
  rocked does not drag the trajectory (on 66 development runs, random objects of seeds
  1000-1011, mean IoU 0.960 against 0.957 with squared contact residuals);
- the minimiser: bounded trust-region least squares (SciPy's ``trf``) with the Jacobian's
  sparsity (a knot touches the contacts on either side of it and its two prior terms), started
  from the shape of the ordinary fit of the world-frame contacts (the naive fit, nH) and every
  pose at the identity.

``multi+track`` tracks the poses with one superquadric as above, then fits ``multi`` to the
contacts carried into the object's frame by the tracked poses (the union's parts are not tracked
jointly: a stated simplification).

The contacts must come in the order they were recorded (``contacts.npz``'s order).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares
from scipy.sparse import lil_matrix
from scipy.spatial.transform import Rotation

from hapticsim.constants import DEFAULT_LAMBDA
from hapticsim.geometry.eof import contact_residuals
from hapticsim.geometry.layout import (
    N_PARAMS,
    SLICE_A,
    SLICE_CENTER,
    SLICE_EPS,
    SLICE_ROTVEC,
    SLICE_TAPER,
)

Array = NDArray[np.float64]

#: The tracking methods and the method each fits the shape with.
SHAPE_METHOD: dict[str, str] = {"nH+track": "nH", "multi+track": "multi"}
#: Smallest contact scale [m] (exact contacts still sit on a meshed, not the true, surface).
MIN_CONTACT_SCALE: float = 2e-4
#: Most trust-region iterations of the joint fit.
MAX_NFEV: int = 100
#: Contacts between two knots of the tracked trajectory.
KNOT_SPACING: int = 15
#: Points of the object's surface that :func:`pose_drift`'s ADD and ADD-S average over.
DRIFT_SURFACE_POINTS: int = 2000
#: The object's frame where it rested (:meth:`Tracked.poses`'s layout): the first tracked pose.
IDENTITY_POSE: Array = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
IDENTITY_POSE.flags.writeable = False


@dataclass(frozen=True)
class MotionPrior:
    """Scales of an object's motion from one knot of its trajectory to the next,
    :data:`KNOT_SPACING` contacts on (one standard deviation of a soft-L1 prior; module
    docstring).

    Attributes:
        slide: horizontal translation [m].
        lift: vertical translation [m].
        turn: rotation about the vertical [rad].
        tilt: rotation about a horizontal axis [rad].
    """

    slide: float = 2e-3
    lift: float = 3e-4
    turn: float = 0.035
    tilt: float = 0.009

    @property
    def scales(self) -> Array:
        """(6,) the scales of (rotation vector x, y, z, translation x, y, z)."""
        return np.array([self.tilt, self.tilt, self.turn, self.slide, self.slide, self.lift])


@dataclass(frozen=True)
class Tracked:
    """What the joint fit found.

    Attributes:
        vector: (13,) the superquadric in the object's frame.
        rotations: (n, 3, 3) the object's rotation at each contact.
        translations: (n, 3) [m] the translation of `pivot` at each contact.
        pivot: (3,) [m] the point the rotations turn about (the naive fit's centre).
        cost: the final cost (half the sum of squared, robust residuals).
        iterations: function evaluations of the trust-region fit.
        status: ``"converged"`` or ``"iterations"``.
    """

    vector: Array
    rotations: Array
    translations: Array
    pivot: Array
    cost: float
    iterations: int
    status: str

    def object_frame(self, points: Array, normals: Array) -> tuple[Array, Array]:
        """The contacts (n, 3) and normals (n, 3) carried into the object's frame."""
        moved = points - self.translations - self.pivot
        local = np.einsum("nji,nj->ni", self.rotations, moved) + self.pivot
        return local, np.einsum("nji,nj->ni", self.rotations, normals)

    def poses(self) -> Array:
        """(n, 7) float: each contact's translation [m] and quaternion (w first) of the object's
        frame in the world (``contacts.npz``'s ``object_pose`` layout)."""
        quat = Rotation.from_matrix(self.rotations).as_quat()  # x, y, z, w
        origin = self.pivot + self.translations - self.rotations @ self.pivot
        return np.column_stack([origin, quat[:, 3], quat[:, :3]])


def _residuals(points: Array, normals: Array, vector: Array, lam: float) -> Array:
    """The EOF residuals (n,) of the contacts against the superquadric `vector` (13,)."""
    rotation = Rotation.from_rotvec(vector[SLICE_ROTVEC]).as_matrix()
    return contact_residuals(points, normals, vector[SLICE_A], vector[SLICE_EPS],
                             vector[SLICE_TAPER], rotation, vector[SLICE_CENTER], lam)  # fmt: skip


def _soft_l1(r: Array) -> Array:
    """Residuals whose squares are the soft-L1 cost ``2 (sqrt(1 + r^2) - 1)``."""
    return np.sign(r) * np.sqrt(2.0 * (np.sqrt(1.0 + r * r) - 1.0))


def knot_weights(n: int, spacing: int | None = None) -> tuple[Array, Array]:
    """The knots of a trajectory over `n` contacts: their contact indices (k,), one every
    `spacing` (default :data:`KNOT_SPACING`) contacts from the first to the last, and the (n, k)
    weights that interpolate a contact's pose linearly between its two knots."""
    spacing = KNOT_SPACING if spacing is None else spacing
    k = max(2, int(np.ceil((n - 1) / spacing)) + 1)
    at = np.linspace(0.0, n - 1.0, k)
    weights = np.zeros((n, k))
    for i in range(n):
        j = min(int(np.searchsorted(at, i, side="right")) - 1, k - 2)
        w = (i - at[j]) / (at[j + 1] - at[j])
        weights[i, j], weights[i, j + 1] = 1.0 - w, w
    return at, weights


def track_poses(
    points: Array, normals: Array, start: Array, bounds: Any, prior: MotionPrior | None = None,
    lam: float = DEFAULT_LAMBDA, *, spacing: int | None = None,
    contact_scale: float | None = None, pivot: Array | None = None, known_shape: bool = False,
) -> Tracked:  # fmt: skip
    """The joint fit of the module docstring from the superquadric `start` (13,).

    Args:
        points: (n, 3) contacts in recording order [m, world]; normals: (n, 3) unit normals.
        start: (13,) the naive fit's vector.
        bounds: the fitter's :class:`~hapticsim.fitting.objective.Bounds` of the contacts.
        prior: the motion prior (default :class:`MotionPrior`).
        lam: the EOF's normal weight.
        spacing: contacts between two knots (default :data:`KNOT_SPACING`; 1: a pose per
            contact).
        contact_scale: the contacts' residual scale [m] (default: the module docstring's).
        pivot: (3,) the point the rotations turn about (default: `start`'s centre).
        known_shape: keep the shape at `start` and fit the poses only (a diagnosis: tracking
            with the object's model known, ``scripts/track_diagnosis.py``).
    """
    prior = MotionPrior() if prior is None else prior
    n = len(points)
    scales = prior.scales
    _, weights = knot_weights(n, spacing)
    k = weights.shape[1]
    if contact_scale is None:
        r0 = _residuals(points, normals, start, lam)
        sigma_c = max(MIN_CONTACT_SCALE, float(np.sqrt(np.mean(r0**2))))
    else:
        sigma_c = float(contact_scale)
    pivot = np.asarray(start[SLICE_CENTER] if pivot is None else pivot, dtype=np.float64).copy()
    n_shape = 0 if known_shape else N_PARAMS
    fixed = np.asarray(start, dtype=np.float64)

    def unpack(x: Array) -> tuple[Array, Array]:
        knots = np.zeros((k, 6))
        knots[1:] = x[n_shape:].reshape(k - 1, 6)
        return (x[:N_PARAMS] if n_shape else fixed), knots

    def residuals(x: Array) -> Array:
        shape, knots = unpack(x)
        motion = weights @ knots
        rot = Rotation.from_rotvec(motion[:, :3]).as_matrix()
        local = np.einsum("nji,nj->ni", rot, points - motion[:, 3:] - pivot) + pivot
        local_n = np.einsum("nji,nj->ni", rot, normals)
        r = _residuals(local, local_n, shape, lam)
        steps = np.diff(knots, axis=0) / scales
        return np.concatenate([_soft_l1(r / sigma_c), _soft_l1(steps).ravel()])

    sparsity = lil_matrix((n + 6 * (k - 1), n_shape + 6 * (k - 1)), dtype=np.int8)
    sparsity[:n, :n_shape] = 1
    for j in range(1, k):
        cols = slice(n_shape + 6 * (j - 1), n_shape + 6 * j)
        sparsity[np.flatnonzero(weights[:, j]), cols] = 1
        for step in (j - 1, j):  # the prior's steps into and out of knot j
            if step < k - 1:
                sparsity[n + 6 * step : n + 6 * step + 6, cols] = 1
    free = np.full(6 * (k - 1), np.inf)
    if known_shape:
        lower, upper, x0 = -free, free, np.zeros(6 * (k - 1))
        x_scale = np.tile(scales, k - 1)
    else:
        lower = np.concatenate([bounds.lower, -free])
        upper = np.concatenate([bounds.upper, free])
        x0 = np.concatenate([np.clip(start, bounds.lower, bounds.upper), np.zeros(6 * (k - 1))])
        x_scale = np.concatenate([bounds.scale, np.tile(scales, k - 1)])
    result = least_squares(
        residuals, x0, jac_sparsity=sparsity.tocsr(), bounds=(lower, upper), method="trf",
        x_scale=x_scale, max_nfev=MAX_NFEV, tr_solver="lsmr",
    )  # fmt: skip
    shape, knots = unpack(result.x)
    motion = weights @ knots
    return Tracked(
        vector=shape.copy(), rotations=Rotation.from_rotvec(motion[:, :3]).as_matrix(),
        translations=motion[:, 3:].copy(), pivot=pivot, cost=float(result.cost),
        iterations=int(result.nfev),
        status="converged" if result.status > 0 else "iterations",
    )  # fmt: skip


def fit_tracked(method: str, points: Array, normals: Array, fit_shape: Any, start: float,
                prior: MotionPrior | None = None, lam: float = DEFAULT_LAMBDA) -> Any:  # fmt: skip
    """A tracking fit (module docstring) as a :class:`~hapticsim.fitting.result.FitResult`
    with its ``poses``.

    Args:
        method: ``"nH+track"`` or ``"multi+track"``.
        points, normals: the checked contacts (n, 3) in recording order.
        fit_shape: ``fit_shape(base_method, points, normals)`` runs the ordinary fit (the
            driver's, with the caller's budget and seed) and returns its FitResult.
        start: ``time.perf_counter()`` when the fit began.
        prior: the motion prior.
        lam: the EOF's normal weight.
    """
    from dataclasses import replace

    from hapticsim.fitting.objective import Bounds
    from hapticsim.geometry import Superquadric

    naive = fit_shape("nH", points, normals)
    tracked = track_poses(points, normals, naive.solid.to_vector(), Bounds.from_points(points),
                          prior, lam)  # fmt: skip
    local, local_n = tracked.object_frame(points, normals)
    if SHAPE_METHOD[method] == "multi":
        shaped = fit_shape("multi", local, local_n)
    else:
        r = _residuals(local, local_n, tracked.vector, lam)
        shaped = replace(naive, solid=Superquadric.from_vector(tracked.vector),
                         eof=float(np.mean(r**2)))  # fmt: skip
    return replace(
        shaped, method=method, seconds=time.perf_counter() - start, poses=tracked.poses(),
        message=f"{shaped.message}; poses tracked ({tracked.status}, {tracked.iterations} "
        "evaluations of the joint fit, beside the budget)",
    )  # fmt: skip


def pose_drift(estimated: Array, true: Array, center: Array, solid: Any = None) -> dict[str, float]:
    """How far a tracked pose (7,) is from the true one (7,), both the object frame's origin [m]
    and quaternion (w first) in the world.

    Returns:
        ``position_m``, the distance between where the two put the point `center` (3,) of the
        object's frame (the object's centre); ``angle_deg``, the angle of the rotation between
        them; and with the object's `solid` (in its own frame) the pose-estimation measures of
        the field (Hinterstoisser et al. 2012; the BOP benchmark), over
        :data:`DRIFT_SURFACE_POINTS` points of its surface (a fixed stream): ``add_m``, the
        mean distance between where the two poses put each point, and ``adds_m``, the mean
        distance from where the tracked pose puts each point to the surface where the true
        pose puts it. ADD-S does not count a turn about an axis of symmetry (a cylinder's
        about its axis), which no touch can see; ``angle_deg`` and ADD do.
    """
    rot_e = Rotation.from_quat([*estimated[4:], estimated[3]])
    rot_t = Rotation.from_quat([*true[4:], true[3]])
    center = np.array(center, dtype=np.float64)
    at_e = rot_e.apply(center) + estimated[:3]
    at_t = rot_t.apply(center) + true[:3]
    out = {
        "position_m": float(np.linalg.norm(at_e - at_t)),
        "angle_deg": float(np.degrees((rot_e.inv() * rot_t).magnitude())),
    }
    if solid is not None:
        surface, _ = solid.sample_surface(DRIFT_SURFACE_POINTS, np.random.default_rng(0))
        put_e = rot_e.apply(surface) + estimated[:3]
        out["add_m"] = float(np.mean(np.linalg.norm(put_e - rot_t.apply(surface) - true[:3],
                                                    axis=1)))  # fmt: skip
        back = rot_t.inv().apply(put_e - true[:3])  # the tracked points in the true frame
        out["adds_m"] = float(np.mean(solid.surface_distance(back)))
    return out


def true_poses(object_poses: Array, initial: Array) -> Array:
    """(n, 7) the true poses of the object's frame (its pose at rest, `initial` (7,)) at each
    contact, in :meth:`Tracked.poses`'s layout, from ``contacts.npz``'s ``object_pose``
    (n, 7: the object body's pose)."""
    poses = np.atleast_2d(np.asarray(object_poses, dtype=np.float64))
    r0 = Rotation.from_quat([*initial[4:], initial[3]])
    rel = Rotation.from_quat(poses[:, [4, 5, 6, 3]]) * r0.inv()
    origin = poses[:, :3] - rel.apply(np.asarray(initial[:3], dtype=np.float64))
    quat = rel.as_quat()  # x, y, z, w
    return np.column_stack([origin, quat[:, 3], quat[:, :3]])


__all__ = [
    "DRIFT_SURFACE_POINTS", "IDENTITY_POSE", "MotionPrior", "SHAPE_METHOD", "Tracked",
    "fit_tracked", "knot_weights", "pose_drift", "track_poses", "true_poses",
]  # fmt: skip
