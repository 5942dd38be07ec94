"""``hapticsim/HapticExploreCompact-v0``: the exploration task, compact observation for learners.

See :class:`HapticExploreCompactEnv`. The compact observation is made by :class:`CompactObserver`
from what ``HapticExplore-v0`` shows (its observation and the agent's own past actions), so a
policy trained on v1 also runs on a v0 environment (``hapticsim.envs.policies`` policy
``"learned"``), with exactly the features it was trained on.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from hapticsim._validate import finite_array
from hapticsim.envs.estimator import FitSchedule
from hapticsim.envs.haptic_explore_v0 import HapticExploreConfig, HapticExploreEnv
from hapticsim.envs.observation import OBS_BOUND, decode_fit
from hapticsim.envs.touch import encode_touch
from hapticsim.errors import ChoiceError, HapticsimError, InvalidInputError
from hapticsim.geometry import N_PARAMS, Superquadric
from hapticsim.geometry.rays import raycast_many
from hapticsim.geometry.sampling import fibonacci_sphere

Array = NDArray[np.float64]

#: Id of the environment this module defines (stored beside trained weights; weights of its
#: former id, ``hapticsim/HapticExplore-v1``, are taken as its own).
ENV_ID: str = "hapticsim/HapticExploreCompact-v0"
#: Fixed approach directions of the coverage features (Fibonacci lattice, object-centred frame).
N_DIRECTIONS: int = 32
#: Length of the compact observation: 13 fit + fit_valid + eof + touches + contacts + 32 gaps
#: + 32 failed flags + the widest gap's direction and value (4).
OBS_DIM: int = N_PARAMS + 4 + 2 * N_DIRECTIONS + 4
#: Length of the v1 action: approach vector (3), stroke direction, stroke length.
ACTION_DIM_V1: int = 5
#: Reward definitions of v1.
REWARDS_V1: tuple[str, ...] = ("log_epsilon", "epsilon")
#: Touches that scale the observation's touch count (``touches / TOUCH_SCALE``).
TOUCH_SCALE: float = 10.0
#: Contacts that scale the observation's contact count.
CONTACT_SCALE: float = 100.0
#: Radius of the stand-in sphere before the first fit [m] (the uncertainty baseline's).
INITIAL_RADIUS: float = 0.04
#: Half-angle of the cone around an approach that brought no contact [rad].
FAILED_CONE: float = 0.35
#: Where the coverage gaps sit in the observation.
GAP_SLICE: slice = slice(N_PARAMS + 4, N_PARAMS + 4 + N_DIRECTIONS)
#: The fixed directions, (N_DIRECTIONS, 3) unit vectors.
DIRECTIONS: Array = fibonacci_sphere(N_DIRECTIONS)
#: Names of the observation's entries, in order (for docs, tests and weight files).
OBS_NAMES: tuple[str, ...] = (
    *(f"fit_{i}" for i in range(N_PARAMS)),
    "fit_valid",
    "eof",
    "touches",
    "contacts",
    *(f"gap_{k}" for k in range(N_DIRECTIONS)),
    *(f"failed_{k}" for k in range(N_DIRECTIONS)),
    "widest_x",
    "widest_y",
    "widest_z",
    "widest_gap",
)


def estimate_from_observation(
    obs: dict[str, np.ndarray], scale: float, initial_radius: float = INITIAL_RADIUS
) -> Superquadric:
    """The current estimate in the object-centred frame, or a stand-in sphere before a fit.

    The fit decoded from a v0 observation (:func:`~hapticsim.envs.observation.decode_fit`);
    without a valid fit, a sphere about the rough position of radius `initial_radius`, or the
    contacts' mean distance from it (at least a quarter of `initial_radius`) once there are some.

    Args:
        obs: a ``HapticExplore-v0`` observation.
        scale: its length scale [m] (``config.obs_scale``).
        initial_radius: stand-in radius without contacts [m].

    Returns:
        the superquadric, centre relative to the rough position [m].
    """
    if int(obs["fit_valid"][0]):
        try:
            return decode_fit(obs["fit"], scale)
        except HapticsimError:
            pass
    contacts = observed_contacts(obs, scale)
    if len(contacts):
        r = max(float(np.mean(np.linalg.norm(contacts, axis=1))), 0.25 * initial_radius)
    else:
        r = initial_radius
    return Superquadric(a=(r, r, r), eps=(1.0, 1.0))


def observed_contacts(obs: dict[str, np.ndarray], scale: float) -> Array:
    """(n, 3) float, the contacts shown in a v0 observation [m, object-centred frame]."""
    mask = np.asarray(obs["mask"], dtype=bool)
    return np.asarray(obs["points"], dtype=np.float64)[mask] * scale


#: Length of :func:`observation_head`.
HEAD_DIM: int = N_PARAMS + 4


def observation_head(obs: dict[str, np.ndarray]) -> Array:
    """The first :data:`HEAD_DIM` entries of the compact (and touch) observation: the v0 fit,
    its validity and error of fit, touches / 10 and contacts shown / 100, clipped to the
    observation bound."""
    head = np.concatenate(
        [
            np.asarray(obs["fit"], np.float64),
            [float(obs["fit_valid"][0]), float(obs["eof"][0])],
            [float(obs["touches"][0]) / TOUCH_SCALE, float(np.sum(obs["mask"])) / CONTACT_SCALE],
        ]
    )
    return np.clip(head, -OBS_BOUND, OBS_BOUND)


class CompactObserver:
    """The compact observation of v1, made from v0 observations and the agent's approaches.

    Entries (:data:`OBS_NAMES`, float32, :data:`OBS_DIM` = 85):

    | Index  | Name        | Content                                                  | Unit  |
    |--------|-------------|----------------------------------------------------------|-------|
    | 0-12   | fit_i       | the v0 ``fit`` entry (normalised estimate; 0 without)    | 1     |
    | 13     | fit_valid   | 1 once a fit exists                                      | -     |
    | 14     | eof         | sqrt(error of fit) / obs_scale (v0 ``eof``)              | 1     |
    | 15     | touches     | touches so far / 10                                      | 1     |
    | 16     | contacts    | contacts shown / 100                                     | 1     |
    | 17-48  | gap_k       | coverage gap in fixed direction k (below)                | 1     |
    | 49-80  | failed_k    | 1 if a touch within 0.35 rad of direction k brought no   | -     |
    |        |             | contact this episode                                     |       |
    | 81-83  | widest_xyz  | the direction u_k of the widest gap among those not      | 1     |
    |        |             | failed (the first such k on ties; all if every one did)  |       |
    | 84     | widest_gap  | that gap                                                 | 1     |

    The gap of direction ``u_k`` (32 Fibonacci directions, object-centred frame): the approach
    ray from far along ``u_k`` towards the rough position is cast on the current estimate (a
    stand-in sphere before the first fit, :func:`estimate_from_observation`); the gap is
    ``min(1, d / r)``, d the distance [m] from that predicted contact to the nearest contact so
    far and ``r`` the estimate's mean semi-axis; 1 without contacts, 0 where the ray misses the
    estimate. This is the per-direction form of the ``uncertainty`` baseline's criterion and of
    v0's :func:`~hapticsim.metrics.coverage.coverage_uncertainty`; the widest gap's
    direction summarises it (touching there is that baseline's choice restricted to the 32
    directions, with a fixed stroke: the learner may follow it, or not). Nothing here uses the
    ground truth.

    Args:
        obs_scale: the v0 observation's length scale [m].
    """

    def __init__(self, obs_scale: float) -> None:
        if not np.isfinite(obs_scale) or obs_scale <= 0:
            raise InvalidInputError(f"`obs_scale` must be > 0 [m], got {obs_scale!r}")
        self.obs_scale = float(obs_scale)
        self._failed = np.zeros(N_DIRECTIONS, dtype=bool)
        self._count = 0

    def reset(self, obs: dict[str, np.ndarray]) -> NDArray[np.float32]:
        """Start an episode from the v0 reset observation; returns the compact observation."""
        self._failed[:] = False
        self._count = int(np.sum(obs["mask"]))
        return self.features(obs)

    def update(self, obs: dict[str, np.ndarray], approach: Array) -> NDArray[np.float32]:
        """The compact observation after a touch along `approach`.

        Args:
            obs: the v0 observation after the touch.
            approach: (3,) float, the touch's unit approach direction (object-centred frame).
        """
        count = int(np.sum(obs["mask"]))
        if count <= self._count:  # the touch brought nothing: remember where not to go
            self._failed |= DIRECTIONS @ np.asarray(approach, np.float64) > np.cos(FAILED_CONE)
        self._count = count
        return self.features(obs)

    def features(self, obs: dict[str, np.ndarray]) -> NDArray[np.float32]:
        """The compact observation of a v0 observation (with this episode's failed approaches)."""
        contacts = observed_contacts(obs, self.obs_scale)
        estimate = estimate_from_observation(obs, self.obs_scale)
        gaps = np.ones(N_DIRECTIONS)
        if len(contacts):
            far = 3.0 * estimate.bounding_radius + 2.0 * float(np.linalg.norm(estimate.center))
            s = raycast_many(estimate, far * DIRECTIONS, -DIRECTIONS, 2.0 * far)
            hit = ~np.isnan(s)
            predicted = far * DIRECTIONS[hit] - s[hit, None] * DIRECTIONS[hit]
            d2 = np.sum((predicted[:, None, :] - contacts[None, :, :]) ** 2, axis=-1)
            gaps[:] = 0.0
            gaps[hit] = np.minimum(1.0, np.sqrt(d2.min(axis=1)) / float(np.mean(estimate.a)))
        head = observation_head(obs)
        open_gaps = np.where(self._failed, -1.0, gaps) if not self._failed.all() else gaps
        k = int(np.argmax(open_gaps))
        out = np.concatenate([head, gaps, self._failed, DIRECTIONS[k], [gaps[k]]])
        return out.astype(np.float32)


def decode_action_v1(action: Any) -> tuple[Array, float, float]:
    """The approach direction, stroke direction and stroke fraction of a v1 action.

    Args:
        action: (5,) float in ``[-1, 1]`` (clipped).

    Returns:
        approach: (3,) unit vector ``a[0:3] / |a[0:3]|`` (straight down from above, ``+z``,
            when ``|a[0:3]| < 1e-6``), object-centred frame;
        stroke_angle: ``psi = pi * a3`` [rad];
        stroke_fraction: ``(a4 + 1) / 2`` of ``max_stroke`` (a probe below one spacing).
    """

    a = np.clip(finite_array(action, "action", (ACTION_DIM_V1,)), -1.0, 1.0)
    norm = float(np.linalg.norm(a[0:3]))
    approach = a[0:3] / norm if norm >= 1e-6 else np.array([0.0, 0.0, 1.0])
    return approach, float(np.pi * a[3]), float(0.5 * (a[4] + 1.0))


def encode_action_v1(approach: Any, stroke_angle: float, stroke_fraction: float) -> Array:
    """The v1 action that decodes to this touch (inverse of :func:`decode_action_v1`).

    Args:
        approach: (3,) approach direction (any length), object-centred frame.
        stroke_angle: psi [rad], wrapped to [-pi, pi].
        stroke_fraction: stroke length over ``max_stroke``, in [0, 1].

    Returns:
        (5,) float ``[approach / |approach|, psi / pi, 2 * fraction - 1]``, clipped to [-1, 1].
    """

    d = finite_array(approach, "approach", (3,))
    d = d / max(float(np.linalg.norm(d)), 1e-12)
    psi = float(np.angle(np.exp(1j * stroke_angle)))
    return np.clip(np.array([*d, psi / np.pi, 2.0 * stroke_fraction - 1.0]), -1.0, 1.0)


def finger_for_touch(touches: int, n_fingers: int) -> int:
    """The finger of the touch after `touches` touches: the fingers in turn, index finger first.

    As the ``uncertainty`` baseline: 1, 2, ..., n - 1, 0 (the thumb), 1, ...
    """
    return (int(touches) + 1) % int(n_fingers)


def v0_action(
    action: Any, touches: int, max_stroke: float, n_fingers: int
) -> tuple[NDArray[np.float32], Array]:
    """The v0 action that executes a v1 action, and its approach direction.

    Args:
        action: (5,) float v1 action (:func:`decode_action_v1`).
        touches: touches made so far (selects the finger, :func:`finger_for_touch`).
        max_stroke: stroke length of a full stroke [m].
        n_fingers: fingers of the hand.
    """
    approach, psi, fraction = decode_action_v1(action)
    finger = finger_for_touch(touches, n_fingers)
    out = encode_touch(approach, psi, fraction * max_stroke, finger, max_stroke, n_fingers)
    return out, approach


@dataclass(frozen=True)
class HapticExploreV1Config:
    """The settings of v1: those of v0 (:class:`HapticExploreConfig`) and v1's reward.

    Attributes:
        core: the core environment's (v0's) settings (backend, objects, touch budget, noise,
            fit schedule, ...); its reward is ignored (v1 always scores epsilon, so
            ``compute_metrics`` is on).
        reward: ``"log_epsilon"`` (default, privileged: ``log eps_{t-1} - log eps_t`` with eps
            floored at `epsilon_floor`, so the return is ``-log eps_T``: every halving of the
            final error counts the same) or ``"epsilon"`` (v0's ``eps_{t-1} - eps_t``).
        epsilon_floor: floor of epsilon in the log reward (> 0).
        coverage_weight: weight c >= 0 of a coverage term added to the reward:
            ``c * (G_{t-1} - G_t)``, G the mean coverage gap over the 32 directions of the
            observation (1 before any contact; no ground truth), so touching where the estimate
            is least supported pays at once instead of through the noisy change of epsilon.
    """

    core: HapticExploreConfig
    reward: str = "log_epsilon"
    epsilon_floor: float = 1e-3
    coverage_weight: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.core, HapticExploreConfig):
            raise InvalidInputError(
                f"`core` must be a HapticExploreConfig, got {type(self.core).__name__}"
            )
        if self.reward not in REWARDS_V1:
            raise ChoiceError("reward", self.reward, REWARDS_V1)
        floor = self.epsilon_floor
        if not isinstance(floor, (int, float)) or not np.isfinite(floor) or not 0 < floor < 1:
            raise InvalidInputError(f"`epsilon_floor` must be in (0, 1), got {floor!r}")
        c = self.coverage_weight
        if not isinstance(c, (int, float)) or not np.isfinite(c) or not 0 <= c <= 100:
            raise InvalidInputError(f"`coverage_weight` must be in [0, 100], got {c!r}")
        if self.core.reward != "epsilon" or not self.core.compute_metrics:
            object.__setattr__(self, "core", replace(self.core, reward="epsilon"))

    @classmethod
    def from_kwargs(cls, **kwargs: Any) -> HapticExploreV1Config:
        """The config from keyword arguments: v1's own (``reward``, ``epsilon_floor``) and v0's."""
        own = {f.name for f in fields(cls)} - {"core"}
        v1 = {k: kwargs.pop(k) for k in list(kwargs) if k in own}

        if "fit" in kwargs and isinstance(kwargs["fit"], dict):
            kwargs["fit"] = FitSchedule(**kwargs["fit"])
        kwargs["reward"] = "epsilon"
        return cls(core=HapticExploreConfig(**kwargs), **v1)


