"""Argument checks shared by every public function (internal).

Each helper converts its input to a float array, checks shape and finiteness and raises
:class:`~hapticsim.errors.InvalidInputError` with a message naming the argument.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim.constants import MAX_COORDINATE, MAX_INT, MIN_LENGTH
from hapticsim.errors import InvalidInputError


def _shape_str(shape: tuple[int, ...]) -> str:
    return "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


#: dtype kinds converted to float64: unsigned and signed integers, floats.
_REAL_KINDS = "iuf"


def as_float_array(value: Any, name: str) -> NDArray[np.float64]:
    """Convert `value` to a float64 array or raise naming `name`.

    Integers and floats are converted; booleans, complex numbers (whose imaginary part a plain
    cast would drop), strings, bytes, dates and records are refused. Sequences of Python
    numbers (dtype object) are converted when every element is a real number.
    """
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged nested sequences
        raise InvalidInputError(f"`{name}` must be numeric, got {type(value).__name__}") from exc
    kind = raw.dtype.kind
    if kind in "iu" and isinstance(value, (list, tuple)) and _contains_bool(value):
        kind = "b"  # [1, True] is an int array to NumPy; a JSON `true` is not a number
    if kind == "c":
        raise InvalidInputError(f"`{name}` must be real, got complex values ({raw.dtype})")
    if kind in _REAL_KINDS:
        return raw.astype(np.float64, copy=False)
    if kind == "O":
        try:
            values = [_real_scalar(v, name) for v in raw.ravel()]
            return np.array(values, dtype=np.float64).reshape(raw.shape)
        except (TypeError, ValueError, OverflowError) as exc:
            raise InvalidInputError(
                f"`{name}` must be numeric, got {type(value).__name__} of {raw.dtype}"
            ) from exc
    what = "bool" if kind == "b" else str(raw.dtype)
    raise InvalidInputError(f"`{name}` must be numeric, got {what} values")


def _contains_bool(value: list[Any] | tuple[Any, ...]) -> bool:
    """True when a nested list/tuple holds a bool anywhere."""
    return any(
        isinstance(v, (bool, np.bool_)) or (isinstance(v, (list, tuple)) and _contains_bool(v))
        for v in value
    )


def _real_scalar(value: Any, name: str) -> float:
    """One element of an object array as a float: real numbers only."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.number)):
        raise TypeError(f"`{name}` element {value!r} is not a real number")
    if isinstance(value, (complex, np.complexfloating)):
        raise TypeError(f"`{name}` element {value!r} is complex")
    return float(value)


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


def physical_points(value: Any, name: str = "points", min_count: int = 0) -> NDArray[np.float64]:
    """An (n, 3) finite float array of contact locations [m] within the physical range.

    Coordinates must lie within +-:data:`~hapticsim.constants.MAX_COORDINATE` and the points
    must span at least :data:`~hapticsim.constants.MIN_LENGTH` (the longest side of their
    bounding box; points all at one location are left to the caller's message):
    outside that, squares of coordinates overflow or bounds of the fit underflow, and no
    touched object is that large or that small in metres.

    Raises:
        InvalidInputError: as :func:`points_array`, or coordinates out of range.
    """

    arr = points_array(value, name, min_count)
    if arr.size and float(np.abs(arr).max()) > MAX_COORDINATE:
        raise InvalidInputError(
            f"`{name}` must have coordinates within +-{MAX_COORDINATE:g} m, got "
            f"{float(np.abs(arr).max()):.3g} (metres expected)"
        )
    if len(arr) >= 2:
        extent = float(np.max(arr.max(axis=0) - arr.min(axis=0)))  # no squares: no underflow
        if 0.0 < extent < MIN_LENGTH:
            raise InvalidInputError(
                f"`{name}` must span at least {MIN_LENGTH:g} m, got {extent:.3g} m "
                "(metres expected)"
            )
    return arr


def normals_array(value: Any, count: int, name: str = "normals") -> NDArray[np.float64]:
    """An (count, 3) finite float array of non-zero vectors, returned normalised to unit length."""
    arr = finite_array(value, name, (None, 3))
    if arr.shape[0] != count:
        raise InvalidInputError(
            f"`{name}` must have one row per point ({count}), got {arr.shape[0]}"
        )
    with np.errstate(over="ignore"):  # squares of 1e300 overflow: such rows are redone below
        norm = np.linalg.norm(arr, axis=1)
    huge = ~np.isfinite(norm)
    if np.any(huge):  # scaled by their largest component first (the others stay bit for bit)
        arr = arr.copy()
        arr[huge] /= np.max(np.abs(arr[huge]), axis=1)[:, None]
        norm[huge] = np.linalg.norm(arr[huge], axis=1)
    if np.any(norm < 1e-12):
        bad = int(np.argmax(norm < 1e-12))
        raise InvalidInputError(f"`{name}` row {bad} has zero length")
    return arr / norm[:, None]


def positive_int(value: Any, name: str, minimum: int = 1, maximum: int | None = None) -> int:
    """An int in [`minimum`, `maximum`] (bools rejected).

    `maximum` defaults to :data:`~hapticsim.constants.MAX_INT` (2**62), so that every accepted
    value converts to a NumPy int64 exactly; counts that size arrays pass a tighter one.
    """

    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InvalidInputError(f"`{name}` must be an integer, got {value!r}")
    if value < minimum:
        raise InvalidInputError(f"`{name}` must be >= {minimum}, got {value}")
    top = MAX_INT if maximum is None else maximum
    if value > top:
        raise InvalidInputError(f"`{name}` must be <= {top:,}, got {value:,}")
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


def _one_edit(a: str, b: str) -> bool:
    """Whether `a` becomes `b` by one insertion, deletion, substitution or swap of neighbours."""
    if a == b or abs(len(a) - len(b)) > 1:
        return False
    if len(a) == len(b):
        diff = [i for i, (x, y) in enumerate(zip(a, b, strict=True)) if x != y]
        if len(diff) == 1:
            return True
        i = diff[0]
        return len(diff) == 2 and diff[1] == i + 1 and a[i] == b[i + 1] and a[i + 1] == b[i]
    short, long = (a, b) if len(a) < len(b) else (b, a)
    i = 0
    while i < len(short) and short[i] == long[i]:
        i += 1
    return short[i:] == long[i + 1 :]


def suggestion(name: Any, choices: Any) -> str | None:
    """The choice `name` was probably meant to be: the same but for case, else the one choice
    one edit away (case ignored); None when there is no such single choice."""
    if not isinstance(name, str):
        return None
    options = [str(c) for c in choices]
    folded = name.casefold()
    same = [c for c in options if c.casefold() == folded]
    if len(same) == 1 and same[0] != name:
        return same[0]
    near = [c for c in options if _one_edit(folded, c.casefold())]
    return near[0] if len(near) == 1 else None


def did_you_mean(name: Any, choices: Any) -> str:
    """``" (did you mean 'cube'?)"`` for :func:`suggestion`'s choice, or ``""``: the end of an
    error message on a misspelt name."""
    hit = suggestion(name, choices)
    return "" if hit is None else f" (did you mean {hit!r}?)"
