"""``hapticsim/HapticExplore-v0``: choose touches to recover an object's superquadric shape.

See :class:`HapticExploreEnv`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from hapticsim.data.io import Contacts
from hapticsim.envs.backends import make_backend
from hapticsim.envs.config import HapticExploreConfig
from hapticsim.envs.episode_draw import EpisodeDraw, EpisodeDrawer
from hapticsim.envs.estimator import FitSchedule, FitUpdate, IncrementalFitter
from hapticsim.envs.observation import OBS_BOUND, encode_fit
from hapticsim.envs.touch import ACTION_DIM, TouchResult, decode_action
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import N_PARAMS, Superquadric
from hapticsim.geometry.solid import Solid
from hapticsim.metrics.coverage import coverage_uncertainty
from hapticsim.metrics.episode import TruthScorer
from hapticsim.perception.vision import DepthCamera

Array = NDArray[np.float64]

@dataclass(frozen=True)
class StepTimings:
    """Wall-clock times of one step [s].

    Measurements, not environment state: two timings always compare equal, so that seeded
    episodes give equal ``info`` dictionaries (Gymnasium's determinism checks).

    Attributes:
        touch: executing the touch (simulation or ray casting) [s].
        fit: updating the estimate [s].
        metrics: scoring it against the truth [s].
        step: the whole step [s].
    """

    touch: float = field(default=0.0, compare=False)
    fit: float = field(default=0.0, compare=False)
    metrics: float = field(default=0.0, compare=False)
    step: float = field(default=0.0, compare=False)

    def to_dict(self) -> dict[str, float]:
        """``{"touch", "fit", "metrics", "step"}`` [s]."""
        return {"touch": self.touch, "fit": self.fit, "metrics": self.metrics, "step": self.step}


class HapticExploreEnv(gym.Env[dict[str, np.ndarray], np.ndarray]):
    """Haptic exploration of one object: each step is one touch, the goal a good superquadric.

    An episode draws an object (the paper's four bodies by default, or random superquadrics,
    tapered or not) and keeps it in a fixed pose. The agent knows only the object's rough
    position (the centre of a vision estimate from one noisy depth image, plus a calibration
    error of ``position_noise`` per axis; :attr:`rough`), the origin of the *object-centred
    frame* (axes parallel to the world's); the MuJoCo hand plans its palm poses on that
    estimate. Each action is one touch, a probe or a short contour stroke, executed by a
    scripted controller of the MuJoCo hand (or, with ``backend="analytic"``, by ray casting on
    the analytic surface). The contacts so far are
    fitted by a superquadric (robust ``nH`` fits where they pay, warm-started least squares in
    between; see :class:`~hapticsim.envs.estimator.FitSchedule`).

    ## Action space

    ``Box(-1, 1, (5,), float32)``, one touch (:mod:`hapticsim.envs.touch`):

    | Num | Action             | Min | Max | Mapping                                       | Unit  |
    |-----|--------------------|-----|-----|-----------------------------------------------|-------|
    | 0   | approach azimuth   | -1  | 1   | phi = pi * a0                                 | rad   |
    | 1   | approach elevation | -1  | 1   | sin(elevation) = a1 (uniform on the sphere)   | rad   |
    | 2   | stroke direction   | -1  | 1   | psi = pi * a2 in the contact's tangent plane, | rad   |
    |     |                    |     |     | 0 horizontal (z x n), pi/2 upward             |       |
    | 3   | stroke length      | -1  | 1   | L = (a3 + 1) / 2 * max_stroke, a probe when   | m     |
    |     |                    |     |     | L < stroke_spacing                            |       |
    | 4   | finger             | -1  | 1   | floor((a4 + 1) / 2 * n_fingers), 0 = thumb    | index |

    The fingertip comes from far along the approach direction ``(cos el cos phi, cos el sin phi,
    sin el)`` (object-centred frame) towards the rough position and stops at the first contact;
    a stroke then follows the contour in the plane spanned by that contact's normal and the
    stroke direction, one contact every ``stroke_spacing`` metres (up to 11 per touch with the
    defaults). The object stands on a thin post (as in the MuJoCo scene): a contact where the
    fingertip would hit it is unreachable (the touch is ``"blocked"``, a stroke stops there).
    The finger matters to the hand (reach, palm placement); the analytic backend records it.

    ## Observation space

    ``Dict``; M = ``max_contacts``, s = ``obs_scale`` [m], all float32 but the masks:

    | Key        | Shape   | Content                                                  | Unit   |
    |------------|---------|----------------------------------------------------------|--------|
    | points     | (M, 3)  | contact points minus the rough position, divided by s,   | 1      |
    |            |         | in order of arrival, 0 where ``mask`` is 0               |        |
    | normals    | (M, 3)  | measured outward unit normals, 0 where ``mask`` is 0     | 1      |
    | mask       | (M,)    | MultiBinary: 1 for a filled buffer slot                  | -      |
    | fit        | (13,)   | current estimate: a / s (3), (eps - 1.05) / 0.95 (2),    | 1      |
    |            |         | taper (2), rotation vector / pi (3),                     |        |
    |            |         | (centre - rough position) / s (3); 0 without a fit       |        |
    | fit_valid  | (1,)    | MultiBinary: 1 once a fit exists (>= 13 contacts)        | -      |
    | eof        | (1,)    | sqrt(error of fit) / s of the estimate; 0 without a fit  | 1      |
    | touches    | (1,)    | touches made so far, in [0, touch_budget]                | count  |

    Scaled values are clipped to [-10, 10]. The observation never holds the ground truth;
    :func:`~hapticsim.envs.observation.decode_fit` turns ``fit`` back into a
    :class:`~hapticsim.geometry.Superquadric`.

    ## Rewards

    - ``"epsilon"`` (default, **privileged**: uses the ground truth, for studying strategies, not
      available on a robot): ``epsilon_{t-1} - epsilon_t``, epsilon = alpha + beta of the
      estimate against the truth (SPEC §4); epsilon = 1 while there is no estimate (all of the
      object missed), so an episode's return is ``1 - epsilon_final``.
    - ``"uncertainty"``: ``U_{t-1} - U_t``, U the
      :func:`~hapticsim.metrics.coverage.coverage_uncertainty` of the estimate (1 without one);
      no ground truth.
    - ``"eof"``: ``e_{t-1} - e_t``, ``e = min(1, sqrt(EOF) / mean(a))`` of the estimate (1 without
      one); no ground truth, but it rewards touching where the fit is already good.

    ## Episode end

    Truncated after ``touch_budget`` touches (default 20); terminated when epsilon <=
    ``target_epsilon`` (privileged, off by default).

    ## Info

    ``alpha``, ``beta``, ``epsilon``, ``iou``, ``chamfer`` [m] of the estimate against the truth
    (before the first fit: 0, 1, 1, 0, inf); ``n_contacts``, ``new_contacts``, ``touch_status``
    (``ok``, ``missed``, ``blocked``, ``failed``), ``fit_status`` (``too_few_contacts``, ``full``,
    ``refine``, ``kept``, ``failed``), ``fit_eof`` [m^2], ``fit_evaluations``; ``timings``
    (:class:`StepTimings`: touch, fit, metrics, step [s]);
    ``estimate`` (:class:`~hapticsim.geometry.Superquadric`), ``solid`` (what is scored: the
    estimate, or a ``multi`` schedule's union) and ``truth`` (the solid, world frame),
    ``origin`` (rough position [m, world]), ``uncertainty`` (reward ``"uncertainty"`` only).
    All contacts, with fingers, forces [N] (MuJoCo; 0 on the analytic backend), times [s] and
    clean values, are in :attr:`contacts`.

    ## Arguments

    ``render_mode`` (None or ``"rgb_array"``, offscreen MuJoCo: set ``MUJOCO_GL=egl``) and the
    fields of :class:`HapticExploreConfig` as keywords (or ``config=``).
    ``reset(options={"shape": solid})`` explores the given object instead of
    drawing one.

    ## Version history

    - v0: initial version; ``sensing="tactile"`` (contacts estimated from taxel pads) added
      later, the observation unchanged.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 2}

    def __init__(
        self,
        render_mode: str | None = None,
        config: HapticExploreConfig | None = None,
        **kwargs: Any,
    ) -> None:
        if config is not None and kwargs:
            raise InvalidInputError("give either `config` or keyword arguments, not both")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise InvalidInputError(
                f"`render_mode` must be None or one of {self.metadata['render_modes']}, got "
                f"{render_mode!r}"
            )
        if "fit" in kwargs and isinstance(kwargs["fit"], dict):
            kwargs["fit"] = FitSchedule(**kwargs["fit"])
        self.config = config if config is not None else HapticExploreConfig(**kwargs)
        self.render_mode = render_mode
        self._backend = make_backend(self.config)

        width, height = self.config.camera_size
        self._camera = DepthCamera(width=width, height=height)
        self._drawer = EpisodeDrawer(self.config.objects, self._camera,
                                     self.config.position_noise, self._backend.preparer())
        self._ahead: EpisodeDraw | None = None
        #: resets that used draws made ahead (:meth:`offer_draw`)
        self.resets_drawn_ahead = 0
        self.n_fingers = int(self._backend.n_fingers)
        self._fitter = IncrementalFitter(self.config.fit)

        m = self.config.max_contacts
        b = OBS_BOUND
        self.observation_space = spaces.Dict(
            {
                "points": spaces.Box(-b, b, (m, 3), np.float32),
                "normals": spaces.Box(-1.0, 1.0, (m, 3), np.float32),
                "mask": spaces.MultiBinary(m),
                "fit": spaces.Box(-b, b, (N_PARAMS,), np.float32),
                "fit_valid": spaces.MultiBinary(1),
                "eof": spaces.Box(0.0, b, (1,), np.float32),
                "touches": spaces.Box(0.0, float(self.config.touch_budget), (1,), np.float32),
            }
        )
        self.action_space = spaces.Box(-1.0, 1.0, (ACTION_DIM,), np.float32)
        self._truth: Solid | None = None
        self._rough = None
        self._truth_scorer = None
        self._origin = np.zeros(3)
        self._clear()

    # ------------------------------------------------------------------ state
    def _clear(self) -> None:
        self._points: list[Array] = []
        self._normals: list[Array] = []
        keys = ("points_clean", "normals_clean", "finger", "force", "time", "touch")
        if self.config.sensing == "tactile":
            keys += ("points_exact", "normals_exact", "sigma")
        self._extra: dict[str, list[np.ndarray]] = {k: [] for k in keys}
        #: the pads' readings [Pa] at the last contact (tactile sensing), or None.
        self._last_images: NDArray[np.float32] | None = None
        #: the pads' traction fields [Pa] and taxel states at the last contact, or None.
        self._last_traction: NDArray[np.float32] | None = None
        self._last_taxel_state: NDArray[np.int8] | None = None
        self._touches = 0
        self._update = FitUpdate(None, 0.0, "too_few_contacts")
        self._metrics = _NO_FIT_METRICS.copy()
        self._scored: Solid | None = None
        self._progress = 1.0  # the quantity whose drop is the reward

    @property
    def last_images(self) -> NDArray[np.float32] | None:
        """(pads, rows, cols) float, every pad's reading [Pa] at the last recorded contact with
        tactile sensing; None before it, and with exact sensing (the tactile variant's
        observation, :mod:`hapticsim.envs.haptic_explore_tactile_v0`)."""
        return self._last_images

    @property
    def last_traction(self) -> tuple[NDArray[np.float32], NDArray[np.int8]] | None:
        """Every pad's traction field (pads, rows, cols, 3) [Pa] and taxel states (pads, rows,
        cols) at the last recorded contact with tactile sensing (SPEC §11); None before it and
        with exact sensing (``hapticsim/HapticExploreTactile-v1``'s observation)."""
        if self._last_traction is None or self._last_taxel_state is None:
            return None
        return self._last_traction, self._last_taxel_state

    @property
    def truth(self) -> Solid | None:
        """The ground truth of the episode (world frame), privileged."""
        return self._truth

    @property
    def rough(self):  # noqa: ANN201 - hapticsim.perception.vision.RoughObject
        """What the planner was given this episode: the vision estimate
        (:func:`hapticsim.perception.vision.vision_estimate`) moved to the rough position; None
        before
        the first reset."""
        return self._rough

    @property
    def origin(self) -> Array:
        """(3,) float, the object's rough position [m, world]: origin of the object frame."""
        return self._origin.copy()

    @property
    def estimate(self) -> Superquadric | None:
        """The current estimate (world frame), None before the first fit."""
        return self._update.estimate

    @property
    def solid(self) -> Solid | None:
        """The estimated solid scored each step: the estimate, or with a ``multi`` fit schedule
        the union of its last full fit (:class:`~hapticsim.envs.estimator.FitSchedule`)."""
        return self._update.solid

    @property
    def contacts(self):  # noqa: ANN201 - hapticsim.data.io.Contacts
        """All contacts so far as :class:`hapticsim.data.io.Contacts` (world frame), with extra
        arrays ``points_clean``, ``normals_clean``, ``finger``, ``force`` [N], ``time`` [s] and
        ``touch`` (index of the touch that made each contact); with tactile sensing also
        ``points_exact``, ``normals_exact`` (the true contacts the estimates stand for) and
        ``sigma`` [m]."""

        pts, nrm = self._stacked()
        vectors = ("points_clean", "normals_clean", "points_exact", "normals_exact")
        extra = {
            k: (np.concatenate(v) if v else np.zeros((0, 3) if k in vectors else 0))
            for k, v in self._extra.items()
        }
        return Contacts(points=pts, normals=nrm, extra=extra)

    def _stacked(self) -> tuple[Array, Array]:
        if not self._points:
            return np.zeros((0, 3)), np.zeros((0, 3))
        return np.concatenate(self._points), np.concatenate(self._normals)

    @property
    def drawer(self) -> EpisodeDrawer:
        """What a reset draws before the backend builds the episode (picklable)."""
        return self._drawer

    def offer_draw(self, draw: EpisodeDraw) -> None:
        """Give the next reset its draws, made ahead (:meth:`EpisodeDrawer.draw` on a copy of
        :attr:`np_random`, packed or not: :meth:`EpisodeDrawer.pack`). That reset uses them only
        if it is given no shape and finds the generator in the state they start from (after
        any seeding); otherwise it draws its own. Either way its results are the same, bit for
        bit; only its time differs."""
        if not isinstance(draw, EpisodeDraw):
            raise InvalidInputError(f"`draw` must be an EpisodeDraw, got {type(draw).__name__}")
        self._ahead = self._drawer.unpack(draw)

    # ------------------------------------------------------------------ gymnasium API
    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Start an episode on a new object (see the class docstring)."""
        super().reset(seed=seed)
        options = options or {}
        shape = options.get("shape")
        if shape is not None and not isinstance(shape, Solid):
            raise InvalidInputError(
                "`options['shape']` must be a solid (Superquadric, SuperquadricUnion or "
                f"MeshSolid), got {type(shape).__name__}"
            )
        self._clear()
        self._fitter.reset()
        # What the robot knows before touching: one depth image's estimate, off by the
        # camera-to-hand calibration error. The fitter and the sensor draw from streams of their
        # own, seeded here: an episode's object, noise and rough position (and, for a policy
        # that ignores the estimate, its contacts) do not depend on how many fits ran, so two
        # fitters can be compared on the same contacts; and the next episode's object does not
        # depend on how many contacts this one made, so every policy meets the same objects.
        # The draws are made here, or ahead by another process from the state the generator
        # is in now (then they are the same numbers, bit for bit).
        ahead, self._ahead = self._ahead, None
        if (ahead is not None and shape is None
                and ahead.state == self.np_random.bit_generator.state):  # fmt: skip
            drawn = ahead
            self.np_random.bit_generator.state = ahead.after
            self.resets_drawn_ahead += 1
        else:
            drawn = self._drawer.draw(self.np_random, shape)
        self._fit_rng = np.random.default_rng(drawn.fit_seed)
        self._rough = drawn.rough
        self._truth = self._backend.reset(
            drawn.shape, np.random.default_rng(drawn.sensor_seed), rough=self._rough,
            prepared=drawn.prepared,
        )
        self._origin = self._rough.center.copy()
        info = self._info(TouchResult.empty("ok"), 0.0, 0.0, 0.0)
        return self._observation(), info

    def step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """One touch, a refit and the reward (see the class docstring)."""
        if self._truth is None:
            raise InvalidInputError("call `reset` before `step`")
        start = time.perf_counter()
        touch = decode_action(
            action, self.config.max_stroke, self.config.stroke_spacing, self.n_fingers
        )
        result = self._backend.touch(touch, self._origin)
        if len(result):
            self._points.append(result.points)
            self._normals.append(result.normals)
            for k in self._extra:
                if k != "touch":
                    self._extra[k].append(getattr(result, k))
            self._extra["touch"].append(np.full(len(result), self._touches, np.int64))
            if result.images is not None:
                self._last_images = result.images[-1]
            if result.traction is not None and result.taxel_state is not None:
                self._last_traction = result.traction[-1]
                self._last_taxel_state = result.taxel_state[-1]
        self._touches += 1

        pts, nrm = self._stacked()
        self._update = self._fitter.update(pts, nrm, self._fit_rng, new_contacts=len(result))
        metric_start = time.perf_counter()
        if self.config.compute_metrics:
            self._metrics = self._score(self._update.solid)
        metric_seconds = time.perf_counter() - metric_start

        progress = self._progress_value(pts)
        reward = float(self._progress - progress)
        reward -= self.config.displacement_penalty * result.object_moved
        self._progress = progress
        terminated = bool(
            self.config.target_epsilon is not None
            and self._metrics["epsilon"] <= self.config.target_epsilon
        )
        truncated = self._touches >= self.config.touch_budget
        info = self._info(result, self._update.seconds, metric_seconds, time.perf_counter() - start)
        return self._observation(), reward, terminated, bool(truncated), info

    def render(self) -> NDArray[np.uint8] | None:
        """An RGB picture (``render_mode="rgb_array"``): truth, estimate and contacts."""
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array'")
            return None
        if self._truth is None:
            raise InvalidInputError("call `reset` before `render`")
        pts, _ = self._stacked()
        return self._backend.render(self.estimate, pts, self.config.width, self.config.height)

    def close(self) -> None:
        """Free the backend (simulation and renderer)."""
        self._backend.close()
        super().close()

    @property
    def backend(self) -> Any:
        """The touch backend (:mod:`hapticsim.envs.backends`): the MuJoCo hand's simulation or
        the analytic ray caster."""
        return self._backend

    # ------------------------------------------------------------------ internals
    def _score(self, estimate: Solid | None) -> dict[str, float]:
        if estimate is None:
            return _NO_FIT_METRICS.copy()
        if estimate is self._scored:  # kept estimate: same score
            return dict(self._metrics)
        self._scored = estimate
        return self._scorer().score(estimate).to_dict()

    def _scorer(self):  # noqa: ANN202 - hapticsim.metrics.episode.TruthScorer
        """The scorer of this episode's truth (made on first use, its random numbers fixed)."""
        if self._truth_scorer is None or self._truth_scorer.truth is not self._truth:

            if self._truth_scorer is None:
                self._truth_scorer = TruthScorer(
                    self._truth, self.config.metric_samples, self.config.chamfer_samples, rng=0
                )
            # the truth's samples always come from with_truth, so that an instance's first
            # episode scores as a later one with the same seed does
            self._truth_scorer = self._truth_scorer.with_truth(self._truth, rng=0)
        return self._truth_scorer

    def _progress_value(self, points: Array) -> float:
        estimate = self._update.estimate
        if self.config.reward == "epsilon":
            return self._metrics["epsilon"]
        if self.config.reward == "uncertainty":
            return coverage_uncertainty(estimate, points)
        if estimate is None:
            return 1.0
        return float(min(1.0, np.sqrt(self._update.eof) / float(np.mean(estimate.a))))

    def _observation(self) -> dict[str, np.ndarray]:
        m, s = self.config.max_contacts, self.config.obs_scale
        pts, nrm = self._stacked()
        k = min(len(pts), m)
        points = np.zeros((m, 3), np.float32)
        normals = np.zeros((m, 3), np.float32)
        mask = np.zeros(m, np.int8)
        points[:k] = np.clip((pts[:k] - self._origin) / s, -OBS_BOUND, OBS_BOUND)
        normals[:k] = np.clip(nrm[:k], -1.0, 1.0)
        mask[:k] = 1
        estimate = self._update.estimate
        eof = np.sqrt(max(self._update.eof, 0.0)) / s if estimate is not None else 0.0
        return {
            "points": points,
            "normals": normals,
            "mask": mask,
            "fit": encode_fit(estimate, self._origin, s),
            "fit_valid": np.array([estimate is not None], np.int8),
            "eof": np.array([min(eof, OBS_BOUND)], np.float32),
            "touches": np.array([self._touches], np.float32),
        }

    def _info(
        self, result: TouchResult, fit_seconds: float, metric_seconds: float, step_seconds: float
    ) -> dict[str, Any]:
        pts, _ = self._stacked()
        info: dict[str, Any] = dict(self._metrics)
        info.update(
            n_contacts=len(pts),
            new_contacts=len(result),
            touch_status=result.status,
            fit_status=self._update.status,
            fit_eof=float(self._update.eof),
            fit_evaluations=int(self._update.evaluations),
            timings=StepTimings(
                float(result.seconds),
                float(fit_seconds),
                float(metric_seconds),
                float(step_seconds),
            ),
            estimate=self._update.estimate,
            solid=self._update.solid,
            truth=self._truth,
            origin=self._origin.copy(),
            object_moved=float(result.object_moved),
            object_turned=float(result.object_turned),
        )
        if self.config.reward == "uncertainty":
            info["uncertainty"] = self._progress
        return info


_NO_FIT_METRICS: dict[str, float] = {
    "alpha": 0.0, "beta": 1.0, "epsilon": 1.0, "iou": 0.0, "chamfer": float("inf"),
}  # fmt: skip
