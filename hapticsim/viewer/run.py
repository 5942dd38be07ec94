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
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim._files import read_json
from hapticsim.data.io import read_contacts
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Solid, solid_from_dict, solid_from_json

#: Files every run directory holds (the truth is either of TRUTH_FILES).
REQUIRED_FILES: tuple[str, ...] = ("contacts.npz", "fit.json", "metrics.json")
TRUTH_FILES: tuple[str, ...] = ("truth.json", "truth.stl")
#: Methods the replay refits after every touch as they are; others are replayed with nH.
REPLAY_METHODS: tuple[str, ...] = ("LS", "H", "nLS", "nH")
#: Fewest contacts a superquadric is fitted to (13 parameters).
MIN_FIT_CONTACTS: int = 13


@dataclass
class RunData:
    """What the viewer shows of one run.

    Attributes:
        path: the run directory.
        truth: the true solid [m, world].
        estimate: the run's fitted solid.
        method: the run's fitting method.
        points, normals: (n, 3) measured contacts [m] and unit normals, in recording order.
        finger: (n,) int, finger of each contact; finger_names: the hand's fingers (or
            ``finger 0`` ...).
        metrics: ``metrics.json``.
        hand: ``hand.npz``'s arrays, or None (an older run).
        taxels: (n, rows, cols) pressure image of each contact's pad, or None.
    """

    path: Path
    truth: Solid
    estimate: Solid
    method: str
    points: np.ndarray
    normals: np.ndarray
    finger: np.ndarray
    finger_names: tuple[str, ...]
    metrics: dict[str, Any]
    hand: dict[str, np.ndarray] | None = None
    taxels: np.ndarray | None = None

    @property
    def title(self) -> str:
        """One line naming the run: object, hand, strategy, method and its epsilon."""
        m = self.metrics
        return (
            f"{m.get('object', '?')} touched by the {m.get('hand', '?')} hand, "
            f"{m.get('strategy', '?')} exploration, {len(self.points)} contacts, {self.method} "
            f"fit: epsilon = {m.get('epsilon', float('nan')):.3f}"
        )


def missing_files(path: Path) -> list[str]:
    """The required files missing from run directory `path` (the truth as 'truth.json or
    truth.stl')."""
    missing = [name for name in REQUIRED_FILES if not (path / name).is_file()]
    if not any((path / name).is_file() for name in TRUTH_FILES):
        missing.append(" or ".join(TRUTH_FILES))
    return missing


def load_run(path: str | Path) -> RunData:
    """Read run directory `path` (module docstring).

    Raises:
        InvalidInputError: not a directory, required files missing (all named), or a file that
            does not read.
    """
    from hapticsim.data.objects import load_mesh

    run = Path(path)
    if not run.is_dir():
        raise InvalidInputError(f"{run} is not a run directory (hapticsim explore --out DIR)")
    missing = missing_files(run)
    if missing:
        raise InvalidInputError(
            f"{run} is not a complete explore run: missing {', '.join(missing)}"
        )
    contacts = read_contacts(run / "contacts.npz")
    n = len(contacts.points)
    extra = contacts.extra or {}
    finger = np.asarray(extra["finger"], int) if "finger" in extra else np.zeros(n, int)
    truth = (
        solid_from_json(run / "truth.json") if (run / "truth.json").is_file()
        else load_mesh(run / "truth.stl")
    )  # fmt: skip
    fit = _read_object(run / "fit.json")
    estimate = solid_from_dict(fit)
    metrics = _read_object(run / "metrics.json")
    hand = _read_npz(run / "hand.npz") if (run / "hand.npz").is_file() else None
    names = (
        tuple(str(s) for s in hand["finger_names"]) if hand is not None and "finger_names" in hand
        else tuple(f"finger {i}" for i in range(int(finger.max(initial=0)) + 1))
    )  # fmt: skip
    taxels = None
    if (run / "tactile.npz").is_file():
        tactile = _read_npz(run / "tactile.npz")
        images = tactile.get("images")
        if images is not None and len(images) == n:
            taxels = images[np.arange(n), finger]
    return RunData(
        path=run, truth=truth, estimate=estimate, method=str(fit.get("method", "nH")),
        points=contacts.points, normals=contacts.normals, finger=finger, finger_names=names,
        metrics=metrics, hand=hand, taxels=taxels,
    )  # fmt: skip


def _read_object(path: Path) -> dict[str, Any]:
    data = read_json(path)
    if not isinstance(data, dict):
        raise InvalidInputError(f"{path} must hold a JSON object")
    return data


def _read_npz(path: Path) -> dict[str, np.ndarray]:
    try:
        with np.load(path) as data:
            return {k: data[k] for k in data.files}
    except (OSError, ValueError) as exc:
        raise InvalidInputError(f"{path} does not read as a .npz file: {exc}") from None


@dataclass
class State:
    """The run after one touch.

    Attributes:
        contacts: contacts recorded so far.
        hand_position, hand_wxyz: (G, 3) and (G, 4) pose of every hand geom, or None.
        estimate: the solid fitted to the contacts so far (None before 13), with its epsilon.
        method: the method that fitted it.
    """

    contacts: int
    hand_position: np.ndarray | None = None
    hand_wxyz: np.ndarray | None = None
    estimate: Solid | None = None
    epsilon: float | None = None
    method: str = ""



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
        ))  # fmt: skip
    return states


__all__ = ["RunData", "State", "load_run", "missing_files", "replay_states"]
