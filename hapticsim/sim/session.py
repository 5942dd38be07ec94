"""One headless exploration run: scene, rough object, strategy, recorded contacts.

:func:`run_exploration` runs a scripted strategy: the simulation half of a trial whose explorer
is a strategy (:class:`hapticsim.exploration.StrategyExplorer`;
:func:`hapticsim.exploration.run_trial` adds sensor noise, the fit and the score).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hapticsim._validate import as_generator, positive_int
from hapticsim.constants import DEFAULT_CONTACTS, MAX_CONTACTS, MIN_CONTACTS
from hapticsim.errors import SimulationError
from hapticsim.geometry.solid import Solid, solid_arg
from hapticsim.perception.vision import RoughObject, vision_estimate
from hapticsim.sim.explorer import Explorer, ExplorerConfig
from hapticsim.sim.free_space import FreeSpaceTrace
from hapticsim.sim.hand_trace import HandTrace
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.scene import SceneConfig, build_scene
from hapticsim.sim.strategies import get_strategy
from hapticsim.sim.video import ExplorationVideo

#: Why an exploration without a better reason gathered too few contacts.
UNREACHED: str = "the hand could not reach the object's surface"
#: Default number of contacts (paper IV).
DEFAULT_COUNT: int = DEFAULT_CONTACTS


@dataclass(frozen=True, eq=False)
class Exploration:
    """What an exploration produced.

    Attributes:
        truth: the true object [world]: a superquadric or a mesh solid.
        rough: what the controllers knew.
        arrays: recorded contacts (see :meth:`Recorder.arrays`): ``points_clean``,
            ``normals_clean``, ``finger``, ``force``, ``time``, ``pattern``, ``dist``.
        pattern_kinds: kind (``"patch"``/``"stripe"``) of each pattern id.
        log: one entry per controller run (finger, contacts, how it ended).
        sim_time: simulated time [s].
        steps: physics steps.
        wall_time: wall-clock time of the run, scene building included [s].
        explorer: the explorer (its simulator holds the final state).
        requested: contacts asked for.
        stop_reason: why fewer than `requested` were gathered (None when all were).
        free_space: (f, 3) float, fingertip centres along the run [m, world]
            (:class:`~hapticsim.sim.free_space.FreeSpaceTrace`): outside the object.
        tactile: with tactile sensing, every pad's reading at each contact
            (:meth:`Recorder.tactile_arrays`), else an empty dict.
        unfelt: touches the skin did not feel (tactile sensing; not recorded).
        truth_final: a free object (SPEC §12) where the exploration left it (`truth` is where it
            rested before the first touch); None for a fixed object.
    """

    truth: Solid
    rough: RoughObject
    arrays: dict[str, np.ndarray]
    pattern_kinds: tuple[str, ...]
    log: tuple[dict[str, Any], ...]
    sim_time: float
    steps: int
    wall_time: float
    explorer: Explorer = field(repr=False)
    requested: int = 0
    stop_reason: str | None = None
    free_space: np.ndarray | None = None
    tactile: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    unfelt: int = 0
    truth_final: Solid | None = None

    @classmethod
    def of(
        cls, truth: Solid, explorer: Explorer, requested: int, wall_time: float,
        stop_reason: str | None, free_space: np.ndarray | None, count: int | None = None,
    ) -> Exploration:  # fmt: skip
        """What `explorer` recorded on `truth` (its recorder, log and simulator), the first
        `count` contacts (default: all)."""
        recorder = explorer.recorder
        keep = slice(0, count)
        final = None
        if explorer.scene.free:  # the object at rest before the first touch, and at the end
            from hapticsim.sim.dynamics import relative_motion

            truth = explorer.scene.truth
            sim = explorer.sim
            final = truth.transformed(*relative_motion(sim.object_pose(), sim.initial_object_pose))
        return cls(
            truth=truth,
            rough=explorer.rough,
            arrays={k: v[keep] for k, v in recorder.arrays().items()},
            pattern_kinds=tuple(recorder.pattern_kinds),
            log=tuple(explorer.log),
            sim_time=explorer.sim.time,
            steps=explorer.sim.steps,
            wall_time=wall_time,
            explorer=explorer,
            requested=requested,
            stop_reason=stop_reason,
            free_space=free_space,
            tactile={k: v[keep] for k, v in recorder.tactile_arrays().items()},
            unfelt=recorder.unfelt,
            truth_final=final,
        )

    @property
    def count(self) -> int:
        """Number of recorded contacts."""
        return int(len(self.arrays["finger"]))

    @property
    def complete(self) -> bool:
        """True when as many contacts were gathered as asked for."""
        return self.count >= self.requested

    @property
    def steps_per_second(self) -> float:
        """Physics steps per wall-clock second over the whole run."""
        return self.steps / max(self.wall_time, 1e-9)


def run_exploration(
    truth: Solid,
    strategy: str = "paper",
    count: int = DEFAULT_COUNT,
    rng: np.random.Generator | int | None = 0,
    scene_config: SceneConfig | None = None,
    config: ExplorerConfig | None = None,
    progress: Callable[[int], None] | None = None,
    on_pattern_end: Callable[[Explorer], None] | None = None,
    rough: RoughObject | None = None,
    video: ExplorationVideo | None = None,
    hand_trace: HandTrace | None = None,
) -> Exploration:
    """Explore an object with the hand and return the recorded (clean) contacts.

    Args:
        truth: the object, posed in the world (a superquadric or a mesh solid).
        strategy: a registered strategy name (:func:`~hapticsim.sim.strategies.strategy_names`).
        count: contacts to gather, >= :data:`MIN_CONTACTS`.
        rng: seed or generator (the rough object and the strategy's random choices).
        scene_config: scene options.
        config: explorer options.
        progress: called with the number of contacts after every pattern.
        on_pattern_end: called with the explorer after every pattern.
        rough: what the controllers know about the object (default: a vision estimate,
            :func:`~hapticsim.perception.vision.vision_estimate`, drawn from `rng`).
        video: takes frames of the run (:class:`~hapticsim.sim.video.ExplorationVideo`); the
            caller calls its ``finish``. Frames change nothing in the simulation.
        hand_trace: keeps the hand's pose at every new contact
            (:class:`~hapticsim.sim.hand_trace.HandTrace`, a run's ``hand.npz``); changes nothing.

    Returns:
        The exploration.

    Raises:
        InvalidInputError: unknown strategy (listing the choices) or bad arguments.
        SimulationError: the object is too large or too far for the hand, the simulation went
            unstable, or fewer than :data:`MIN_CONTACTS` contacts were gathered.
    """
    truth = solid_arg(truth, "truth")
    run_strategy = get_strategy(strategy)
    count = positive_int(count, "count", minimum=MIN_CONTACTS, maximum=MAX_CONTACTS)
    gen = as_generator(rng)
    rough_rng, strategy_rng = gen.spawn(2)
    start = time.perf_counter()
    scene = build_scene(truth, scene_config)
    # the skin's sensor model draws from a third stream, so exact runs keep theirs
    tactile_rng = gen.spawn(1)[0] if scene.config.sensing == "tactile" else None
    if rough is None:
        rough = vision_estimate(truth, rough_rng)
    recorder = Recorder(count)
    explorer = Explorer(scene, rough, recorder, config, progress, on_pattern_end,
                        tactile_rng=tactile_rng)  # fmt: skip
    if video is not None:
        video.attach(explorer.sim, recorder)
    if hand_trace is not None:
        hand_trace.attach(explorer.sim, recorder)
    trace = FreeSpaceTrace()  # fingertip centres: free space for nML (changes no physics)
    trace.attach(explorer.sim)
    run_strategy(explorer, count, strategy_rng)
    wall = time.perf_counter() - start
    if len(recorder) < MIN_CONTACTS:
        raise SimulationError(
            f"the {strategy!r} exploration gathered only {len(recorder)} contacts (at least "
            f"{MIN_CONTACTS} needed): {explorer.lost or UNREACHED}"
        )
    return Exploration.of(truth, explorer, count, wall, explorer.stop_reason, trace.points())


__all__ = ["DEFAULT_COUNT", "Exploration", "MIN_CONTACTS", "run_exploration"]
