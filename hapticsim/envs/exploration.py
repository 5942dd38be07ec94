"""An exploration by one of the environment's policies, as ``hapticsim explore`` records it.

The simulation's own strategies (``paper``, ``sweep``, ...: :mod:`hapticsim.sim.strategies`) plan
a fixed set of patches and stripes from the rough object. The environment's policies
(:mod:`hapticsim.envs.policies`: ``uncertainty``, ``learned``, ``random``) choose each touch from
what has been felt so far, so a run can cover a whole object rather than the side a plan
favours: :func:`run_policy_exploration` runs one in :class:`~hapticsim.envs.haptic_explore_v0.
HapticExploreEnv` on the MuJoCo hand (the given scene configuration, no sensor noise: explore
adds it afterwards) until `count` contacts are recorded, and returns the same
:class:`~hapticsim.sim.session.Exploration` a strategy's run does. The environment refits after
every touch (its default schedule), which the policies read from its observation.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from hapticsim._validate import as_generator, positive_int
from hapticsim.constants import MAX_CONTACTS
from hapticsim.errors import InvalidInputError, SimulationError
from hapticsim.geometry.solid import Solid, solid_arg
from hapticsim.sim.free_space import FreeSpaceTrace

#: The policies an exploration can run (``learned:PATH`` too: a weight file).
POLICY_STRATEGIES: tuple[str, ...] = (
    "uncertainty", "information", "learned", "learned-touch", "random",
)  # fmt: skip
#: Touches in a row that record nothing before the run gives up.
MAX_IDLE_TOUCHES: int = 40


def is_policy_strategy(name: Any) -> bool:
    """True for a policy name an exploration runs in the environment (module docstring)."""
    from hapticsim.envs.policies import LEARNED_PREFIX

    return isinstance(name, str) and (name in POLICY_STRATEGIES or (
        name.startswith(LEARNED_PREFIX) and len(name) > len(LEARNED_PREFIX)))  # fmt: skip


def run_policy_exploration(
    truth: Solid,
    policy: str,
    count: int,
    rng: np.random.Generator | int | None = 0,
    scene_config: Any = None,
    progress: Callable[[int], None] | None = None,
    video: Any = None,
    max_touches: int | None = None,
    hand_trace: Any = None,
) -> Any:
    """Explore `truth` with an environment policy until `count` contacts (module docstring).

    Args:
        truth: the object, posed in the world.
        policy: ``"uncertainty"``, ``"information"``, ``"learned"``, ``"learned-touch"``,
            ``"random"`` or ``"learned:PATH"``.
        count: contacts to gather.
        rng: seed or generator (the environment's seed, then the policy's).
        scene_config: the scene (:class:`~hapticsim.sim.scene.SceneConfig`; default ones).
        progress: called with the number of contacts after every touch.
        video: an :class:`~hapticsim.sim.video.ExplorationVideo` taking frames, or None.
        max_touches: touches allowed (default `count`: at least one contact each).
        hand_trace: a :class:`~hapticsim.sim.hand_trace.HandTrace` keeping the hand's poses, or
            None.

    Returns:
        the :class:`~hapticsim.sim.session.Exploration` (its patterns are the touches' probes
        and strokes).

    Raises:
        InvalidInputError: an unknown policy.
        SimulationError: the object is too large or too far for the hand, or fewer than
            :data:`~hapticsim.sim.session.MIN_CONTACTS` contacts were gathered.
    """
    from hapticsim.envs.haptic_explore_tactile_v0 import v0_class
    from hapticsim.envs.policies import make_policy
    from hapticsim.sim.scene import SceneConfig
    from hapticsim.sim.session import MIN_CONTACTS, Exploration

    truth = solid_arg(truth, "truth")
    if not is_policy_strategy(policy):
        raise InvalidInputError(
            f"`policy` must be one of {POLICY_STRATEGIES} or 'learned:PATH', got {policy!r}"
        )
    count = positive_int(count, "count", minimum=MIN_CONTACTS, maximum=MAX_CONTACTS)
    budget = count if max_touches is None else positive_int(max_touches, "max_touches")
    config = SceneConfig() if scene_config is None else scene_config
    gen = as_generator(rng)
    env_seed, policy_seed = (int(s) for s in gen.integers(2**63, size=2))
    start = time.perf_counter()
    env = v0_class(config.sensing)(
        backend="mujoco", objects=[truth], touch_budget=budget, noise=0.0,
        max_contacts=max(256, count + 64), compute_metrics=False, reward="eof",
        hand=config.hand, sensing=config.sensing, skin=config.skin,
    )  # fmt: skip
    backend = env._backend
    backend.scene_config = replace(backend.scene_config, taxel_model=config.taxel_model)
    agent = make_policy(policy, env, rng=policy_seed)
    obs, _ = env.reset(seed=env_seed, options={"shape": truth})
    agent.reset(policy_seed)
    explorer = backend._explorer
    trace = FreeSpaceTrace()  # fingertip centres: free space for nML (changes no physics)
    trace.attach(explorer.sim)
    if video is not None:
        video.attach(explorer.sim, explorer.recorder)
    if hand_trace is not None:
        hand_trace.attach(explorer.sim, explorer.recorder)
    recorder, idle, touches, stop = explorer.recorder, 0, 0, None
    while len(recorder) < count:
        if touches >= budget:
            stop = f"the {budget} touches allowed were used up"
            break
        before = len(recorder)
        obs, _, _, _, _ = env.step(agent(obs))
        touches += 1
        idle = idle + 1 if len(recorder) == before else 0
        if progress is not None:
            progress(min(len(recorder), count))
        if idle >= MAX_IDLE_TOUCHES:
            stop = f"{MAX_IDLE_TOUCHES} touches in a row recorded nothing"
            break
    wall = time.perf_counter() - start
    if len(recorder) < MIN_CONTACTS:
        raise SimulationError(
            f"the {policy!r} exploration gathered only {len(recorder)} contacts (at least "
            f"{MIN_CONTACTS} needed): {stop or 'the hand could not reach the surface'}"
        )
    keep = slice(0, count)
    return Exploration(
        truth=truth,
        rough=explorer.rough,
        arrays={k: v[keep] for k, v in recorder.arrays().items()},
        pattern_kinds=tuple(recorder.pattern_kinds),
        log=tuple(explorer.log),
        sim_time=explorer.sim.time,
        steps=explorer.sim.steps,
        wall_time=wall,
        explorer=explorer,
        requested=count,
        stop_reason=stop,
        free_space=trace.points(),
        tactile={k: v[keep] for k, v in recorder.tactile_arrays().items()},
        unfelt=recorder.unfelt,
    )


__all__ = ["MAX_IDLE_TOUCHES", "POLICY_STRATEGIES", "is_policy_strategy", "run_policy_exploration"]
