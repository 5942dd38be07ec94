"""Registration of hapticsim's Gymnasium environments (called when ``hapticsim`` is imported).

Gymnasium 1.x reads no entry points from installed packages, so ``import hapticsim`` registers
them; ``gymnasium.make("hapticsim/HapticExplore-v0")`` then works, and so does
``gymnasium.make("hapticsim:hapticsim/HapticExplore-v0")`` without a prior import. Versions:

- ``hapticsim/HapticExplore-v0``: the exploration task (Dict observation of contacts and fit);
- ``hapticsim/HapticExplore-v1``: the same task with a compact observation, an action without
  finger and a log-epsilon reward, for learners
  (:class:`~hapticsim.envs.haptic_explore_v1.HapticExploreV1Env`);
- ``hapticsim/HapticExploreTactile-v0``: the task felt through taxel pads, their images in the
  observation (:class:`~hapticsim.envs.haptic_explore_tactile_v0.HapticExploreTactileEnv`): an
  environment of its own name, another observation (SPEC §8).
"""

from __future__ import annotations

#: Id of the exploration environment.
HAPTIC_EXPLORE_ID: str = "hapticsim/HapticExplore-v0"
#: Its string entry point (imported only when the environment is made).
HAPTIC_EXPLORE_ENTRY_POINT: str = "hapticsim.envs.haptic_explore_v0:HapticExploreEnv"
#: Id of version 1 (compact observation for learners).
HAPTIC_EXPLORE_V1_ID: str = "hapticsim/HapticExplore-v1"
#: Its string entry point.
HAPTIC_EXPLORE_V1_ENTRY_POINT: str = "hapticsim.envs.haptic_explore_v1:HapticExploreV1Env"
#: Id of the tactile environment (taxel images in the observation).
HAPTIC_EXPLORE_TACTILE_ID: str = "hapticsim/HapticExploreTactile-v0"
#: Its string entry point.
HAPTIC_EXPLORE_TACTILE_ENTRY_POINT: str = (
    "hapticsim.envs.haptic_explore_tactile_v0:HapticExploreTactileEnv"
)


def register_envs() -> None:
    """Register ``hapticsim/HapticExplore-v0``, ``-v1`` and ``hapticsim/HapticExploreTactile-v0``;
    calling it again does nothing."""
    from gymnasium.envs.registration import register, registry

    for env_id, entry_point in (
        (HAPTIC_EXPLORE_ID, HAPTIC_EXPLORE_ENTRY_POINT),
        (HAPTIC_EXPLORE_V1_ID, HAPTIC_EXPLORE_V1_ENTRY_POINT),
        (HAPTIC_EXPLORE_TACTILE_ID, HAPTIC_EXPLORE_TACTILE_ENTRY_POINT),
    ):
        if env_id in registry:
            continue
        register(
            id=env_id, entry_point=entry_point, max_episode_steps=None, disable_env_checker=False
        )
