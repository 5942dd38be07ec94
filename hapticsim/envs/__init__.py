"""Gymnasium environments for research on haptic exploration strategies.

``hapticsim/HapticExplore-v0`` (:class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv`) is
registered when ``hapticsim`` is imported::

    import gymnasium as gym
    import hapticsim  # noqa: F401  (registers the environments)

    env = gym.make("hapticsim/HapticExplore-v0", backend="analytic")

Modules: ``haptic_explore_v0`` (the environment), ``touch`` (action semantics, backend protocol),
``analytic`` and ``mujoco_backend`` (the two backends), ``support`` (which contacts the object's
stand makes unreachable), ``estimator`` (the fit schedule), ``objects`` (object distributions),
``policies`` (baseline exploration policies), ``comparison`` (policy comparison: tables, plot),
``benchmark`` (steps per second), ``rendering`` (pictures), ``registration``.
Importing this package imports neither gymnasium nor MuJoCo.
"""
