"""Argument checks shared by every public function (internal).

Each helper converts its input to a float array, checks shape and finiteness and raises
:class:`~hapticsim.errors.InvalidInputError` with a message naming the argument.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.errors import InvalidInputError


def _shape_str(shape: tuple[int, ...]) -> str:
    return "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


def as_float_array(value: Any, name: str) -> NDArray[np.float64]:
    """Convert `value` to a float64 array or raise naming `name`."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"`{name}` must be numeric, got {type(value).__name__}") from exc
    return arr


def finite_array(value: Any, name: str, shape: tuple[int | None, ...]) -> NDArray[np.float64]:
    """A finite float64 array of the given shape (None matches any length).

    Raises:
        InvalidInputError: wrong shape, not numeric, or NaN/inf entries.
    """
    arr = as_float_array(value, name)
    ok = arr.ndim == len(shape) and all(
        s is None or s == d for s, d in zip(shape, arr.shape, strict=False)
    )
    if not ok:
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape)
        want += ",)" if len(shape) == 1 else ")"
        raise InvalidInputError(f"`{name}` must be {want} float, got {_shape_str(arr.shape)}")
    if not np.all(np.isfinite(arr)):
        raise InvalidInputError(f"`{name}` contains NaN or infinite values")
    return arr


def points_array(value: Any, name: str = "points", min_count: int = 0) -> NDArray[np.float64]:
    """An (n, 3) finite float array with at least `min_count` rows."""
    arr = finite_array(value, name, (None, 3))
    if arr.shape[0] < min_count:
        raise InvalidInputError(f"`{name}` must hold at least {min_count} rows, got {arr.shape[0]}")
    return arr


def normals_array(value: Any, count: int, name: str = "normals") -> NDArray[np.float64]:
    """An (count, 3) finite float array of non-zero vectors, returned normalised to unit length."""
    arr = finite_array(value, name, (None, 3))
    if arr.shape[0] != count:
        raise InvalidInputError(
            f"`{name}` must have one row per point ({count}), got {arr.shape[0]}"
        )
    norm = np.linalg.norm(arr, axis=1)
    if np.any(norm < 1e-12):
        bad = int(np.argmax(norm < 1e-12))
        raise InvalidInputError(f"`{name}` row {bad} has zero length")
    return arr / norm[:, None]


def positive_int(value: Any, name: str, minimum: int = 1) -> int:
    """An int >= `minimum` (bools rejected)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InvalidInputError(f"`{name}` must be an integer, got {value!r}")
    if value < minimum:
        raise InvalidInputError(f"`{name}` must be >= {minimum}, got {value}")
    return int(value)


def finite_float(value: Any, name: str, low: float = -np.inf, high: float = np.inf) -> float:
    """A finite float in [low, high]."""
    if isinstance(value, bool):
        raise InvalidInputError(f"`{name}` must be a number, got {value!r}")
    try:
        out = float(value)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"`{name}` must be a number, got {value!r}") from exc
    if not np.isfinite(out) or out < low or out > high:
        raise InvalidInputError(
            f"`{name}` must be a finite number in [{low}, {high}], got {value!r}"
        )
    return out


def as_generator(rng: Any, name: str = "rng") -> np.random.Generator:
    """A ``numpy.random.Generator`` from a Generator (returned as is), a seed >= 0, or None.

    Raises:
        InvalidInputError: anything else (floats, negative seeds, bools, the legacy RandomState).
    """
    if isinstance(rng, np.random.Generator):
        return rng
    if rng is None:
        return np.random.default_rng()
    if isinstance(rng, bool) or not isinstance(rng, (int, np.integer)) or rng < 0:
        raise InvalidInputError(
            f"`{name}` must be a numpy.random.Generator, a non-negative int seed or None, "
            f"got {rng!r}"
        )
    return np.random.default_rng(int(rng))


def positive_fields(obj: Any, names: tuple[str, ...] | list[str], unit: str = "") -> None:
    """Check that each named attribute of `obj` (a config dataclass) is a finite float > 0.

    Raises:
        InvalidInputError: naming the first field that is not, e.g. "`lead` must be > 0, got -1".
    """
    suffix = f" [{unit}]" if unit else ""
    for name in names:
        value = getattr(obj, name)
        if finite_float(value, name) <= 0:
            raise InvalidInputError(f"`{name}` must be > 0{suffix}, got {value!r}")
