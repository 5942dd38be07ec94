"""Registration of hapticsim's Gymnasium environments (called when ``hapticsim`` is imported).

Gymnasium 1.x reads no entry points from installed packages, so ``import hapticsim`` registers
them; ``gymnasium.make("hapticsim/HapticExplore-v0")`` then works, and so does
``gymnasium.make("hapticsim:hapticsim/HapticExplore-v0")`` without a prior import. Versions:

- ``hapticsim/HapticExplore-v0``: the exploration task (Dict observation of contacts and fit);
- ``hapticsim/HapticExploreCompact-v0``: the same task with a compact observation, an action
  without finger and a log-epsilon reward, for learners
  (:class:`~hapticsim.envs.haptic_explore_compact_v0.HapticExploreCompactEnv`). It was registered as
  ``hapticsim/HapticExplore-v1`` until 0.1 (SPEC §8: another task is another name, not a newer
  version), which made ``gym.make`` of v0 warn that it was "out of date"; the old id still
  makes it, with a :class:`FutureWarning` naming the new one, and is kept out of Gymnasium's
  version lookup, so v0 warns of nothing;
- ``hapticsim/HapticExploreTactile-v0``: the task felt through taxel pads, their images in the
  observation (:class:`~hapticsim.envs.haptic_explore_tactile_v0.HapticExploreTactileEnv`): an
  environment of its own name, another observation (SPEC §8);
- ``hapticsim/HapticExploreTactile-v1``: the same with the skin's traction field (shear and
  each taxel's stick or slip; SPEC §11) beside the images
  (:class:`~hapticsim.envs.haptic_explore_tactile_v1.HapticExploreTactileV1Env`);
- ``hapticsim/HapticExploreTouch-v0``: the compact task observed as the touch history itself
  (contacts, normals and past touches as sets for a permutation-invariant encoder, no coverage
  features; :class:`~hapticsim.envs.haptic_explore_touch_v0.HapticExploreTouchEnv`);
- ``hapticsim/HapticExploreTouchTactile-v0``: the same felt through taxel pads, each touch's pad
  image in its set element
  (:class:`~hapticsim.envs.haptic_explore_touch_v0.HapticExploreTouchTactileEnv`).

Each id's vector entry point is :class:`~hapticsim.envs.vector.HapticVectorEnv`: ``gym.make_vec(
env_id, num_envs=N)`` steps the N environments in one worker process per CPU core, not one per
environment; ``vectorization_mode="sync"`` or ``"async"`` still gives Gymnasium's own.
"""

from __future__ import annotations

import warnings
from functools import partial

import gymnasium as gym
from gymnasium.envs.registration import EnvSpec, register, registry

#: Id of the exploration environment.
HAPTIC_EXPLORE_ID: str = "hapticsim/HapticExplore-v0"
#: Its string entry point (imported only when the environment is made).
HAPTIC_EXPLORE_ENTRY_POINT: str = "hapticsim.envs.haptic_explore_v0:HapticExploreEnv"
#: Id of the compact variant for learners (a wrapper of the core).
HAPTIC_EXPLORE_COMPACT_ID: str = "hapticsim/HapticExploreCompact-v0"
#: Its string entry point.
HAPTIC_EXPLORE_COMPACT_ENTRY_POINT: str = (
    "hapticsim.envs.haptic_explore_compact_v0:HapticExploreCompactEnv"
)
#: Ids that name another one now (old -> new): they still make it, with a FutureWarning.
RENAMED_IDS: dict[str, str] = {"hapticsim/HapticExplore-v1": HAPTIC_EXPLORE_COMPACT_ID}
#: Id of the tactile environment (taxel images in the observation).
HAPTIC_EXPLORE_TACTILE_ID: str = "hapticsim/HapticExploreTactile-v0"
#: Its string entry point.
HAPTIC_EXPLORE_TACTILE_ENTRY_POINT: str = (
    "hapticsim.envs.haptic_explore_tactile_v0:HapticExploreTactileEnv"
)

#: Id of the tactile environment with the skin's traction field (shear and stick/slip states).
HAPTIC_EXPLORE_TACTILE_V1_ID: str = "hapticsim/HapticExploreTactile-v1"
#: Its string entry point.
HAPTIC_EXPLORE_TACTILE_V1_ENTRY_POINT: str = (
    "hapticsim.envs.haptic_explore_tactile_v1:HapticExploreTactileV1Env"
)

