"""A run directory (``hapticsim explore --out DIR``): its files, written and read in one place.

Written by :func:`hapticsim.exploration.explore`, read by ``hapticsim view``
(:mod:`hapticsim.viewer`) and by anyone with :func:`load_run`:

- ``contacts.npz`` (required): the contacts with noise (``points``, ``normals``) and what was
  recorded beside them (:mod:`hapticsim.exploration.explore` lists the keys);
- ``fit.json`` (required): the fit result (SPEC §6); ``metrics.json`` (required): the quality
  measures, contact accuracy, the object, the vision estimate;
- the truth (required): ``truth.json`` (a superquadric or union) or ``truth.stl`` (a mesh,
  world frame, metres);
- ``report.png``; optional: ``hand.npz`` (the hand at every touch,
  :mod:`hapticsim.sim.hand_trace`), ``tactile.npz`` (taxel images, tactile sensing),
  ``scene.png`` and ``exploration.mp4``/``.gif``.

:func:`write_run` writes every file through a temporary name and a rename, all or none.
:func:`load_run` checks every file first and names all that are missing.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim._files import OutputSet, read_json, write_bytes_atomic, write_json
from hapticsim.data.io import Contacts, read_contacts, write_contacts
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.geometry import Solid, solid_from_dict, solid_from_json

#: Files every run directory holds (the truth is either of TRUTH_FILES).
REQUIRED_FILES: tuple[str, ...] = ("contacts.npz", "fit.json", "metrics.json")
TRUTH_FILES: tuple[str, ...] = ("truth.json", "truth.stl")


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
        taxel_state: (n, rows, cols) int8, that pad's taxel states (0 free, 1 stick, 2 slip;
            SPEC §11), or None (a run from before the traction field).
        object_pose: (n, 7) a free object's body pose at each contact (position [m],
            quaternion w first; SPEC §12), or None for a fixed object.
        tracked: a tracking fit's poses (``fit.json``'s ``poses``, (n, 7), the estimate's frame
            in the world at each contact), or None.
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
    taxel_state: np.ndarray | None = None
    object_pose: np.ndarray | None = None
    tracked: np.ndarray | None = None

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
    taxels = states = None
    if (run / "tactile.npz").is_file():
        tactile = _read_npz(run / "tactile.npz")
        images = tactile.get("images")
        if images is not None and len(images) == n:
            taxels = images[np.arange(n), finger]
        state = tactile.get("taxel_state")
        if taxels is not None and state is not None and state.shape == images.shape:
            states = state[np.arange(n), finger].astype(np.int8)
    return RunData(
        path=run, truth=truth, estimate=estimate, method=str(fit.get("method", "nH")),
        points=contacts.points, normals=contacts.normals, finger=finger, finger_names=names,
        metrics=metrics, hand=hand, taxels=taxels, taxel_state=states,
        object_pose=_poses(extra.get("object_pose"), n, f"{run}/contacts.npz: object_pose"),
        tracked=_poses(fit.get("poses"), n, f"{run}/fit.json: poses"),
    )  # fmt: skip


def _poses(value: Any, n: int, what: str) -> np.ndarray | None:
    """Poses read from a run's file, checked: (n, 7) finite numbers, or None when absent."""
    if value is None:
        return None
    try:
        pose = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        pose = None
    if pose is None or pose.shape != (n, 7) or not np.all(np.isfinite(pose)):
        got = "something else" if pose is None else f"shape {pose.shape}"
        raise InvalidInputError(f"{what} must be ({n}, 7) finite numbers, got {got}")
    return pose


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


def npz_bytes(arrays: dict[str, Any]) -> bytes:
    """Arrays as the bytes of a compressed ``.npz`` file."""
    buf = io.BytesIO()
    np.savez_compressed(buf, **arrays)
    return buf.getvalue()


def write_run(
    out: str | Path,
    contacts: Contacts,
    truth_file: tuple[str, bytes],
    fit: dict[str, Any],
    metrics: dict[str, Any],
    files: dict[str, tuple[str, bytes]] | None = None,
) -> dict[str, Path]:
    """Write a run directory, all files or none (even on Ctrl-C).

    Args:
        out: the directory (made if missing).
        contacts: the contacts and the arrays recorded beside them (``contacts.npz``).
        truth_file: the truth's file name (one of :data:`TRUTH_FILES`) and its bytes.
        fit: the fit result (``fit.json``).
        metrics: ``metrics.json``.
        files: further files by kind: ``{"report": ("report.png", bytes), ...}``.

    Returns:
        every file written, by kind (``contacts``, ``truth``, ``fit``, ``metrics`` and the
        kinds of `files`).
    """
    if truth_file[0] not in TRUTH_FILES:
        raise ChoiceError("truth_file", truth_file[0], TRUTH_FILES)
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    with OutputSet():
        written = {
            "contacts": write_contacts(folder / "contacts.npz", contacts),
            "truth": write_bytes_atomic(folder / truth_file[0], truth_file[1]),
            "fit": write_json(folder / "fit.json", fit),
            "metrics": write_json(folder / "metrics.json", metrics),
        }
        for kind, (name, data) in (files or {}).items():
            written[kind] = write_bytes_atomic(folder / name, data)
    return written


__all__ = [
    "REQUIRED_FILES", "TRUTH_FILES", "RunData", "load_run", "missing_files", "npz_bytes",
    "write_run",
]  # fmt: skip
