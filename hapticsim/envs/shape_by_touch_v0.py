"""``hapticsim/ShapeByTouch-v0``: 3-D shape perception by touch as an ap_gym active perception
task (extra ``apgym``: ``pip install -e ".[apgym]"``), so that ap_gym's agents and tooling (its
log wrapper, its training loops) run on hapticsim unchanged.

Each step the agent makes a touch and predicts the object's shape. The task is
``HapticExploreCompact-v0``'s: its observation (85 numbers), its action (approach, stroke angle
and length; the fingers in turn) and its objects, noise and fits.

## Action space

``Dict({"action": Box(-1, 1, (5,)), "prediction": Box(-1, 1, (5,))})``: the compact touch and
the prediction.

## Prediction target

The shape, in numbers that do not depend on the object's pose or on which axis is called which:
the semi-axes sorted (largest first) and divided by the observation scale (0.1 m), then the two
exponents eps1, eps2 mapped from [0.1, 2] to [-1, 1]. Only superquadric families (``paper``,
``random``, ``random_tapered``) have one.

## Loss and reward

ap_gym's mean squared error over the five numbers, normalised (``LossFn.normalized``) so that a
blind guess (the distribution's mean, whose expected loss is estimated from 2,000 draws of the
objects at construction) scores 1 and the truth 0. The reward is minus the loss (the base reward
is 0): an agent is paid for predicting well after every touch. ``info["prediction"]["loss"]``
holds it each step.

## Version history

- v0: initial version.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

from hapticsim.envs.haptic_explore_compact_v0 import HapticExploreCompactEnv
from hapticsim.errors import InvalidInputError

try:
    import ap_gym
except ImportError:  # pragma: no cover - the extra is optional
    ap_gym = None

#: Length of the prediction.
PREDICTION_DIM: int = 5
#: Object families with a superquadric truth, the target's shape.
FAMILIES: tuple[str, ...] = ("paper", "random", "random_tapered")
#: Draws of the objects that estimate the blind guess's expected loss.
BLIND_DRAWS: int = 2000


def shape_target(shape: Any, obs_scale: float) -> np.ndarray:
    """The prediction target of a superquadric (module docstring): (5,) float32."""
    a = np.sort(np.asarray(shape.a, dtype=float))[::-1] / obs_scale
    eps = (np.asarray(shape.eps, dtype=float) - 1.05) / 0.95
    return np.clip(np.concatenate([a, eps]), -1.0, 1.0).astype(np.float32)


_BLIND: dict[tuple[str, float], np.ndarray] = {}


def _blind_targets(kind: str, objects: Any, obs_scale: float) -> np.ndarray:
    """(BLIND_DRAWS, 5) targets of the family's objects (seeded; drawn once per family and
    scale, so a vector environment's copies share them)."""
    key = (kind, float(obs_scale))
    if key not in _BLIND:
        draws = np.random.default_rng(12345)
        _BLIND[key] = np.stack([shape_target(objects.sample(draws), obs_scale)
                                for _ in range(BLIND_DRAWS)])  # fmt: skip
    return _BLIND[key]


def make_shape_by_touch(render_mode: str | None = None, **kwargs: Any) -> Any:
    """The environment (the entry point of ``hapticsim/ShapeByTouch-v0``; keyword arguments as
    ``HapticExploreCompact-v0``'s).

    Raises:
        InvalidInputError: ap_gym is not installed, or the objects have no superquadric truth.
    """
    if ap_gym is None:
        raise InvalidInputError(
            'hapticsim/ShapeByTouch-v0 needs ap_gym: pip install -e ".[apgym]"'
        )
    return ShapeByTouchEnv(render_mode=render_mode, **kwargs)


