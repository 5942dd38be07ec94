"""Gymnasium environments for research on haptic exploration strategies.

``hapticsim/HapticExplore-v0`` (:class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv`) is
registered when ``hapticsim`` is imported::

    import gymnasium as gym
    import hapticsim  # noqa: F401  (registers the environments)

    env = gym.make("hapticsim/HapticExplore-v0", backend="analytic")

Modules: ``haptic_explore_v0`` (the environment), ``observation`` (its fit codec), ``touch``
(action semantics, backend protocol), ``analytic`` and ``mujoco_backend`` (the two backends),
``support`` (which contacts the object's stand makes unreachable), ``estimator`` (the fit
schedule), ``policies`` (baseline exploration policies), ``rendering`` (pictures),
``vector`` (the native vector environment: N environments in one worker process per core,
``gym.make_vec``'s default for hapticsim's ids), ``registration``. Policy comparisons and speed
benchmarks sit on top, in :mod:`hapticsim.benchmarks`; the object distributions an episode
draws from are data (:mod:`hapticsim.data.distributions`).
Importing this package imports neither gymnasium nor MuJoCo.
"""
