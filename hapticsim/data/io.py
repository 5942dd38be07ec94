"""Reading and writing contact files and JSON (SPEC §6), atomically.

Contacts: ``.npz`` with ``points`` (n, 3) and optionally ``normals`` (n, 3), other keys ignored by
readers that do not need them; or ``.csv`` with header ``x,y,z[,nx,ny,nz]``. Files are written to
a temporary sibling and renamed, so a failure never leaves a half-written file.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._files import (
    atomic_write,
    check_output_path,
    read_json,
    read_text,
    write_json,
    write_text_atomic,
)
from hapticsim._validate import finite_array, normals_array, points_array
from hapticsim.errors import InvalidInputError

Array = NDArray[np.float64]
CONTACT_SUFFIXES: tuple[str, ...] = (".npz", ".csv")
#: Optional contacts-file array of free-space points, (f, 3) [m, world], any f: where the
#: fingertips have been, outside the object (``explore`` writes their centres along the run).
#: ``fit`` ignores it (SPEC §6) unless asked: ``--method nML --free-space``.
FREE_SPACE_KEY: str = "free_space"


@dataclass(frozen=True)
class Contacts:
    """Contact data: points and optional outward unit normals, in the world frame.

    Attributes:
        points: (n, 3) float, contact locations [m].
        normals: (n, 3) float unit vectors or None.
        extra: further named arrays (e.g. ``points_clean``, ``finger``), each with n rows,
            optionally ``free_space`` (:data:`FREE_SPACE_KEY`), (f, 3) with any f, and 0-d
            arrays of metadata (e.g. ``sensing``, a string).
    """

    points: Array
    normals: Array | None = None
    extra: dict[str, np.ndarray] | None = None

    def __post_init__(self) -> None:
        pts = points_array(self.points, "points")
        object.__setattr__(self, "points", pts)
        if self.normals is not None:
            object.__setattr__(self, "normals", normals_array(self.normals, len(pts)))
        extra = dict(self.extra or {})
        for key, value in extra.items():
            arr = np.asarray(value)
            if key == FREE_SPACE_KEY:  # free-space points: any number of rows
                extra[key] = finite_array(arr, key, (None, 3))
                continue
            if arr.ndim == 0:  # metadata of the whole file
                extra[key] = arr
                continue
            if arr.shape[0] != len(pts):
                raise InvalidInputError(
                    f"contacts array `{key}` must have one row per point ({len(pts)}), "
                    f"got shape {arr.shape}"
                )
            extra[key] = arr
        object.__setattr__(self, "extra", extra)

    def __len__(self) -> int:
        return int(self.points.shape[0])


def read_contacts(path: str | Path) -> Contacts:
    """Read a contacts file (``.npz`` or ``.csv``, SPEC §6).

    Raises:
        InvalidInputError: missing or empty file, unknown suffix, missing ``points``, wrong
            shapes, NaN, zero-length normals or normals that do not match the points.
    """
    path = Path(path)
    if not path.is_file():
        raise InvalidInputError(f"contacts file not found: {path}")
    if path.stat().st_size == 0:
        raise InvalidInputError(f"contacts file is empty: {path}")
    suffix = path.suffix.lower()
    if suffix == ".npz":
        return _read_npz(path)
    if suffix == ".csv":
        return _read_csv(path)
    raise InvalidInputError(
        f"contacts file must end in one of {CONTACT_SUFFIXES}, got {path.name!r}"
    )


def _read_npz(path: Path) -> Contacts:
    try:
        # np.load leaves its own handle open when the file is not a zip: pass ours
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
    except Exception as exc:  # zipfile/pickle errors: report in one line
        raise InvalidInputError(f"cannot read {path} as .npz: {exc}") from exc
    if "points" not in arrays:
        raise InvalidInputError(
            f"{path} has no `points` array (found: {sorted(arrays) or 'nothing'})"
        )
    points = arrays.pop("points")
    normals = arrays.pop("normals", None)
    try:
        return Contacts(points=points, normals=normals, extra=arrays)
    except InvalidInputError as exc:
        raise InvalidInputError(f"{path}: {exc}") from exc


def _read_csv(path: Path) -> Contacts:
    lines = read_text(path).splitlines()
    if not lines:
        raise InvalidInputError(f"contacts file is empty: {path}")
    header = [h.strip().lower() for h in lines[0].split(",")]
    if header not in (["x", "y", "z"], ["x", "y", "z", "nx", "ny", "nz"]):
        raise InvalidInputError(f"{path}: header must be x,y,z or x,y,z,nx,ny,nz, got {lines[0]!r}")
    rows = [ln for ln in lines[1:] if ln.strip()]
    if not rows:
        raise InvalidInputError(f"{path} has a header but no contacts")
    try:
        table = np.array([[float(v) for v in ln.split(",")] for ln in rows], dtype=np.float64)
    except ValueError as exc:
        raise InvalidInputError(f"{path}: non-numeric value ({exc})") from exc
    if table.ndim != 2 or table.shape[1] != len(header):
        raise InvalidInputError(f"{path}: every row must have {len(header)} values")
    try:
        return Contacts(points=table[:, :3], normals=table[:, 3:] if len(header) == 6 else None)
    except InvalidInputError as exc:
        raise InvalidInputError(f"{path}: {exc}") from exc


def write_contacts(path: str | Path, contacts: Contacts) -> Path:
    """Write contacts to ``.npz`` (all arrays) or ``.csv`` (points and normals), atomically."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".npz":
        arrays: dict[str, np.ndarray] = {"points": contacts.points}
        if contacts.normals is not None:
            arrays["normals"] = contacts.normals
        arrays.update(contacts.extra or {})
        return atomic_write(path, lambda fh: np.savez(fh, **arrays), "wb")
    if suffix == ".csv":
        cols = [contacts.points] + ([contacts.normals] if contacts.normals is not None else [])
        header = "x,y,z" + (",nx,ny,nz" if contacts.normals is not None else "")
        table = np.concatenate(cols, axis=1)
        body = "\n".join(",".join(repr(float(v)) for v in row) for row in table)
        return write_text_atomic(path, header + "\n" + body + "\n")
    raise InvalidInputError(
        f"contacts file must end in one of {CONTACT_SUFFIXES}, got {path.name!r}"
    )


def as_points_normals(
    points: Any, normals: Any | None = None, min_count: int = 1
) -> tuple[Array, Array | None]:
    """Validate a points array and optional matching normals (normalised to unit length)."""
    pts = points_array(points, "points", min_count=min_count)
    nrm = None if normals is None else normals_array(normals, len(pts))
    return pts, nrm


__all__ = [
    "Contacts",
    "atomic_write",
    "as_points_normals",
    "check_output_path",
    "finite_array",
    "read_contacts",
    "read_json",
    "write_contacts",
    "write_json",
    "write_text_atomic",
]
