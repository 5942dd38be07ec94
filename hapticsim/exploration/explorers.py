"""Explorers: what chooses the touches of a trial. One protocol, two implementations.

- :class:`StrategyExplorer`: a scripted strategy of the simulation (``paper``, ``patch``,
  ``stripe``, ``sweep``: :mod:`hapticsim.sim.strategies`) plans a set of patches and stripes on
  the vision estimate and runs them (:func:`hapticsim.sim.session.run_exploration`).
- :class:`PolicyExplorer`: an environment policy (:mod:`hapticsim.envs.policies`:
  ``uncertainty``, ``information``, ``learned``, ``learned-touch``, ``random``,
  ``learned:PATH``) chooses each touch from what has been felt so far, in
  :class:`~hapticsim.envs.haptic_explore_v0.HapticExploreEnv` on the MuJoCo hand (no sensor
  noise: the trial adds it afterwards, SPEC §5), until `count` contacts are recorded. The
  environment refits after every touch (its default schedule), which the policies read.

Both return the same :class:`~hapticsim.sim.session.Exploration`. A name that is both a
strategy and a policy (``paper``) is the strategy.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, Protocol

import numpy as np

from hapticsim._validate import did_you_mean
from hapticsim.errors import InvalidInputError, SimulationError

#: Touches in a row that record nothing before a policy's exploration gives up.
MAX_IDLE_TOUCHES: int = 40


@dataclass
class ExplorationHooks:
    """What a caller watches or keeps during an exploration; none of it changes the physics.

    Attributes:
        progress: called with the number of contacts so far (after every pattern or touch).
        on_pattern_end: called with the simulation's explorer after every pattern (scripted
            strategies only).
        video: an :class:`~hapticsim.sim.video.ExplorationVideo` taking frames, or None.
        hand_trace: a :class:`~hapticsim.sim.hand_trace.HandTrace` keeping the hand's poses.
    """

    progress: Callable[[int], None] | None = None
    on_pattern_end: Callable[[Any], None] | None = None
    video: Any = None
    hand_trace: Any = None


class Explorer(Protocol):
    """Chooses and makes the touches of one exploration."""

    name: str

    def explore(
        self, truth: Any, count: int, rng: np.random.Generator, scene: Any,
        hooks: ExplorationHooks | None = None,
    ) -> Any:  # fmt: skip
        """Explore `truth` (posed in the world) with the hand of `scene` until `count`
        contacts; returns the :class:`~hapticsim.sim.session.Exploration`.

        Raises:
            SimulationError: the object is out of the hand's reach, the simulation went
                unstable, or too few contacts were gathered.
        """
        ...


@dataclass(frozen=True)
class StrategyExplorer:
    """A scripted strategy of the simulation (module docstring)."""

    name: str

    def explore(
        self, truth: Any, count: int, rng: np.random.Generator, scene: Any,
        hooks: ExplorationHooks | None = None,
    ) -> Any:  # fmt: skip
        from hapticsim.sim.session import run_exploration

        h = hooks or ExplorationHooks()
        return run_exploration(truth, self.name, count, rng, scene_config=scene,
                               progress=h.progress, on_pattern_end=h.on_pattern_end,
                               video=h.video, hand_trace=h.hand_trace)  # fmt: skip


@dataclass(frozen=True)
class PolicyExplorer:
    """An environment policy choosing every touch (module docstring).

    Attributes:
        name: the policy's name.
        max_touches: touches allowed (default: `count`, at least one contact each).
    """

    name: str
    max_touches: int | None = None

    def explore(
        self, truth: Any, count: int, rng: np.random.Generator, scene: Any,
        hooks: ExplorationHooks | None = None,
    ) -> Any:  # fmt: skip
        from hapticsim.envs.haptic_explore_tactile_v0 import make_v0
        from hapticsim.envs.policies import make_policy
        from hapticsim.sim.free_space import FreeSpaceTrace
        from hapticsim.sim.scene import SceneConfig
        from hapticsim.sim.session import MIN_CONTACTS, UNREACHED, Exploration

        h = hooks or ExplorationHooks()
        budget = count if self.max_touches is None else self.max_touches
        config = SceneConfig() if scene is None else scene
        env_seed, policy_seed = (int(s) for s in rng.integers(2**63, size=2))
        start = time.perf_counter()
        env = make_v0(
            backend="mujoco", objects=[truth], touch_budget=budget, noise=0.0,
            max_contacts=max(256, count + 64), compute_metrics=False, reward="eof",
            hand=config.hand, sensing=config.sensing, skin=config.skin,
        )  # fmt: skip
        backend = env.unwrapped.backend
        backend.scene_config = replace(backend.scene_config, taxel_model=config.taxel_model,
                                       steer_on=config.steer_on,
                                       object_dynamics=config.object_dynamics,
                                       force_limit=config.force_limit)  # fmt: skip
        agent = make_policy(self.name, env, rng=policy_seed)
        obs, _ = env.reset(seed=env_seed, options={"shape": truth})
        agent.reset(policy_seed)
        explorer = backend.explorer
        trace = FreeSpaceTrace()  # fingertip centres: free space for nML (changes no physics)
        trace.attach(explorer.sim)
        if h.video is not None:
            h.video.attach(explorer.sim, explorer.recorder)
        if h.hand_trace is not None:
            h.hand_trace.attach(explorer.sim, explorer.recorder)
        recorder, idle, touches, stop = explorer.recorder, 0, 0, None
        while len(recorder) < count:
            if touches >= budget:
                stop = f"the {budget} touches allowed were used up"
                break
            before = len(recorder)
            obs, _, _, _, _ = env.step(agent(obs))
            touches += 1
            idle = idle + 1 if len(recorder) == before else 0
            if h.progress is not None:
                h.progress(min(len(recorder), count))
            if explorer.lost is not None:  # a free object tipped over or left its place
                stop = explorer.lost
                break
            if idle >= MAX_IDLE_TOUCHES:
                stop = f"{MAX_IDLE_TOUCHES} touches in a row recorded nothing"
                break
        wall = time.perf_counter() - start
        if len(recorder) < MIN_CONTACTS:
            raise SimulationError(
                f"the {self.name!r} exploration gathered only {len(recorder)} contacts (at "
                f"least {MIN_CONTACTS} needed): {stop or UNREACHED}"
            )
        return Exploration.of(truth, explorer, count, wall, stop, trace.points(), count=count)


def policy_explorer_names() -> tuple[str, ...]:
    """The environment policies an exploration can run (``learned:PATH`` too): every policy
    whose name is not a scripted strategy's."""
    from hapticsim.envs.policies import POLICY_NAMES
    from hapticsim.sim.strategies import strategy_names

    strategies = set(strategy_names())
    return tuple(n for n in POLICY_NAMES if n not in strategies)


