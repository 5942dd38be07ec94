"""One touch: the continuous action of the exploration environment and what executes it.

An action of :class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv` is a vector in
``[-1, 1]^5`` that :func:`decode_action` turns into a :class:`Touch`:

=====  ==================  =====================================================  =======
index  name                mapping                                                unit
=====  ==================  =====================================================  =======
0      approach azimuth    ``phi = pi * a0``                                      [rad]
1      approach elevation  ``sin(el) = a1`` (uniform actions: uniform on sphere)  [rad]
2      stroke direction    ``psi = pi * a2``, in the tangent plane at the contact  [rad]
3      stroke length       ``L = (a3 + 1) / 2 * max_stroke``; ``L < spacing``:    [m]
                           a probe (one contact)
4      finger              ``k = floor((a4 + 1) / 2 * n_fingers)``, clipped       index
=====  ==================  =====================================================  =======

The approach direction ``d = (cos el cos phi, cos el sin phi, sin el)`` is expressed in the
*object-centred frame*: origin at the object's rough position (what a robot knows before touching),
axes parallel to the world's. The fingertip comes from far along ``d`` and moves along ``-d``
towards the rough position until it meets the surface. A stroke then follows the contour from the
first contact for ``L`` metres in the direction ``cos(psi) t_h + sin(psi) t_v``, with ``t_h`` the
horizontal tangent (``z x n``, normalised) and ``t_v = n x t_h`` the upward tangent at the first
contact's outward normal ``n``; so ``psi = +-pi/2`` strokes up or down across a top or bottom
edge, ``psi = 0`` or ``pi`` sideways across a side edge.

A backend (:class:`TouchBackend`) executes touches: the analytic ray caster
(:mod:`hapticsim.envs.analytic`) or the MuJoCo hand (:mod:`hapticsim.envs.mujoco_backend`).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_array
from hapticsim.data.noise import add_noise
from hapticsim.envs.support import Support
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.geometry.rays import raycast
from hapticsim.geometry.solid import Solid

Array = NDArray[np.float64]

#: Length of the action vector.
ACTION_DIM: int = 5
#: Names of the action components, in order.
ACTION_NAMES: tuple[str, ...] = (
    "approach_azimuth",
    "approach_elevation",
    "stroke_direction",
    "stroke_length",
    "finger",
)
#: Statuses of a touch.
TOUCH_STATUSES: tuple[str, ...] = ("ok", "missed", "blocked", "failed")


@dataclass(frozen=True)
class Touch:
    """A decoded action: one probe or short contour stroke.

    Attributes:
        approach: (3,) float, unit vector from the object towards where the fingertip comes from,
            object-centred frame (axes of the world).
        stroke_angle: psi [rad], direction of the stroke in the tangent plane at first contact
            (0: horizontal tangent ``z x n``, pi/2: upward tangent).
        stroke_length: L [m], 0 for a probe.
        finger: index of the finger that touches (0 is the thumb).
    """

    approach: Array
    stroke_angle: float
    stroke_length: float
    finger: int

    def __post_init__(self) -> None:
        d = finite_array(self.approach, "approach", (3,))
        norm = float(np.linalg.norm(d))
        if norm < 1e-9:
            raise InvalidInputError("`approach` must be a non-zero vector")
        object.__setattr__(self, "approach", d / norm)
        if not np.isfinite(self.stroke_angle):
            raise InvalidInputError(f"`stroke_angle` must be finite, got {self.stroke_angle!r}")
        if not np.isfinite(self.stroke_length) or self.stroke_length < 0:
            raise InvalidInputError(f"`stroke_length` must be >= 0 [m], got {self.stroke_length!r}")
        if int(self.finger) < 0:
            raise InvalidInputError(f"`finger` must be >= 0, got {self.finger!r}")
        object.__setattr__(self, "finger", int(self.finger))

    @property
    def is_probe(self) -> bool:
        """True for a touch without a stroke."""
        return self.stroke_length <= 0.0


def decode_action(action: Any, max_stroke: float, stroke_spacing: float, n_fingers: int) -> Touch:
    """Map an action in ``[-1, 1]^5`` to a :class:`Touch` (table in the module docstring).

    Values outside ``[-1, 1]`` are clipped.

    Args:
        action: (5,) float.
        max_stroke: stroke length [m] of ``a3 = 1``.
        stroke_spacing: distance [m] between contacts along a stroke; shorter strokes are probes.
        n_fingers: number of fingers of the hand.

    Returns:
        The touch.

    Raises:
        InvalidInputError: wrong shape or NaN.
    """
    a = np.clip(finite_array(action, "action", (ACTION_DIM,)), -1.0, 1.0)
    phi = np.pi * a[0]
    el = float(np.arcsin(a[1]))
    approach = np.array([np.cos(el) * np.cos(phi), np.cos(el) * np.sin(phi), np.sin(el)])
    length = 0.5 * (a[3] + 1.0) * max_stroke
    if length < stroke_spacing:
        length = 0.0
    finger = min(int(np.floor(0.5 * (a[4] + 1.0) * n_fingers)), n_fingers - 1)
    return Touch(approach, float(np.pi * a[2]), float(length), finger)


def encode_touch(
    approach: Array,
    stroke_angle: float,
    stroke_length: float,
    finger: int,
    max_stroke: float,
    n_fingers: int,
) -> NDArray[np.float32]:
    """The action that decodes to the given touch (inverse of :func:`decode_action`).

    Args:
        approach: (3,) float, approach direction (any length), object-centred frame.
        stroke_angle: psi [rad], wrapped to [-pi, pi].
        stroke_length: L [m], clipped to [0, max_stroke].
        finger: finger index, clipped to [0, n_fingers - 1].
        max_stroke: stroke length [m] of ``a3 = 1``.
        n_fingers: number of fingers.

    Returns:
        (5,) float32 action in ``[-1, 1]``.
    """  # fmt: skip
    d = finite_array(approach, "approach", (3,))
    d = d / max(float(np.linalg.norm(d)), 1e-12)
    phi = float(np.arctan2(d[1], d[0]))
    psi = float(np.angle(np.exp(1j * stroke_angle)))
    length = float(np.clip(stroke_length, 0.0, max_stroke))
    k = int(np.clip(finger, 0, n_fingers - 1))
    a = np.array(
        [phi / np.pi, d[2], psi / np.pi, 2.0 * length / max_stroke - 1.0,
         2.0 * (k + 0.5) / n_fingers - 1.0],
    )  # fmt: skip
    return np.clip(a, -1.0, 1.0).astype(np.float32)


@dataclass(frozen=True)
class TouchResult:
    """The contacts that one touch produced (world frame).

    Attributes:
        points: (k, 3) float, measured contact points [m] (with sensor noise).
        normals: (k, 3) float, measured outward unit normals.
        points_clean: (k, 3) float, contact points before sensor noise [m].
        normals_clean: (k, 3) float, normals before sensor noise.
        finger: (k,) int, finger of each contact.
        force: (k,) float, normal force [N] (0 where the backend has no forces).
        time: (k,) float, time of each contact since the episode started [s].
        status: one of :data:`TOUCH_STATUSES`: ``"ok"``, ``"missed"`` (no contact),
            ``"blocked"`` (the table or the hand's reach prevented it), ``"failed"``.
        seconds: wall-clock time the backend took [s].
        message: details for statuses other than ``"ok"``.
        images: with tactile sensing, (k, pads, rows, cols) float32, every pad's reading [Pa]
            at each contact; else None.
        sigma: with tactile sensing, (k,) float, each estimated contact's per-coordinate std
            [m]; else None.
        points_exact: with tactile sensing, (k, 3) float, the true contacts [m] the estimates
            stand for (MuJoCo's, or the ray cast's); else None.
        normals_exact: the same for the normals.
        traction: with tactile sensing, (k, pads, rows, cols, 3) float32, every pad's traction
            field [Pa] at each contact (pressure, then the tangential traction along the pad's
            u and v; SPEC §11); else None.
        taxel_state: with tactile sensing, (k, pads, rows, cols) int8, each taxel's state (0
            free, 1 stick, 2 slip); else None.
        object_moved: how far [m] the touch moved a free object's centre (SPEC §12; 0 for a
            fixed object and the analytic backend).
        object_turned: by what angle [deg] it turned the object.

    With tactile sensing ``points_clean``/``normals_clean`` are the contacts estimated from the
    taxels (before SPEC §5 noise) and ``force`` the skin's.
    """

    points: Array
    normals: Array
    points_clean: Array
    normals_clean: Array
    finger: NDArray[np.int64]
    force: Array
    time: Array
    status: str = "ok"
    seconds: float = 0.0
    message: str = ""
    images: NDArray[np.float32] | None = None
    sigma: Array | None = None
    points_exact: Array | None = None
    normals_exact: Array | None = None
    traction: NDArray[np.float32] | None = None
    taxel_state: NDArray[np.int8] | None = None
    object_moved: float = 0.0
    object_turned: float = 0.0

    def __post_init__(self) -> None:
        if self.status not in TOUCH_STATUSES:
            raise ChoiceError("status", self.status, TOUCH_STATUSES)
        n = np.asarray(self.points).reshape(-1, 3).shape[0]
        for name in ("points", "normals", "points_clean", "normals_clean"):
            arr = np.asarray(getattr(self, name), dtype=np.float64).reshape(-1, 3)
            if arr.shape[0] != n:
                raise InvalidInputError(f"`{name}` must have {n} rows, got {arr.shape[0]}")
            object.__setattr__(self, name, arr)
        for name, dtype in (("finger", np.int64), ("force", np.float64), ("time", np.float64)):
            arr = np.asarray(getattr(self, name), dtype=dtype).reshape(-1)
            if arr.shape[0] != n:
                raise InvalidInputError(f"`{name}` must have {n} entries, got {arr.shape[0]}")
            object.__setattr__(self, name, arr)
        for name in ("images", "sigma", "points_exact", "normals_exact", "traction",
                     "taxel_state"):  # fmt: skip
            value = getattr(self, name)
            if value is not None and np.asarray(value).shape[0] != n:
                raise InvalidInputError(
                    f"`{name}` must have {n} rows, got {np.asarray(value).shape[0]}"
                )

    def __len__(self) -> int:
        return int(self.points.shape[0])

    @classmethod
    def empty(cls, status: str, seconds: float = 0.0, message: str = "") -> TouchResult:
        """A touch without contacts."""
        z = np.zeros((0, 3))
        return cls(
            z, z, z, z, np.zeros(0, np.int64), np.zeros(0), np.zeros(0), status, seconds, message
        )


class TouchBackend:
    """Base of what executes touches on an object: the analytic ray caster or the MuJoCo hand.

    A backend owns the object's placement: :meth:`reset` receives the shape drawn by the
    environment and returns the ground truth as placed in its world. It keeps the support that
    holds the object in the episode (``self._support``, set in ``reset``: touches that would
    hit it are unreachable) and adds the sensor noise of its level to the contacts
    (``noise``, sigma_N, at the truth's size, from the episode's sensor stream ``self._rng``).
    """

    #: Number of fingers (action component 4 selects one).
    n_fingers: int
    #: Relative sensor noise sigma_N (SPEC §5) added to the contacts.
    noise: float = 0.0
    _support: Support | None = None
    _truth: Any = None
    _rng: Any = None

    def reset(
        self, shape: Solid, rng: np.random.Generator, rough: Any = None, prepared: Any = None
    ) -> Solid:
        """Start an episode on `shape`; return the ground truth in the backend's world frame.

        `rough` (:class:`hapticsim.perception.vision.RoughObject`) is what the planner knows: the
        vision
        estimate, centred at the rough position the environment will aim at; a backend that
        plans (the hand) plans on it. `prepared`: what :meth:`preparer` made of `shape`, or
        None (then reset makes it).
        """
        raise NotImplementedError

    def preparer(self) -> Callable[[Solid], Any] | None:
        """The part of :meth:`reset` that depends on the shape alone, as a picklable function
        whose result `reset` takes as `prepared` (so that it can be made ahead, in another
        process, with the episode's draws); None when there is none worth moving."""
        return None

    def touch(self, touch: Touch, origin: Array) -> TouchResult:
        """Execute one touch aimed at `origin` (3,) [m, world], the object's rough position."""
        raise NotImplementedError

    def render(
        self, estimate: Superquadric | None, points: Array, width: int, height: int
    ) -> NDArray[np.uint8]:
        """An (height, width, 3) uint8 picture of the scene, the estimate and the contacts."""
        raise NotImplementedError

    def close(self) -> None:
        """Release resources (renderers, simulations)."""

    @property
    def support(self) -> Support:
        """The object's support in this episode."""
        if self._support is None:
            raise InvalidInputError("call `reset` first")
        return self._support

    def _reachable(self, point: Array) -> bool:
        return not self.support.blocks(point)

    def _check_touch(self, touch: Touch, ready: bool) -> None:
        """Reject a touch before :meth:`reset` (`ready` False) or with a finger the hand does
        not have."""
        if not ready or self._truth is None or self._rng is None:
            raise InvalidInputError("call `reset` before `touch`")
        if not 0 <= touch.finger < self.n_fingers:
            raise InvalidInputError(
                f"`finger` must be in [0, {self.n_fingers - 1}], got {touch.finger}"
            )

    def _approach(
        self, shape: Solid, touch: Touch, origin: Array, start: float, missed: str
    ) -> tuple[Array | None, TouchResult | None]:
        """Where the approach along ``touch.approach`` towards `origin` (3,) [m, world] first
        meets `shape`: ``(point, None)``, or ``(None, result)`` for a ray that misses (the
        result's message `missed`) or a point the support blocks (`start`: the touch's
        ``time.perf_counter()``)."""
        origin = np.asarray(origin, dtype=np.float64)
        d = touch.approach
        far = 2.0 * shape.bounding_radius + 2.0 * float(np.linalg.norm(origin - shape.center))
        s = raycast(shape, origin + far * d, -d, far)
        if s is None:
            return None, TouchResult.empty("missed", time.perf_counter() - start, missed)
        point = origin + (far - s) * d
        if not self._reachable(point):
            return None, TouchResult.empty(
                "blocked", time.perf_counter() - start, "the support is in the way"
            )
        return point, None

    def _noisy(self, points: Array, normals: Array) -> tuple[Array, Array]:
        """The contacts with SPEC §5 noise of the backend's level on top; copies without."""
        if self.noise > 0:
            return add_noise(points, normals, self.noise, self._truth.size, self._rng)
        return points.copy(), normals.copy()
