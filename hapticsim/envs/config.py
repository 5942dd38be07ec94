"""The settings of ``HapticExplore-v0`` (:class:`HapticExploreConfig`), checked once when made;
every variant wraps a core environment made from them."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import SCORE_CHAMFER_POINTS, SCORE_SAMPLES, SENSINGS, STEERINGS
from hapticsim.data.distributions import ObjectDistribution, ObjectSet
from hapticsim.envs.backends import BACKENDS
from hapticsim.envs.estimator import FitSchedule
from hapticsim.envs.support import SUPPORTS
from hapticsim.errors import ChoiceError, InvalidInputError

Array = NDArray[np.float64]

#: Reward definitions.
REWARDS: tuple[str, ...] = ("epsilon", "uncertainty", "eof")


@dataclass(frozen=True)
class HapticExploreConfig:
    """Everything that defines the environment (the keyword arguments of the constructor).

    Attributes:
        backend: ``"mujoco"`` (the simulated hand) or ``"analytic"`` (ray casting on the true
            superquadric; fast, same action semantics).
        objects: the object distribution, or one of its kind names (``"paper"``, ``"random"``,
            ``"random_tapered"``); or any object or list of objects (body names, superquadric
            JSON files, union JSON files, ``random``/``random_tapered``, mesh files, or solids:
            :class:`~hapticsim.data.distributions.ObjectSet`), one drawn per episode.
        touch_budget: touches per episode; the episode is truncated after it.
        max_contacts: size of the observation's contact buffer (later contacts are still fitted
            but not shown).
        max_stroke: stroke length of action component 3 = 1 [m].
        stroke_spacing: distance between contacts along a stroke [m].
        noise: relative sensor noise sigma_N (SPEC §5).
        position_noise: standard deviation per axis [m] of the camera-to-hand calibration error
            added to the vision estimate's centre
            (:func:`hapticsim.perception.vision.vision_estimate`,
            one noisy depth image); the result is the rough position, the origin of the
            object-centred frame.
        obs_scale: length [m] dividing points, semi-axes and centre in the observation.
        reward: ``"epsilon"`` (privileged: the drop of the volume error epsilon of the estimate
            against the ground truth), ``"uncertainty"`` (drop of the coverage uncertainty of the
            estimate, no ground truth) or ``"eof"`` (drop of the estimate's normalised RMS error of
            fit, no ground truth).
        target_epsilon: terminate when epsilon falls to this value (privileged); None: never.
        fit: the fit schedule.
        support: what holds the object up in the analytic backend: ``"stand"`` (a thin post
            under it, as in the MuJoCo scene, which always has one), ``"table"`` or ``"none"``;
            contacts where a fingertip would hit it are unreachable.
        camera_size: (width, height) [px] of the depth image of the vision estimate made at
            every reset (:class:`hapticsim.perception.vision.DepthCamera`, otherwise its defaults):
            half
            the resolution of ``hapticsim explore``'s 320 x 240, which halves the cost of a
            reset (about 25 ms of CPU) for a rough centre about 1 mm worse (median 6 mm).
        hand: the MuJoCo backend's hand: ``"hapticsim"`` (default, four fingers), ``"shadow"``
            or ``"adroit"`` (five fingers; the optional extra ``hands``), or the path of a TOML
            hand description (``docs/hands.md``); the finger count sets what action component 4
            selects. The analytic backend has no hand and ignores it.
        compute_metrics: score the estimate against the truth every step (info); forced on for
            ``reward="epsilon"`` and ``target_epsilon``.
        metric_samples: samples inside each solid for alpha, beta, epsilon and IoU, scored by
            :class:`hapticsim.metrics.episode.TruthScorer` (scrambled Sobol samples drawn once,
            so successive scores share them and their difference, the reward, is far less
            noisy; RMS error of epsilon 0.0032 measured at the default 4096 for superquadrics).
        chamfer_samples: surface points per shape of the Chamfer distance (a superquadric: an
            evenly spread lattice of directions, area-weighted, exact point-to-surface
            distances, RMS error 1.2 % at the default 128; other solids: area samples).
        width, height: size of rendered pictures [pixels].
        sensing: ``"exact"`` (the backend's exact contacts) or ``"tactile"``: contacts
            estimated from taxel pads on the fingertips (the MuJoCo hand's,
            :mod:`hapticsim.sim.tactile`; on the analytic backend a rigid fingertip pad pressed
            on the exact surface); the observation stays v0's
            (``hapticsim/HapticExploreTactile-v0`` adds the taxel images).
        skin: with tactile sensing, the skin: a preset (``"ideal"``, ``"vision"``,
            ``"capacitive"``) or a ``.toml`` skin file (stored as the loaded preset).
        steer_on: with tactile sensing on the MuJoCo backend, what the hand's controllers steer
            on: ``"skin"`` (default: each touching pad's estimated contact) or ``"contacts"``
            (MuJoCo's; :class:`~hapticsim.sim.scene.SceneConfig`). The analytic backend has no
            controllers: its touches are ray casts.
        object_dynamics: the MuJoCo backend's object (SPEC §12): ``"fixed"`` (default),
            ``"resting"`` or ``"held"``, or an :class:`~hapticsim.sim.dynamics.ObjectDynamics`
            (stored as one); info's ``object_moved`` [m] and ``object_turned`` [deg] say how
            far each touch moved it. The analytic backend has no physics: fixed only.
        force_limit: the MuJoCo hand's force limit [N] (:class:`~hapticsim.sim.scene.SceneConfig`);
            None: none. Not for the analytic backend.
        displacement_penalty: subtracted from the reward per metre the touch moved the object's
            centre (info's ``object_moved``), >= 0; 0 (default): none. 10 costs 0.01 per mm,
            about a touch's typical drop of epsilon.
    """

    backend: str = "mujoco"
    objects: ObjectDistribution | ObjectSet | Any = "paper"
    touch_budget: int = 20
    max_contacts: int = 256
    max_stroke: float = 0.05
    stroke_spacing: float = 0.005
    noise: float = 0.02
    position_noise: float = 0.005
    obs_scale: float = 0.1
    reward: str = "epsilon"
    target_epsilon: float | None = None
    fit: FitSchedule = field(default_factory=FitSchedule)
    support: str = "stand"
    hand: str | os.PathLike[str] = "hapticsim"
    camera_size: tuple[int, int] = (160, 120)
    compute_metrics: bool = True
    metric_samples: int = SCORE_SAMPLES
    chamfer_samples: int = SCORE_CHAMFER_POINTS
    width: int = 480
    height: int = 360
    sensing: str = "exact"
    skin: Any = "ideal"
    steer_on: str = "skin"
    object_dynamics: Any = "fixed"
    force_limit: float | None = None
    displacement_penalty: float = 0.0

    def __post_init__(self) -> None:
        size = self.camera_size
        if (
            not isinstance(size, (tuple, list))
            or len(size) != 2
            or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v >= 8
                       for v in size)
        ):  # fmt: skip
            raise InvalidInputError(
                f"`camera_size` must be (width, height), two ints >= 8 [px], got {size!r}"
            )
        object.__setattr__(self, "camera_size", (int(size[0]), int(size[1])))
        if self.backend not in BACKENDS:
            raise ChoiceError("backend", self.backend, BACKENDS)
        if self.support not in SUPPORTS:
            raise ChoiceError("support", self.support, SUPPORTS)
        if self.reward not in REWARDS:
            raise ChoiceError("reward", self.reward, REWARDS)
        object.__setattr__(self, "objects", ObjectDistribution.coerce(self.objects))
        if not isinstance(self.hand, (str, os.PathLike)) and not hasattr(self.hand, "fingers"):
            raise InvalidInputError(
                f"`hand` must be a hand name or a TOML description path, got {self.hand!r}"
            )
        if not isinstance(self.fit, FitSchedule):
            raise InvalidInputError(f"`fit` must be a FitSchedule, got {type(self.fit).__name__}")
        for name in ("touch_budget", "max_contacts", "width", "height"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
                raise InvalidInputError(f"`{name}` must be an int >= 1, got {value!r}")
        for name, low in (("metric_samples", 1000), ("chamfer_samples", 10)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
                raise InvalidInputError(f"`{name}` must be an int >= {low}, got {value!r}")
        for name, low, high in (
            ("max_stroke", 0.0, 1.0), ("stroke_spacing", 1e-4, 1.0), ("noise", 0.0, 1.0),
            ("position_noise", 0.0, 0.1), ("obs_scale", 1e-3, 10.0),
        ):  # fmt: skip
            value = getattr(self, name)
            if (
                not isinstance(value, (int, float))
                or not np.isfinite(value)
                or not (low <= value <= high)
            ):
                raise InvalidInputError(f"`{name}` must be in [{low}, {high}], got {value!r}")
        if self.target_epsilon is not None and not 0.0 <= float(self.target_epsilon) <= 2.0:
            raise InvalidInputError(
                f"`target_epsilon` must be None or in [0, 2], got {self.target_epsilon!r}"
            )
        if self.reward == "epsilon" or self.target_epsilon is not None:
            object.__setattr__(self, "compute_metrics", True)
        if self.sensing not in SENSINGS:
            raise ChoiceError("sensing", self.sensing, SENSINGS)
        if self.steer_on not in STEERINGS:
            raise ChoiceError("steer_on", self.steer_on, STEERINGS)
        from hapticsim.perception.tactile import load_skin
        from hapticsim.sim.dynamics import dynamics_arg

        object.__setattr__(self, "skin", load_skin(self.skin))
        object.__setattr__(self, "object_dynamics", dynamics_arg(self.object_dynamics))
        penalty = self.displacement_penalty
        if isinstance(penalty, bool) or not isinstance(penalty, (int, float)) or not (
            np.isfinite(penalty) and penalty >= 0.0
        ):
            raise InvalidInputError(
                f"`displacement_penalty` must be a finite number >= 0 [1/m], got {penalty!r}"
            )
        if self.backend == "analytic" and (self.object_dynamics.free or self.force_limit
                                           is not None or penalty > 0):  # fmt: skip
            raise InvalidInputError(
                "`object_dynamics`, `force_limit` and `displacement_penalty` need the MuJoCo "
                "backend (the analytic one has no physics)"
            )


__all__ = ["REWARDS", "HapticExploreConfig"]