#: Id of the touch-history variant for learners.
HAPTIC_EXPLORE_TOUCH_ID: str = "hapticsim/HapticExploreTouch-v0"
#: Its string entry point.
HAPTIC_EXPLORE_TOUCH_ENTRY_POINT: str = (
    "hapticsim.envs.haptic_explore_touch_v0:HapticExploreTouchEnv"
)
#: Id of the touch-history variant felt through taxel pads (pad images in the touch set).
HAPTIC_EXPLORE_TOUCH_TACTILE_ID: str = "hapticsim/HapticExploreTouchTactile-v0"
#: Its string entry point.
HAPTIC_EXPLORE_TOUCH_TACTILE_ENTRY_POINT: str = (
    "hapticsim.envs.haptic_explore_touch_tactile_v0:HapticExploreTouchTactileEnv"
)


#: Id of the ap_gym active perception task (extra ``apgym``).
SHAPE_BY_TOUCH_ID: str = "hapticsim/ShapeByTouch-v0"
#: Its entry point.
SHAPE_BY_TOUCH_ENTRY_POINT: str = "hapticsim.envs.shape_by_touch_v0:make_shape_by_touch"
#: Its vector entry point.
SHAPE_BY_TOUCH_VECTOR_ENTRY_POINT: str = (
    "hapticsim.envs.shape_by_touch_v0:make_shape_by_touch_vec"
)


def canonical_id(env_id: str) -> str:
    """The id an environment id stands for today (a renamed id gives its new name)."""
    return RENAMED_IDS.get(env_id, env_id)


def make_renamed(old_id: str, **kwargs: object):  # noqa: ANN201 - a gymnasium.Env
    """Entry point of a renamed id: warn, then make the environment of its new id."""

    new_id = RENAMED_IDS[old_id]
    warnings.warn(
        f"{old_id} is now {new_id} (another task, not a newer version of "
        f"{HAPTIC_EXPLORE_ID}); the old id will be removed in a later release",
        FutureWarning,
        stacklevel=4,
    )
    from gymnasium.envs.registration import load_env_creator

    return load_env_creator(gym.spec(new_id).entry_point)(**kwargs)


def make_vector_env(env_id: str, num_envs: int = 1, **kwargs: object):  # noqa: ANN201
    """Vector entry point of every id: :class:`~hapticsim.envs.vector.HapticVectorEnv` (N
    environments in a few worker processes; ``gym.make_vec(env_id, num_envs=N)``)."""
    from hapticsim.envs.vector import HapticVectorEnv

    return HapticVectorEnv(env_id, num_envs=num_envs, **kwargs)


def register_envs() -> None:
    """Register ``hapticsim/HapticExplore-v0``, ``hapticsim/HapticExploreCompact-v0``,
    ``hapticsim/HapticExploreTactile-v0`` and ``-v1``, ``hapticsim/HapticExploreTouch-v0``,
    ``hapticsim/HapticExploreTouchTactile-v0`` and ``hapticsim/ShapeByTouch-v0``, and the
    renamed ids (:data:`RENAMED_IDS`); calling
    it again does nothing."""

    for old_id in RENAMED_IDS:
        if old_id in registry:
            continue
        # Under its old key, but with a name of its own: Gymnasium's version lookup (which made
        # v0 "out of date") only sees specs named HapticExplore.
        registry[old_id] = EnvSpec(
            id=old_id.replace("-v", "Renamed-v"), entry_point=partial(make_renamed, old_id),
            disable_env_checker=True,
        )  # fmt: skip
    for env_id, entry_point in (
        (HAPTIC_EXPLORE_ID, HAPTIC_EXPLORE_ENTRY_POINT),
        (HAPTIC_EXPLORE_COMPACT_ID, HAPTIC_EXPLORE_COMPACT_ENTRY_POINT),
        (HAPTIC_EXPLORE_TACTILE_ID, HAPTIC_EXPLORE_TACTILE_ENTRY_POINT),
        (HAPTIC_EXPLORE_TACTILE_V1_ID, HAPTIC_EXPLORE_TACTILE_V1_ENTRY_POINT),
        (HAPTIC_EXPLORE_TOUCH_ID, HAPTIC_EXPLORE_TOUCH_ENTRY_POINT),
        (HAPTIC_EXPLORE_TOUCH_TACTILE_ID, HAPTIC_EXPLORE_TOUCH_TACTILE_ENTRY_POINT),
    ):
        if env_id in registry:
            continue
        register(
            id=env_id, entry_point=entry_point, max_episode_steps=None, disable_env_checker=False,
            vector_entry_point=partial(make_vector_env, env_id),
        )  # fmt: skip
    if SHAPE_BY_TOUCH_ID not in registry:  # ap_gym's own vector env (its loss every step)
        register(id=SHAPE_BY_TOUCH_ID, entry_point=SHAPE_BY_TOUCH_ENTRY_POINT,
                 max_episode_steps=None, disable_env_checker=False,
                 vector_entry_point=SHAPE_BY_TOUCH_VECTOR_ENTRY_POINT)  # fmt: skip