def make_shape_by_touch_vec(num_envs: int = 1, **kwargs: Any) -> Any:
    """The vector environment (the vector entry point: ``gym.make_vec(
    "hapticsim/ShapeByTouch-v0", num_envs=N)``): N environments stepped in turn, each reset in
    the step that ends its episode (ap_gym's loss needs every step's prediction target).

    Raises:
        InvalidInputError: as :func:`make_shape_by_touch`, or `num_envs` < 1.
    """
    if ap_gym is None:
        raise InvalidInputError(
            'hapticsim/ShapeByTouch-v0 needs ap_gym: pip install -e ".[apgym]"'
        )
    kwargs.pop("vectorization_mode", None)
    kwargs.pop("vector_kwargs", None)
    if not isinstance(num_envs, int) or num_envs < 1:
        raise InvalidInputError(f"`num_envs` must be an int >= 1, got {num_envs!r}")
    return ShapeByTouchVectorEnv(num_envs, **kwargs)


if ap_gym is not None:

    class ShapeByTouchVectorEnv(ap_gym.ActivePerceptionVectorEnv):
        """N :class:`ShapeByTouchEnv` in one process, reset in the step that ends an episode;
        ``info["final_obs"]`` holds the ended episodes' last observations."""

        metadata = {"render_modes": [], "autoreset_mode": gym.vector.AutoresetMode.SAME_STEP}

        def __init__(self, num_envs: int, **kwargs: Any) -> None:
            self.envs = [ShapeByTouchEnv(**kwargs) for _ in range(num_envs)]
            first = self.envs[0]
            self.num_envs = num_envs
            self.single_observation_space = first.observation_space
            self.observation_space = gym.vector.utils.batch_space(
                first.observation_space, num_envs
            )
            self.single_action_space = first.action_space
            self.action_space = gym.vector.utils.batch_space(first.action_space, num_envs)
            self.single_prediction_target_space = first.prediction_target_space
            self.prediction_target_space = gym.vector.utils.batch_space(
                first.prediction_target_space, num_envs
            )
            self.loss_fn = first.loss_fn

        def reset(
            self, *, seed: int | None = None, options: dict[str, Any] | None = None
        ) -> tuple[np.ndarray, dict[str, Any]]:
            """Reset every environment (environment i seeded ``seed + i``)."""
            super().reset(seed=seed)
            obs = [e.reset(seed=None if seed is None else seed + i, options=options)[0]
                   for i, e in enumerate(self.envs)]  # fmt: skip
            return np.stack(obs), {}

        def _step(self, action: Any, prediction: Any) -> tuple:
            obs, term, trunc, targets, final = [], [], [], [], {}
            for i, e in enumerate(self.envs):
                targets.append(e._target.copy())  # the episode the prediction was about
                o, _, te, tr, _ = e.inner.step(action[i])
                if te or tr:
                    final[i] = o
                    o, _ = e.reset()
                obs.append(o)
                term.append(te)
                trunc.append(tr)
            info: dict[str, Any] = {}
            if final:
                info["final_obs"] = np.array(
                    [final.get(i) for i in range(self.num_envs)], dtype=object
                )
                info["_final_obs"] = np.array([i in final for i in range(self.num_envs)])
            return (np.stack(obs), np.zeros(self.num_envs), np.array(term), np.array(trunc),
                    info, np.stack(targets))  # fmt: skip

        def close_extras(self, **kwargs: Any) -> None:
            """Free the environments."""
            for e in self.envs:
                e.close()

    class ShapeByTouchEnv(ap_gym.ActivePerceptionEnv):
        """Shape perception by touch (module docstring): a compact-task environment inside."""

        metadata = {"render_modes": ["rgb_array"], "render_fps": 2}

        def __init__(self, render_mode: str | None = None, **kwargs: Any) -> None:
            objects = kwargs.get("objects", "paper")
            if objects not in FAMILIES:
                raise InvalidInputError(
                    f"`objects` must be one of {', '.join(FAMILIES)} (a superquadric truth: "
                    f"the prediction is its shape), got {objects!r}"
                )
            self.inner = HapticExploreCompactEnv(render_mode=render_mode, **kwargs)
            self.render_mode = render_mode
            self.observation_space = self.inner.observation_space
            box = gym.spaces.Box(-1.0, 1.0, (PREDICTION_DIM,), np.float32)
            self.action_space = ap_gym.ActivePerceptionActionSpace(self.inner.action_space, box)
            self.prediction_target_space = box
            core = self.inner.unwrapped
            self._scale = core.config.obs_scale
            targets = _blind_targets(objects, core.config.objects, self._scale)
            self.loss_fn = ap_gym.MSELossFn.from_data(targets).normalized
            #: (5,) float32, the blind guess: the targets' mean (its loss is 1 on average).
            self.blind_guess = targets.mean(axis=0).astype(np.float32)
            self._target = np.zeros(PREDICTION_DIM, np.float32)

        def core_observation(self) -> dict[str, np.ndarray]:
            """The core environment's (``HapticExplore-v0``'s) observation now: the same
            contacts and fit in v0's form, no ground truth (for baseline agents)."""
            return self.inner.unwrapped._observation()

        def reset(
            self, *, seed: int | None = None, options: dict[str, Any] | None = None
        ) -> tuple[np.ndarray, dict[str, Any]]:
            """Start an episode (the compact environment's reset)."""
            super().reset(seed=seed)
            obs, info = self.inner.reset(seed=seed, options=options)
            self._target = shape_target(self.inner.truth, self._scale)
            return obs, info

        def _step(self, action: Any, prediction: Any) -> tuple:
            obs, _, terminated, truncated, info = self.inner.step(action)
            return obs, 0.0, terminated, truncated, info, self._target.copy()

        def render(self) -> Any:
            """The compact environment's picture."""
            return self.inner.render()

        def close(self) -> None:
            """Free the backend."""
            self.inner.close()


