"""Which backend executes an environment's touches: the analytic ray caster or the MuJoCo hand
(both :class:`~hapticsim.envs.touch.TouchBackend`)."""

from __future__ import annotations

from typing import Any

from hapticsim.envs.touch import TouchBackend

#: Backends that execute touches.
BACKENDS: tuple[str, ...] = ("mujoco", "analytic")


def make_backend(config: Any) -> TouchBackend:
    """The touch backend named by ``config.backend`` of a
    :class:`~hapticsim.envs.haptic_explore_v0.HapticExploreConfig`."""
    if config.backend == "analytic":
        from hapticsim.envs.analytic import AnalyticBackend

        return AnalyticBackend(
            noise=config.noise, support=config.support, stroke_spacing=config.stroke_spacing,
            sensing=config.sensing, skin=config.skin,
        )  # fmt: skip
    from hapticsim.envs.mujoco_backend import MujocoBackend
    from hapticsim.sim.scene import SceneConfig

    scene = SceneConfig(object_dynamics=config.object_dynamics, force_limit=config.force_limit,
                        steer_on=config.steer_on)  # fmt: skip
    return MujocoBackend(
        noise=config.noise, stroke_spacing=config.stroke_spacing, hand=config.hand,
        sensing=config.sensing, skin=config.skin, scene_config=scene,
    )  # fmt: skip


__all__ = ["BACKENDS", "make_backend"]