class HapticExploreCompactEnv(gym.Wrapper[np.ndarray, np.ndarray, dict, np.ndarray]):
    """Haptic exploration (as v0) with a compact observation, a simpler action and a log reward:
    a Gymnasium wrapper around the core environment.

    The task, objects, backends, touches, fits and ``info`` are those of ``HapticExplore-v0``
    (:class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv`, the core it wraps:
    ``env.unwrapped``); what the agent sees, does and is rewarded with changes, so that
    off-policy learners train on a few dozen numbers instead of v0's 1,808.

    ## Action space

    ``Box(-1, 1, (5,), float32)``:

    | Num | Action          | Mapping                                                  | Unit |
    |-----|-----------------|----------------------------------------------------------|------|
    | 0-2 | approach vector | approach direction ``a[0:3] / |a[0:3]|`` (object-centred | 1    |
    |     |                 | frame; +z below 1e-6)                                    |      |
    | 3   | stroke angle    | psi = pi * a3, as v0's component 2                       | rad  |
    | 4   | stroke length   | L = (a4 + 1) / 2 * max_stroke, as v0's component 3       | m    |

    The finger is not chosen: touches use the fingers in turn, index finger first
    (:func:`finger_for_touch`, as the ``uncertainty`` baseline). A v1 action maps to the v0
    action :func:`v0_action`.

    ## Observation space

    ``Box(-10, 10, (85,), float32)``: :class:`CompactObserver` (the v0 fit, its validity and
    error of fit, touch and contact counts, the coverage gap in 32 fixed approach directions,
    which of them brought no contact, and the direction and value of the widest open gap). No
    ground truth.

    ## Rewards

    ``"log_epsilon"`` (default, privileged): ``log(max(eps_{t-1}, f)) - log(max(eps_t, f))``,
    eps the volume error of the estimate (1 before the first fit), f = ``epsilon_floor``
    (1e-3); an episode's return is ``-log(max(eps_T, f))``. ``"epsilon"``: v0's drop of epsilon.
    With ``coverage_weight`` c > 0, ``c * (G_{t-1} - G_t)`` is added, G the mean of the
    observation's 32 coverage gaps (a shaping term without ground truth).

    ## Episode end

    Terminated after ``touch_budget`` touches (the touch count is observed, so the budget is
    part of the task; v0 truncates there) or at ``target_epsilon``.

    ## Arguments

    As v0 (``backend``, ``objects``, ``touch_budget``, ``noise``, ``fit``, ...; or
    ``config=HapticExploreV1Config(...)``), plus ``reward``, ``epsilon_floor`` and
    ``coverage_weight`` of v1. ``env``: the core to wrap, or a wrapper of it (the tactile
    variant, whose pads' images the touch observation reads; default: a
    :class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv` made from ``config.core``); the
    core's settings must be ``config.core``.

    ## Version history

    - v1: compact observation (85 numbers, :class:`CompactObserver`), action without finger
      (approach vector, stroke angle and length; fingers in turn), reward ``log_epsilon`` by
      default with an optional coverage term, termination at the touch budget.
    - v0: initial version (:class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv`).
    """

    #: As the core's (a class attribute: Gymnasium checks an entry point's metadata before
    #: making it).
    metadata = {"render_modes": ["rgb_array"], "render_fps": 2}

    def __init__(
        self,
        env: HapticExploreEnv | None = None,
        render_mode: str | None = None,
        config: HapticExploreV1Config | None = None,
        **kwargs: Any,
    ) -> None:
        if config is not None and kwargs:
            raise InvalidInputError("give either `config` or keyword arguments, not both")
        if config is not None and not isinstance(config, HapticExploreV1Config):
            raise InvalidInputError(
                f"`config` must be a HapticExploreV1Config, got {type(config).__name__}"
            )
        self.config = config if config is not None else HapticExploreV1Config.from_kwargs(**kwargs)
        if env is None:
            env = HapticExploreEnv(render_mode=render_mode, config=self.config.core)
        elif (
            not isinstance(env, gym.Env)
            or not isinstance(env.unwrapped, HapticExploreEnv)
            or env.unwrapped.config != self.config.core
        ):
            raise InvalidInputError(
                "`env` must be a HapticExploreEnv (or a wrapper of one) whose settings are "
                "`config.core`"
            )
        super().__init__(env)
        self.n_fingers = env.unwrapped.n_fingers
        self.observer = CompactObserver(self.config.core.obs_scale)
        self.observation_space = spaces.Box(-OBS_BOUND, OBS_BOUND, (OBS_DIM,), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (ACTION_DIM_V1,), np.float32)
        self._touches = 0
        self._eps = 1.0
        self._gap = 1.0

    @property
    def truth(self) -> Any:
        """The episode's ground truth (world frame), privileged."""
        return self.unwrapped.truth

    @property
    def estimate(self) -> Superquadric | None:
        """The current estimate (world frame), None before the first fit."""
        return self.unwrapped.estimate

    @property
    def contacts(self):  # noqa: ANN201 - hapticsim.data.io.Contacts
        """All contacts so far (see v0's :attr:`HapticExploreEnv.contacts`)."""
        return self.unwrapped.contacts

    @property
    def origin(self) -> Array:
        """(3,) float, the rough position [m, world]: origin of the object-centred frame."""
        return self.unwrapped.origin

    @property
    def resets_drawn_ahead(self) -> int:
        """Resets that used draws made ahead (v0's counter: :meth:`HapticExploreEnv.offer_draw`)."""
        return self.unwrapped.resets_drawn_ahead

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Start an episode (v0's reset; ``options={"shape": ...}`` as there)."""
        obs, info = self.env.reset(seed=seed, options=options)
        self._touches = 0
        self._eps = 1.0
        features = self.observer.reset(obs)
        self._gap = float(np.mean(features[GAP_SLICE]))
        return self._observe(obs, features, None), info

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        """One touch (v0's step on the mapped action), the compact observation and reward."""
        if self.unwrapped.truth is None:
            raise InvalidInputError("call `reset` before `step`")
        act, approach = v0_action(
            action, self._touches, self.config.core.max_stroke, self.n_fingers
        )
        obs, _, terminated, truncated, info = self.env.step(act)
        self._touches += 1
        eps = float(info["epsilon"])
        if self.config.reward == "log_epsilon":
            floor = self.config.epsilon_floor
            reward = float(np.log(max(self._eps, floor)) - np.log(max(eps, floor)))
        else:
            reward = self._eps - eps
        self._eps = eps
        features = self.observer.update(obs, approach)
        gap = float(np.mean(features[GAP_SLICE]))
        if self.config.coverage_weight > 0:
            reward += self.config.coverage_weight * (self._gap - gap)
        self._gap = gap
        info["approach"] = approach
        info["coverage_gap"] = gap
        done = bool(terminated or truncated)
        return self._observe(obs, features, approach), reward, done, False, info

    def _observe(
        self, obs: dict[str, np.ndarray], features: NDArray[np.float32], approach: Array | None
    ) -> NDArray[np.float32]:
        """The agent's observation from v0's and the compact one (`approach`: the touch's,
        None at a reset); here the compact one."""
        return features

    def render(self) -> NDArray[np.uint8] | None:
        """An RGB picture (``render_mode="rgb_array"``), as v0."""
        return self.env.render()

    def close(self) -> None:
        """Free the backend."""
        self.env.close()
