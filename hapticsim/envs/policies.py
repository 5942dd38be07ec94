"""Baseline exploration policies for ``hapticsim/HapticExplore-v0``, and an episode runner.

A policy sees only the observation (and the environment's public configuration: length scale,
stroke length, finger count, budget), never the ground truth:

- :class:`RandomPolicy`: uniform random touches.
- :class:`PaperPolicy`: the paper's scripted pattern (Bierbaum et al., III-A, IV), as the hand's
  ``paper`` strategy: a corner patch, then three fingers stroking side by side across an edge
  while the thumb probes a corner, for three edges; open loop, the same 20 touches every time.
- :class:`UncertaintyPolicy`: touch where the current estimate is least supported by contacts:
  among candidate approach directions, the one whose predicted contact (ray cast on the
  estimate) lies farthest from every contact so far, then stroke towards the least supported
  neighbourhood. Before the first fit, a sphere around the rough position stands in for the
  estimate.
- :class:`InformationPolicy`: the same candidates, scored by the expected information of a
  contact under the estimate's Laplace posterior (the drop of its surface variance, or of its
  parameters' entropy) instead of the coverage gap.
- :class:`LearnedPolicy`: a trained actor (:mod:`hapticsim.envs.learned`, numpy only) on the
  compact observation of ``HapticExploreCompact-v0``
  (:class:`~hapticsim.envs.haptic_explore_compact_v0.CompactObserver`), which it computes
  itself from the v0 observation. ``"learned"`` is the actor shipped in the package (trained by
  ``scripts/train_policy.py``; recipe and results in ``docs/policies/learned/``),
  ``"learned:PATH"`` any weight file. ``"learned-touch"`` is the shipped actor that learned
  from the touch history itself (``hapticsim/HapticExploreTouch-v0``'s observation,
  :class:`~hapticsim.envs.haptic_explore_touch_v0.TouchObserver`: contacts, normals and past
  touches encoded by a permutation-invariant network; ``docs/policies/learned_touch/``); a
  weight file trained on any of these observations (or on
  ``hapticsim/HapticExploreTouchTactile-v0``'s, which adds each touch's pad image and runs on
  tactile environments only) runs as ``"learned:PATH"``.

All take ``rng`` (seed or generator) and are deterministic given it (the learned policy is
deterministic and ignores it).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import DEFAULT_LAMBDA
from hapticsim.envs import haptic_explore_compact_v0 as v1
from hapticsim.envs import haptic_explore_touch_v0 as touch_env
from hapticsim.envs.haptic_explore_compact_v0 import estimate_from_observation, observed_contacts
from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
from hapticsim.envs.learned import MEANING_SETTINGS, load_actor
from hapticsim.envs.registration import canonical_id
from hapticsim.envs.touch import encode_touch
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.fitting.uncertainty import (
    expected_information,
    expected_surface_reduction,
    posterior_covariance,
    with_prior,
)
from hapticsim.geometry import N_PARAMS, Superquadric, random_rotation
from hapticsim.geometry.rays import raycast_many
from hapticsim.geometry.sampling import fibonacci_sphere
from hapticsim.geometry.sections import tangent_frame

Array = NDArray[np.float64]
Observation = dict[str, np.ndarray]

#: Prefix of a policy name that gives a weight file: ``"learned:PATH"``.
LEARNED_PREFIX: str = "learned:"
#: The weight file of the shipped ``"learned"`` policy.
LEARNED_WEIGHTS: Path = Path(__file__).with_name("data") / "learned_policy.npz"
#: The weight file of the shipped ``"learned-touch"`` policy.
LEARNED_TOUCH_WEIGHTS: Path = Path(__file__).with_name("data") / "learned_touch_policy.npz"
#: The observations a learned actor can be trained on: environment id -> (observation size,
#: its observer made from the v0 observation's length scale).
LEARNED_OBSERVATIONS: dict[str, tuple[int, Callable[[float], Any]]] = {
    v1.ENV_ID: (v1.OBS_DIM, v1.CompactObserver),
    touch_env.ENV_ID: (touch_env.OBS_DIM, lambda obs_scale: touch_env.TouchObserver()),
    touch_env.TACTILE_ENV_ID: (
        touch_env.TACTILE_OBS_DIM,
        lambda obs_scale: touch_env.TouchObserver(taxels=True),
    ),
}


class Policy:
    """A policy: ``action = policy(observation)``; :meth:`reset` at each episode start.

    Args:
        env: the environment (unwrapped or wrapped); only its configuration is read.
        rng: seed or generator of the policy's own random choices.
    """

    name = "policy"

    def __init__(self, env: Any, rng: np.random.Generator | int | None = None) -> None:
        base: HapticExploreEnv = env.unwrapped
        self.config = base.config
        self.n_fingers = base.n_fingers
        self.action_space = base.action_space
        self.rng = np.random.default_rng(rng)

    def reset(self, rng: np.random.Generator | int | None = None) -> None:
        """Start a new episode (reseed when `rng` is given)."""
        if rng is not None:
            self.rng = np.random.default_rng(rng)

    def __call__(self, obs: Observation) -> NDArray[np.float32]:
        raise NotImplementedError

    def _action(
        self, approach: Array, stroke_angle: float, stroke_fraction: float, finger: int
    ) -> NDArray[np.float32]:
        return encode_touch(
            approach, stroke_angle, stroke_fraction * self.config.max_stroke, finger,
            self.config.max_stroke, self.n_fingers,
        )  # fmt: skip


class RandomPolicy(Policy):
    """Uniformly random actions: approach directions uniform on the sphere, any stroke."""

    name = "random"

    def __call__(self, obs: Observation) -> NDArray[np.float32]:
        return self.rng.uniform(-1.0, 1.0, size=self.action_space.shape).astype(np.float32)


def _direction(azimuth_deg: float, elevation_deg: float) -> Array:
    az, el = np.radians(azimuth_deg), np.radians(elevation_deg)
    return np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])


#: The paper pattern: (azimuth [deg], elevation [deg], stroke angle [deg], stroke length as a
#: fraction of ``max_stroke``, finger: 0 thumb, 1 index, 2 middle, 3 ring, clipped to the hand).
#: As the hand's ``paper`` strategy (:mod:`hapticsim.sim.strategies.library`): a corner patch,
#: then three sweeps, each with three fingers side by side across an edge and the thumb on a
#: corner at the end of that edge (top-front, bottom-back, back-right), then fill-in touches.
PAPER_PATTERN: tuple[tuple[float, float, float, float, int], ...] = (
    # corner patch at the (+x, +y, +z) corner: short strokes around the corner direction
    (45, 35, 90, 0.4, 1), (45, 35, -90, 0.4, 1), (30, 25, 0, 0.4, 1), (60, 25, 180, 0.4, 1),
    # sweep 1: the +x face up over the top edge, thumb on the (+x, -y, +z) corner
    (0, 0, 90, 1.0, 1), (15, 0, 90, 1.0, 2), (-15, 0, 90, 1.0, 3), (-45, 35, -90, 0.4, 0),
    # sweep 2: the -x face down over the bottom edge, thumb on the (-x, +y, -z) corner
    (180, 0, -90, 1.0, 1), (165, 0, -90, 1.0, 2), (-165, 0, -90, 1.0, 3),
    (135, -35, 90, 0.4, 0),
    # sweep 3: the -y face sideways over the vertical edge to -x, thumb on (-x, -y, +z)
    (-90, 20, 180, 1.0, 1), (-90, 0, 180, 1.0, 2), (-90, -20, 180, 1.0, 3),
    (-135, 35, -90, 0.4, 0),
    # fill-in: the +y face down and up, the top, the lower (+x, +y) corner
    (90, 0, -90, 1.0, 1), (90, 30, 90, 1.0, 2), (0, 90, 90, 1.0, 1), (45, -35, 90, 0.4, 0),
)  # fmt: skip


class PaperPolicy(Policy):
    """The paper's exploration pattern as a fixed sequence of touches (:data:`PAPER_PATTERN`).

    A patch at a corner disambiguates the tapering, strokes crossing edges and adjacent faces fix
    extents and shape exponents (paper III-A; IV: "a thumb touching the cube's corner while
    moving three fingers in parallel across its side face"). Designed for the paper's bodies in
    their axis-aligned pose; the sequence repeats after 20 touches. Open loop: it ignores the
    observation (but for the touch count).
    """

    name = "paper"

    def reset(self, rng: np.random.Generator | int | None = None) -> None:  # noqa: D102
        super().reset(rng)
        self._index = 0

    def __init__(self, env: Any, rng: np.random.Generator | int | None = None) -> None:
        super().__init__(env, rng)
        self._index = 0

    def __call__(self, obs: Observation) -> NDArray[np.float32]:
        touches = int(round(float(obs["touches"][0])))
        az, el, psi, frac, finger = PAPER_PATTERN[touches % len(PAPER_PATTERN)]
        return self._action(_direction(az, el), np.radians(psi), frac, finger)


@dataclass(frozen=True)
class _Candidates:
    approach: Array  # (k, 3) approach directions
    points: Array  # (k, 3) predicted first contacts, object-centred frame [m]


class UncertaintyPolicy(Policy):
    """Touch where the current estimate is least supported by the contacts so far.

    Each step: ``n_candidates`` approach directions (a Fibonacci sphere, turned by a random
    rotation from the policy's rng) are ray cast onto the estimate decoded from the observation
    (before the first fit: a sphere about the rough position, of radius ``initial_radius``, or the
    contacts' mean distance from it once there are some). Directions whose predicted contact lies
    on the estimate's underside within ``support_radius`` of its vertical axis (where the stand
    holding the object is) or within ``failed_cone`` of a direction that brought no contact are
    dropped. The policy picks the
    direction whose predicted contact is farthest from all contacts, then the stroke direction
    (of 8) whose predicted end point is farthest from all contacts, and strokes the full length.

    Args:
        env: the environment (configuration only).
        rng: seed or generator.
        n_candidates: approach directions tried per step.
        initial_radius: radius of the stand-in sphere before the first fit [m].
        support_radius: horizontal distance [m] from the estimate's axis, on its underside (the
            lowest ``support_margin`` of its height), treated as unreachable (the stand).
        support_margin: fraction of the estimate's height above its bottom checked for that.
        failed_cone: half-angle of the cone around a failed approach that is avoided [rad].
    """

    name = "uncertainty"

    def __init__(
        self,
        env: Any,
        rng: np.random.Generator | int | None = None,
        n_candidates: int = 96,
        initial_radius: float = 0.04,
        support_radius: float = 0.018,
        support_margin: float = 0.1,
        failed_cone: float = 0.35,
    ) -> None:
        super().__init__(env, rng)
        if n_candidates < 4:
            raise InvalidInputError(f"`n_candidates` must be >= 4, got {n_candidates}")
        self.n_candidates = int(n_candidates)
        self.initial_radius = float(initial_radius)
        self.support_radius = float(support_radius)
        self.support_margin = float(support_margin)
        self.failed_cone = float(failed_cone)
        self._sphere = fibonacci_sphere(self.n_candidates)
        self._failed: list[Array] = []
        self._last: Array | None = None
        self._last_count = 0
        self._finger = 0

    def reset(self, rng: np.random.Generator | int | None = None) -> None:  # noqa: D102
        super().reset(rng)
        self._failed = []
        self._last = None
        self._last_count = 0
        self._finger = 0

    def _contacts(self, obs: Observation) -> Array:
        return observed_contacts(obs, self.config.obs_scale)

    def _estimate(self, obs: Observation) -> Superquadric:
        return estimate_from_observation(obs, self.config.obs_scale, self.initial_radius)

    def _candidates(self, estimate: Superquadric) -> _Candidates:
        dirs = self._sphere @ random_rotation(self.rng).T
        far = 3.0 * estimate.bounding_radius + 2.0 * float(np.linalg.norm(estimate.center))
        s = raycast_many(estimate, far * dirs, -dirs, 2.0 * far)
        ok = ~np.isnan(s)
        return _Candidates(dirs[ok], far * dirs[ok] - s[ok, None] * dirs[ok])

    def __call__(self, obs: Observation) -> NDArray[np.float32]:
        contacts = self._contacts(obs)
        if self._last is not None and len(contacts) == self._last_count:
            self._failed.append(self._last)  # the previous touch brought nothing
        estimate = self._estimate(obs)
        cand = self._candidates(estimate)
        keep = np.ones(len(cand.points), dtype=bool)
        if int(obs["fit_valid"][0]):
            surf = estimate.surface(
                np.linspace(-np.pi / 2, np.pi / 2, 25).repeat(24),
                np.tile(np.linspace(-np.pi, np.pi, 24), 25),
            )[0]
            bottom, top = float(surf[:, 2].min()), float(surf[:, 2].max())
            low = cand.points[:, 2] < bottom + self.support_margin * (top - bottom)
            near = np.linalg.norm(cand.points[:, :2] - estimate.center[:2], axis=1)
            keep &= ~(low & (near < self.support_radius))
        else:
            keep &= cand.approach[:, 2] > -0.9  # not straight from below: the stand
        for d in self._failed:
            keep &= cand.approach @ d < np.cos(self.failed_cone)
        if not np.any(keep):
            keep = np.ones(len(cand.points), dtype=bool)
        approach, points = cand.approach[keep], cand.points[keep]
        gap = self._score(points, contacts, estimate, obs)
        best = int(np.argmax(gap + 1e-9 * self.rng.random(len(gap))))
        p, d = points[best], approach[best]

        # Stroke towards the least supported neighbourhood of the chosen contact.
        normal = estimate.normals(p[None, :])[0]
        t_h, t_v = tangent_frame(normal)
        angles = np.linspace(-np.pi, np.pi, 8, endpoint=False)
        ends = p + self.config.max_stroke * (
            np.cos(angles)[:, None] * t_h + np.sin(angles)[:, None] * t_v
        )
        ends = estimate.project(ends)
        psi = float(angles[int(np.argmax(self._score(ends, contacts, estimate, obs)))])
        self._last, self._last_count = d, len(contacts)
        self._finger = (self._finger + 1) % self.n_fingers
        return self._action(d, psi, 1.0, self._finger)

    def _score(
        self, points: Array, contacts: Array, estimate: Superquadric, obs: Observation
    ) -> Array:
        """(k,) how much a contact at each predicted point is wanted: its distance to the
        nearest contact so far [m] (the coverage gap)."""
        return _distance_to_set(points, contacts)


class InformationPolicy(UncertaintyPolicy):
    """Touch where a contact is expected to tell the most about the shape.

    As :class:`UncertaintyPolicy` (candidates, exclusions, stroke choice), but once the estimate
    is fitted a candidate's score is the expected information of a contact there under the
    estimate's Laplace posterior (computed from the contacts and normals in the observation by
    :func:`~hapticsim.fitting.uncertainty.posterior_covariance`, with a broad prior,
    :func:`~hapticsim.fitting.uncertainty.with_prior`): by default the expected drop of the
    surface's positional variance
    (:func:`~hapticsim.fitting.uncertainty.expected_surface_reduction`), or with
    ``criterion="entropy"`` the entropy drop of the parameters
    (:func:`~hapticsim.fitting.uncertainty.expected_information`), instead of its distance to
    the contacts. Before the first fit, and while the contacts are fewer than 13,
    it scores by the coverage gap as :class:`UncertaintyPolicy` does.
    """

    name = "information"
    #: Scores of a candidate: ``"surface"``, the expected drop of the surface's positional
    #: variance (:func:`~hapticsim.fitting.uncertainty.expected_surface_reduction`), or
    #: ``"entropy"``, the expected information of all 13 parameters
    #: (:func:`~hapticsim.fitting.uncertainty.expected_information`).
    CRITERIA: tuple[str, ...] = ("surface", "entropy")

    def __init__(
        self, env: Any, rng: np.random.Generator | int | None = None, criterion: str = "surface",
        **options: Any,
    ) -> None:  # fmt: skip
        super().__init__(env, rng, **options)
        if criterion not in self.CRITERIA:
            raise ChoiceError("criterion", criterion, self.CRITERIA)
        self.criterion = criterion
        self._posterior: tuple[Array, float] | None = None

    def __call__(self, obs: Observation) -> NDArray[np.float32]:
        self.prepare(obs)  # the posterior once per step, for the approach and the stroke
        return super().__call__(obs)

    def prepare(self, obs: Observation) -> None:
        """The posterior of the observation's estimate, which :meth:`_score` uses (None before
        the first fit and below 13 contacts)."""
        self._posterior = None
        contacts = self._contacts(obs)
        if int(obs["fit_valid"][0]) and len(contacts) >= N_PARAMS:
            estimate = self._estimate(obs)
            normals = np.asarray(obs["normals"], dtype=np.float64)[np.asarray(obs["mask"], bool)]
            cov, noise, _ = posterior_covariance(estimate, contacts, normals, DEFAULT_LAMBDA,
                                                 "tapered")  # fmt: skip
            self._posterior = (with_prior(cov, float(np.mean(estimate.a))), noise)

    def _score(
        self, points: Array, contacts: Array, estimate: Superquadric, obs: Observation
    ) -> Array:
        if self._posterior is None:  # before the first fit, or too few contacts for one
            return _distance_to_set(points, contacts)
        cov, noise = self._posterior
        gain = expected_surface_reduction if self.criterion == "surface" else expected_information
        return gain(estimate, cov, noise, points)


def _distance_to_set(points: Array, contacts: Array) -> Array:
    """(k,) float, distance of each point to its nearest contact [m] (inf without contacts)."""
    if len(contacts) == 0:
        return np.full(len(points), np.inf)
    d2 = np.sum((points[:, None, :] - contacts[None, :, :]) ** 2, axis=-1)
    return np.sqrt(d2.min(axis=1))


class LearnedPolicy(Policy):
    """A trained actor on the compact observation of ``HapticExploreCompact-v0``, the touch
    observation of ``HapticExploreTouch-v0`` or the tactile one of
    ``HapticExploreTouchTactile-v0`` (the weight file says which); deterministic.

    On a v0 environment (the comparisons, ``hapticsim policies evaluate``, the suites) it makes
    the observation it was trained on itself, with a
    :class:`~hapticsim.envs.haptic_explore_compact_v0.CompactObserver` or a
    :class:`~hapticsim.envs.haptic_explore_touch_v0.TouchObserver` (from the v0 observation and its
    own past approaches: exactly what the training environment shows), and returns the v0
    action of its action (:func:`~hapticsim.envs.haptic_explore_compact_v0.v0_action`: the
    fingers in turn); on its own training environment it acts on the observation directly.

    Args:
        env: the environment (``HapticExplore-v0``, or the actor's own; configuration only).
        rng: ignored (the actor is deterministic); accepted for the common interface.
        path: the weight file (default: the shipped one, :attr:`default_weights`).

    Raises:
        InvalidInputError: a missing or malformed weight file, one trained for another
            environment, observation or action size, a tactile actor without tactile sensing,
            or for other observation or action
            settings than the environment's (``obs_scale``, ``max_stroke``, ``stroke_spacing``);
            an environment of another observation; the message says what it was trained for.
    """

    name = "learned"
    #: The weight file without `path`.
    default_weights: Path = LEARNED_WEIGHTS

    def __init__(
        self,
        env: Any,
        rng: np.random.Generator | int | None = None,
        path: str | Path | None = None,
    ) -> None:
        base = env.unwrapped
        compact = _compact_wrapper(env)  # the actor's own kind of environment, or None
        own = compact is not None
        self.config = base.config
        self.n_fingers = base.n_fingers
        self.action_space = (compact or base).action_space
        self.rng = np.random.default_rng(rng)
        self.path = self.default_weights if path is None else Path(path)
        self.actor = load_learned(self.path, self.config)
        env_id = canonical_id(str(self.actor.meta.get("env_id")))
        self.on_v1 = own and compact.observation_space.shape == (self.actor.obs_dim,)
        if own and not self.on_v1:
            raise InvalidInputError(
                f"the policy was trained for {self.actor.describe()}; this environment shows "
                f"observations of size {compact.observation_space.shape}: run it on "
                f"HapticExplore-v0 or on {env_id}"
            )
        self.observer = LEARNED_OBSERVATIONS[env_id][1](self.config.obs_scale)
        if getattr(self.observer, "taxels", False) and self.config.sensing != "tactile":
            raise InvalidInputError(
                f"the policy was trained for {env_id}, which feels the pads' images: run it on "
                f"HapticExploreTactile-v0 (sensing 'tactile') or on {env_id}, not with sensing "
                f"{self.config.sensing!r}"
            )
        self._last: Array | None = None

    @property
    def meta(self) -> dict[str, Any]:
        """What the weights were trained for, and how (the weight file's record)."""
        return dict(self.actor.meta)

    def reset(self, rng: np.random.Generator | int | None = None) -> None:  # noqa: D102
        super().reset(rng)
        self._last = None

    def __call__(self, obs: Any) -> NDArray[np.float32]:
        if self.on_v1:
            return self.actor(obs)
        touches = int(round(float(obs["touches"][0])))
        if touches == 0 or self._last is None:  # an episode's first touch
            features = self.observer.reset(obs)
        else:
            features = self.observer.update(obs, self._last)
        action, self._last = v1.v0_action(
            self.actor(features), touches, self.config.max_stroke, self.n_fingers
        )
        return action


def _compact_wrapper(env: Any) -> Any:
    """The compact-family wrapper (compact, touch, tactile touch) in `env`'s chain of Gymnasium
    wrappers, or None."""
    while isinstance(env, gym.Wrapper):
        if isinstance(env, v1.HapticExploreCompactEnv):
            return env
        env = env.env
    return None


class LearnedTouchPolicy(LearnedPolicy):
    """The shipped actor that learned from the touch history (:class:`LearnedPolicy` with
    :data:`LEARNED_TOUCH_WEIGHTS`)."""

    name = "learned-touch"
    default_weights = LEARNED_TOUCH_WEIGHTS


def load_learned(path: str | Path | None, config: Any = None):  # noqa: ANN201 - learned.Actor
    """The actor of a weight file, checked for a learners' environment and a config.

    Args:
        path: the weight file; None: the shipped ``"learned"`` one (:data:`LEARNED_WEIGHTS`).
        config: a :class:`~hapticsim.envs.haptic_explore_v0.HapticExploreConfig` whose
            observation and action settings must be the trained ones (None: not checked).

    Raises:
        InvalidInputError: see :class:`LearnedPolicy`.
    """

    if path is None:
        path = LEARNED_WEIGHTS
    path = Path(path)
    if path in (LEARNED_WEIGHTS, LEARNED_TOUCH_WEIGHTS) and not path.is_file():
        raise InvalidInputError(
            f"the shipped learned policy {str(path)!r} is missing from this installation"
        )
    actor = load_actor(path, action_dim=v1.ACTION_DIM_V1)
    env_id = canonical_id(str(actor.meta.get("env_id")))
    if env_id not in LEARNED_OBSERVATIONS or actor.obs_dim != LEARNED_OBSERVATIONS[env_id][0]:
        wanted = ", ".join(f"{k} (observation size {n})" for k, (n, _) in
                           LEARNED_OBSERVATIONS.items())  # fmt: skip
        raise InvalidInputError(
            f"policy weights file {str(path)!r} was trained for {actor.describe()}; this "
            f"hapticsim runs learned policies for {wanted}"
        )
    if config is not None:
        actor.check_settings({k: getattr(config, k) for k in MEANING_SETTINGS})
    return actor


def learned_path(name: str) -> Path | None:
    """The weight file a policy name gives: None for ``"learned"`` (the shipped one), the
    shipped touch actor for ``"learned-touch"``, PATH for ``"learned:PATH"``; raises for other
    names (:func:`check_policy_name`)."""
    check_policy_name(name)
    if name == "learned":
        return None
    if name == "learned-touch":
        return LEARNED_TOUCH_WEIGHTS
    if not name.startswith(LEARNED_PREFIX):
        raise InvalidInputError(f"`policy` {name!r} is not a learned policy")
    return Path(name[len(LEARNED_PREFIX) :])


#: The policies by name (:func:`make_policy`), the one registry.
POLICIES: dict[str, type[Policy]] = {
    "random": RandomPolicy,
    "paper": PaperPolicy,
    "uncertainty": UncertaintyPolicy,
    "information": InformationPolicy,
    "learned": LearnedPolicy,
    "learned-touch": LearnedTouchPolicy,
}
#: Names of the policies; ``"learned:PATH"`` names a weight file too.
POLICY_NAMES: tuple[str, ...] = tuple(POLICIES)


def check_policy_name(name: Any) -> str:
    """`name` if it names a policy: one of :data:`POLICY_NAMES`, or ``"learned:PATH"``.

    Raises:
        InvalidInputError: naming the choices.
    """
    if isinstance(name, str) and (
        name in POLICIES or (name.startswith(LEARNED_PREFIX) and len(name) > len(LEARNED_PREFIX))
    ):
        return name
    raise ChoiceError("policy", name, POLICY_NAMES, f"or '{LEARNED_PREFIX}PATH' (a weight file)")


def make_policy(name: str, env: Any, rng: np.random.Generator | int | None = None) -> Policy:
    """A policy by name: one of :data:`POLICY_NAMES`, or ``"learned:PATH"`` (a weight file).

    Raises:
        InvalidInputError: an unknown name (the message lists the choices), or a weight file
            that does not fit the environment (:class:`LearnedPolicy`).
    """
    check_policy_name(name)
    if name.startswith(LEARNED_PREFIX):
        return LearnedPolicy(env, rng, path=name[len(LEARNED_PREFIX) :])
    return POLICIES[name](env, rng)