def explorer_names() -> tuple[str, ...]:
    """Every explorer name: the scripted strategies, then the policies."""
    from hapticsim.sim.strategies import strategy_names

    return (*strategy_names(), *policy_explorer_names())


def is_policy(name: Any) -> bool:
    """True for a name a :class:`PolicyExplorer` runs (``learned:PATH`` included)."""
    from hapticsim.envs.policies import LEARNED_PREFIX

    return isinstance(name, str) and (name in policy_explorer_names() or (
        name.startswith(LEARNED_PREFIX) and len(name) > len(LEARNED_PREFIX)))  # fmt: skip


def check_explorer(name: Any) -> str:
    """`name` if it names an explorer.

    Raises:
        InvalidInputError: naming the strategies and policies to choose from.
    """
    from hapticsim.sim.strategies import strategy_names

    if isinstance(name, str) and (name in strategy_names() or is_policy(name)):
        return name
    raise InvalidInputError(
        f"`strategy` must be one of {', '.join(strategy_names())} (scripted) or "
        f"{', '.join(policy_explorer_names())}, learned:PATH (policies), got {name!r}"
        f"{did_you_mean(name, explorer_names())}"
    )


def explorer_for(name: str, max_touches: int | None = None) -> Explorer:
    """The explorer a name gives (:func:`check_explorer`); `max_touches` bounds a policy's
    touches (default: one per contact asked for)."""
    from hapticsim.sim.strategies import strategy_names

    check_explorer(name)
    if name in strategy_names():
        return StrategyExplorer(name)
    return PolicyExplorer(name, max_touches)


__all__ = [
    "MAX_IDLE_TOUCHES", "ExplorationHooks", "Explorer", "PolicyExplorer", "StrategyExplorer",
    "check_explorer", "explorer_for", "explorer_names", "is_policy", "policy_explorer_names",
]  # fmt: skip