class BaselineAgent:
    """A hapticsim policy (``random``, ``uncertainty``, ...) acting through
    ``ShapeByTouch-v0``: it chooses each touch from the core's observation
    (:meth:`ShapeByTouchEnv.core_observation`), made a compact action (its finger dropped: the
    task turns the fingers in turn), and predicts the shape of the environment's own nH fit
    (the blind guess before the first fit).

    Args:
        env: a ``ShapeByTouch-v0`` environment (wrapped or not).
        policy: a policy name of :func:`hapticsim.envs.policies.make_policy`.
        seed: the policy's seed.
    """

    def __init__(self, env: Any, policy: str = "uncertainty", seed: int = 0) -> None:
        from hapticsim.envs.policies import make_policy

        self.env = env.unwrapped
        self.core = self.env.inner.unwrapped
        self.seed = seed
        self.policy = make_policy(policy, self.core, rng=seed)

    def reset(self) -> None:
        """Start an episode (call after the environment's reset)."""
        self.policy.reset(self.seed)

    def __call__(self, obs: Any) -> dict[str, np.ndarray]:
        from hapticsim.envs.haptic_explore_compact_v0 import encode_action_v1
        from hapticsim.envs.touch import decode_action

        cfg = self.core.config
        touch = decode_action(self.policy(self.env.core_observation()), cfg.max_stroke,
                              cfg.stroke_spacing, self.core.n_fingers)  # fmt: skip
        action = encode_action_v1(touch.approach, touch.stroke_angle,
                                  touch.stroke_length / cfg.max_stroke)  # fmt: skip
        estimate = self.env.inner.estimate
        prediction = (self.env.blind_guess if estimate is None
                      else shape_target(estimate, cfg.obs_scale))  # fmt: skip
        return {"action": action.astype(np.float32), "prediction": prediction}


__all__ = [
    "BaselineAgent",
    "FAMILIES", "PREDICTION_DIM", "make_shape_by_touch", "make_shape_by_touch_vec", "shape_target",
]  # fmt: skip
