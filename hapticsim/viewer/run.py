"""One explore run directory, read for the viewer, and its replay: one state per touch.

A run directory (``hapticsim explore --out DIR``) must hold ``contacts.npz``, ``fit.json``,
``metrics.json`` and the truth (``truth.json`` or ``truth.stl``); ``hand.npz`` (the hand at every
touch, :mod:`hapticsim.sim.hand_trace`) and ``tactile.npz`` (taxel images, tactile sensing) are
used where present. :func:`load_run` checks every file first and names all that are missing.

:func:`replay_states` cuts the run into states: state ``k`` holds the contacts recorded up to the
``k``-th touch (from ``hand.npz``; without it, one state per contact), the hand's pose then, and
the estimate fitted to those contacts with its epsilon against the truth (the run's own method
for the single-superquadric methods, nH for nML and multi, whose fits cost 5-50x more; the last
state shows the run's saved estimate). Estimates need at least 13 contacts.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from hapticsim.data.rundir import RunData, load_run, missing_files
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Solid

#: Methods the replay refits after every touch as they are; others are replayed with nH.
REPLAY_METHODS: tuple[str, ...] = ("LS", "H", "nLS", "nH")
#: Fewest contacts a superquadric is fitted to (13 parameters).
MIN_FIT_CONTACTS: int = 13


@dataclass
class State:
    """The run after one touch.

    Attributes:
        contacts: contacts recorded so far.
        hand_position, hand_wxyz: (G, 3) and (G, 4) pose of every hand geom, or None.
        estimate: the solid fitted to the contacts so far (None before 13), with its epsilon.
        method: the method that fitted it.
        object_pose: a free object's motion from rest at the state's last contact (7:
            translation [m] and quaternion w first, ``x_now = R x_rest + t``), or None (a
            fixed object, or a run whose metrics do not say where the object rested).
    """

    contacts: int
    hand_position: np.ndarray | None = None
    hand_wxyz: np.ndarray | None = None
    estimate: Solid | None = None
    epsilon: float | None = None
    method: str = ""
    object_pose: np.ndarray | None = None



def replay_states(
    run: RunData,
    estimate_every: int = 1,
    progress: Callable[[int, int], None] | None = None,
) -> list[State]:
    """The run's states, one per touch (module docstring).

    Args:
        run: the run.
        estimate_every: refit at every this many states (>= 1); the states between show the
            previous estimate. The last state always shows the run's own estimate.
        progress: called with (done, total) after each fit.
    """
    from hapticsim.fitting import fit
    from hapticsim.metrics.episode import TruthScorer

    if int(estimate_every) < 1:
        raise InvalidInputError(f"`estimate_every` must be >= 1, got {estimate_every}")
    n = len(run.points)
    if run.hand is not None:
        counts = np.minimum(np.asarray(run.hand["contacts"], int), n)
        positions, rotations = run.hand["position"], run.hand["wxyz"]
    else:
        counts, positions, rotations = np.arange(n + 1), None, None
    if counts[-1] < n:  # contacts after the last recorded touch belong to the last state
        counts[-1] = n
    motion = object_motion(run)
    scorer = TruthScorer(run.truth, rng=0)
    method = run.method if run.method in REPLAY_METHODS else "nH"
    due = [k for k in range(len(counts)) if counts[k] >= MIN_FIT_CONTACTS]
    due = [k for i, k in enumerate(due) if i % int(estimate_every) == 0 and k != len(counts) - 1]
    states, current, eps, done = [], None, None, 0
    fitted = set(due)
    for k, c in enumerate(counts):
        if k in fitted:
            result = fit(run.points[:c], run.normals[:c], method=method, rng=0)
            current, eps = result.solid, scorer.score(result.solid).epsilon
            done += 1
            if progress is not None:
                progress(done, len(due) + 1)
        if k == len(counts) - 1:
            current = run.estimate
            if run.tracked is not None:  # a tracking fit's shape is in the object's frame
                from hapticsim.geometry.rotations import quaternion_to_matrix

                last = run.tracked[-1]
                current = current.transformed(quaternion_to_matrix(last[3:]), last[:3])
            eps = run.metrics.get("epsilon")
            eps = float(eps) if eps is not None else scorer.score(run.estimate).epsilon
            if progress is not None:
                progress(len(due) + 1, len(due) + 1)
        states.append(State(
            contacts=int(c),
            hand_position=None if positions is None else positions[k],
            hand_wxyz=None if rotations is None else rotations[k],
            estimate=current, epsilon=eps,
            method=run.method if k == len(counts) - 1 else method,
            object_pose=None if motion is None or c == 0 else motion[c - 1],
        ))  # fmt: skip
    return states


def object_motion(run: RunData) -> np.ndarray | None:
    """(n, 7) a free object's motion from rest at each contact (:class:`State`'s
    ``object_pose``), from ``contacts.npz``'s body poses and the rest pose ``metrics.json``
    states (``object_motion.rest_pose``); None for a fixed object or an older run."""
    from hapticsim.fitting.track import true_poses

    motion = run.metrics.get("object_motion")
    rest = motion.get("rest_pose") if isinstance(motion, dict) else None
    if run.object_pose is None or rest is None:
        return None
    rest = np.asarray(rest, dtype=np.float64)
    if rest.shape != (7,) or not np.all(np.isfinite(rest)):
        raise InvalidInputError(
            f"{run.path}/metrics.json: object_motion.rest_pose must be 7 finite numbers"
        )
    return true_poses(run.object_pose, rest)


__all__ = ["RunData", "State", "load_run", "missing_files", "object_motion", "replay_states"]
