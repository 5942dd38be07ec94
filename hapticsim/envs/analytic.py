"""The analytic touch backend: touches executed on the true superquadric by ray casting.

Fast (well under a millisecond of geometry per touch) and free of simulation artefacts, with the
same action semantics as the MuJoCo hand (:mod:`hapticsim.envs.touch`):

- a **probe** casts the approach ray ``origin + s * d, s from far to 0`` (``d`` the approach
  direction) and returns the first point where the inside-outside function ``F <= 1``, found on a
  coarse grid then refined on two finer ones, within the ray's chord through the bounding sphere
  (resolution: chord / 6e4, about 2e-6 m);
- a **stroke** follows the contour in a plane, like the hand's contour-following controller: the
  plane through the first contact spanned by its normal and the stroke direction; contacts lie
  every ``stroke_spacing`` metres of arc length along that section
  (:func:`~hapticsim.geometry.sections.section_walk`), so the stroke rolls over edges and corners
  onto the next face;
- a contact where a fingertip would hit the object's support (:class:`~hapticsim.envs.support.
  Support`: by default the thin stand under the object, as in the MuJoCo scene) is unreachable:
  a probe there is ``"blocked"``, a stroke stops there;
- sensor noise follows SPEC §5 (relative ``sigma_N``; the clean values are kept beside);
- with tactile sensing (``sensing="tactile"``) each contact is pressed by a rigid fingertip of
  hapticsim's hand (radius 8 mm) carrying a pad of the same grid
  (:func:`hapticsim.perception.tactile.press.
  press`: sunk by the skin's penetration at the probe force, facing along the approach), read
  through the skin's sensor model and estimated
  (:func:`hapticsim.perception.tactile.estimate_contact`);
  the estimates replace the contacts (the ray cast's are kept as ``points_exact``), a contact
  the pad does not feel is dropped, and the images of every pad are in the result, with their
  traction fields (:func:`hapticsim.perception.tactile.traction_field`, friction
  :data:`~hapticsim.constants.DEFAULT_FRICTION`): a probe's press carries no tangential load
  (every taxel in contact sticks), a stroke's later contacts slide (every taxel slips, its
  traction ``mu p`` against the pad's motion).

The backend is the simulator: it sees the ground truth, the environment's observation does not.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_float, positive_int
from hapticsim.constants import DEFAULT_FRICTION, FINGERTIP_RADIUS
from hapticsim.envs.support import SUPPORTS, Support
from hapticsim.envs.touch import Touch, TouchBackend, TouchResult
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.geometry.sections import section_walk
from hapticsim.geometry.solid import Solid
from hapticsim.perception.tactile import PadLayout, estimate_contact, load_skin, traction_field
from hapticsim.perception.tactile.pad import DEFAULT_PAD_GRID
from hapticsim.perception.tactile.press import press
from hapticsim.perception.tactile.skin import PROBE_FORCE

Array = NDArray[np.float64]

#: Fingers of the analytic hand (the MuJoCo hand's count when it is available).
DEFAULT_FINGERS: int = 4
class AnalyticBackend(TouchBackend):
    """Touches on the analytic ground truth (see the module docstring).

    Args:
        noise: relative sensor noise sigma_N (SPEC §5): point std ``noise * mean(a)`` [m] per
            coordinate, normal std ``noise`` per component.
        n_fingers: fingers of the hand (the action selects one; the analytic hand treats them
            alike and records the index).
        support: what holds the object (:data:`~hapticsim.envs.support.SUPPORTS`): ``"stand"``
            (a post under its lowest point, as in the MuJoCo scene), ``"table"`` or ``"none"``.
        stroke_spacing: distance between contacts along a stroke [m].
        touch_seconds: simulated duration of a probe [s]; a stroke adds ``stroke_speed``.
        stroke_speed: fingertip speed along a stroke [m/s].
        sensing: ``"exact"`` (the ray cast's contacts) or ``"tactile"`` (module docstring).
        skin: with tactile sensing, the skin (a preset name, a ``.toml`` file or a
            :class:`~hapticsim.perception.tactile.SkinPreset`).
    """

    def __init__(
        self,
        noise: float = 0.0,
        n_fingers: int = DEFAULT_FINGERS,
        support: str = "stand",
        stroke_spacing: float = 0.005,
        touch_seconds: float = 1.0,
        stroke_speed: float = 0.02,
        sensing: str = "exact",
        skin=None,  # noqa: ANN001 - str | Path | SkinPreset
    ) -> None:
        self.noise = finite_float(noise, "noise", 0.0, 1.0)
        self.n_fingers = positive_int(n_fingers, "n_fingers")
        if support not in SUPPORTS:
            raise ChoiceError("support", support, SUPPORTS)
        self.support_kind = support
        self.stroke_spacing = finite_float(stroke_spacing, "stroke_spacing", 1e-4, 1.0)
        self.touch_seconds = finite_float(touch_seconds, "touch_seconds", 0.0)
        self.stroke_speed = finite_float(stroke_speed, "stroke_speed", 1e-6)
        self._truth: Solid | None = None
        self._rng: np.random.Generator | None = None
        self._support: Support | None = None
        self._clock = 0.0
        self._renderer = None
        if sensing not in ("exact", "tactile"):
            raise InvalidInputError(f"`sensing` must be exact or tactile, got {sensing!r}")
        self.sensing = sensing
        #: Coulomb friction of the skin's traction field (tactile sensing).
        self.friction: float = DEFAULT_FRICTION
        self.skin = load_skin(skin) if sensing == "tactile" else None
        self.pad: PadLayout | None = None
        self._pattern = None
        if self.skin is not None:
            rows, cols, pitch = DEFAULT_PAD_GRID
            pad = PadLayout(rows, cols, pitch, FINGERTIP_RADIUS, [0, 0, -1], [0, 1, 0], [0, 0, 0])
            self.pad = pad if self.skin.pitch is None else pad.resampled(self.skin.pitch)
            self._penetration = self.skin.skin.sphere_penetration(FINGERTIP_RADIUS, PROBE_FORCE)

    @property
    def pad_shape(self) -> tuple[int, int, int]:
        """(pads, rows, cols) of the readings with tactile sensing: a pad per finger."""
        if self.pad is None:
            raise InvalidInputError("the analytic backend has no pads without tactile sensing")
        return (self.n_fingers, *self.pad.shape)

    # ------------------------------------------------------------------ episode
    def preparer(self) -> Callable[[Solid], Support]:
        """The support under a shape (:meth:`Support.under`, ~2 ms: the shape's dense surface
        points)."""
        return partial(Support.under, kind=self.support_kind)

    def reset(
        self, shape: Solid, rng: np.random.Generator, rough: Any = None,
        prepared: Support | None = None,
    ) -> Solid:  # fmt: skip
        """Place `shape` as given (its own pose) and start a new episode.

        Args:
            shape: the object.
            rng: the episode's sensor stream (noise, the skin's pattern and readings).
            rough: the vision estimate (unused: ray casting needs no plan; the environment
                aims every touch at its centre).
            prepared: the support under `shape` (:meth:`preparer`), or None to find it here.

        Returns:
            the ground truth, `shape` itself.
        """
        self._truth = shape
        self._rng = rng
        self._clock = 0.0
        self._support = prepared if prepared is not None else self.preparer()(shape)
        if self.skin is not None:  # the episode's sensor: its gains and dead taxels
            self._pattern = self.skin.sensor.pattern((self.n_fingers, *self.pad.shape), rng)
        return shape

    def touch(self, touch: Touch, origin: Array) -> TouchResult:
        """Execute one probe or stroke aimed at `origin` (3,) [m, world].

        Raises:
            InvalidInputError: before :meth:`reset`, or for a finger the hand does not have.
        """
        self._check_touch(touch, True)
        start = time.perf_counter()
        truth = self._truth
        t0 = self._clock
        self._clock += self.touch_seconds
        first, failed = self._approach(truth, touch, origin, start, "the ray missed")
        if first is None:
            return failed  # type: ignore[return-value]
        points = [first]
        n_steps = int(round(touch.stroke_length / self.stroke_spacing))
        if n_steps > 0:
            points += self._stroke(first, touch.stroke_angle, n_steps)
        pts_clean = np.asarray(points)
        nrm_clean = truth.normals(pts_clean)
        k = len(pts_clean)
        duration = np.arange(k) * self.stroke_spacing / self.stroke_speed
        self._clock += float(duration[-1])
        if self.skin is not None:
            return self._felt(touch, pts_clean, nrm_clean, t0 + self.touch_seconds + duration,
                              start)  # fmt: skip
        pts, nrm = self._noisy(pts_clean, nrm_clean)
        return TouchResult(
            points=pts,
            normals=nrm,
            points_clean=pts_clean,
            normals_clean=nrm_clean,
            finger=np.full(k, touch.finger),
            force=np.zeros(k),
            time=t0 + self.touch_seconds + duration,
            status="ok",
            seconds=time.perf_counter() - start,
        )

    def _felt(
        self, touch: Touch, exact: Array, exact_normals: Array, times: Array, start: float
    ) -> TouchResult:
        """The touch's contacts as the pad feels them (module docstring)."""
        skin, pad = self.skin, self.pad
        assert skin is not None and pad is not None and self._rng is not None
        rows, cols = pad.shape
        images, estimates, keep, fields, states = [], [], [], [], []
        area = pad.taxels[2]
        for i, (x, n) in enumerate(zip(exact, exact_normals, strict=True)):
            depth, rot, core = press(self._truth, x, n, touch.approach, pad, self._penetration)
            pressure = np.zeros((self.n_fingers, rows, cols))
            pressure[touch.finger] = skin.skin.pressure(depth, pad.pitch)
            reading = skin.sensor.apply(pressure, self._pattern, self._rng)
            est = estimate_contact(reading[touch.finger], pad, rot, core, skin.skin, skin.sensor)
            if est is not None:
                load = np.zeros((self.n_fingers, 2))
                if i > 0:  # the pad slides from the last contact: friction opposes its motion
                    step = np.stack([rot @ pad.e_u, rot @ pad.up]) @ (exact[i - 1] - x)
                    if np.linalg.norm(step) > 0:
                        load[touch.finger] = step / np.linalg.norm(step)
                field, state = traction_field(pressure, load, self.friction, area)
                images.append(reading.astype(np.float32))
                fields.append(field.astype(np.float32))
                states.append(state)
                estimates.append(est)
                keep.append(i)
        if not estimates:
            return TouchResult.empty("missed", time.perf_counter() - start, "the pad felt nothing")
        pts_clean = np.array([e.point for e in estimates])
        nrm_clean = np.array([e.normal for e in estimates])
        pts, nrm = self._noisy(pts_clean, nrm_clean)
        return TouchResult(
            points=pts, normals=nrm, points_clean=pts_clean, normals_clean=nrm_clean,
            finger=np.full(len(keep), touch.finger), force=np.array([e.force for e in estimates]),
            time=times[keep], status="ok", seconds=time.perf_counter() - start,
            images=np.stack(images), sigma=np.array([e.sigma for e in estimates]),
            traction=np.stack(fields), taxel_state=np.stack(states),
            points_exact=exact[keep], normals_exact=exact_normals[keep],
        )  # fmt: skip

    def _stroke(self, first: Array, stroke_angle: float, n_steps: int) -> list[Array]:
        """Contacts after `first` along the planar section of a stroke (see the module doc)."""
        assert self._truth is not None
        return section_walk(
            self._truth, first, stroke_angle, n_steps, self.stroke_spacing, self._reachable
        )[1:]

    # ------------------------------------------------------------------ rendering
    def render(
        self, estimate: Superquadric | None, points: Array, width: int, height: int
    ) -> NDArray[np.uint8]:
        """The truth (grey), the estimate (translucent blue) and the contacts (red), MuJoCo."""
        if self._truth is None:
            raise InvalidInputError("call `reset` before `render`")
        from hapticsim.envs.rendering import SceneRenderer

        if self._renderer is None:
            self._renderer = SceneRenderer(width, height)
        return self._renderer.render(self._truth, estimate, points, self.support)

    def close(self) -> None:
        """Free the renderer."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
