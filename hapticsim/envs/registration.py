"""Registration of hapticsim's Gymnasium environments (called when ``hapticsim`` is imported).

Gymnasium 1.x reads no entry points from installed packages, so ``import hapticsim`` registers
them; ``gymnasium.make("hapticsim/HapticExplore-v0")`` then works, and so does
``gymnasium.make("hapticsim:hapticsim/HapticExplore-v0")`` without a prior import.
"""

from __future__ import annotations

#: Id of the exploration environment.
HAPTIC_EXPLORE_ID: str = "hapticsim/HapticExplore-v0"
#: Its string entry point (imported only when the environment is made).
HAPTIC_EXPLORE_ENTRY_POINT: str = "hapticsim.envs.haptic_explore_v0:HapticExploreEnv"


def register_envs() -> None:
    """Register ``hapticsim/HapticExplore-v0``; calling it again does nothing."""
    from gymnasium.envs.registration import register, registry

    if HAPTIC_EXPLORE_ID in registry:
        return
    register(
        id=HAPTIC_EXPLORE_ID,
        entry_point=HAPTIC_EXPLORE_ENTRY_POINT,
        max_episode_steps=None,
        disable_env_checker=False,
    )
