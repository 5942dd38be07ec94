"""Hypothesis strategies for the files and argument values a new user might hand ``hapticsim``.

Files are described by a :class:`FileSpec` (what to write under a name) and materialised in a
work directory by :func:`materialise`. Contacts (``.npz``/``.csv``) and superquadric JSON start
from a valid file and are mutated: wrong dtypes and shapes, NaN/inf, huge and tiny magnitudes,
duplicated or collinear points, missing or extra keys, empty, truncated or bit-flipped bytes,
non-UTF-8 text; a "file" may also be a directory or missing altogether.
"""

from __future__ import annotations

import io
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from hypothesis import strategies as st

from hapticsim.data.bodies import BODIES

#: Magnitudes [m] that scale valid contacts: tiny, sub-physical, ordinary, huge, overflowing.
SCALES = (0.0, 1e-320, 1e-300, 1e-150, 1e-12, 1e-9, 1e-6, 1e-3, 1.0, 1e3, 1e6, 1e7, 1e40, 1e300)
#: dtypes an array in an npz may come with.
DTYPES = ("float64", "float32", "float16", "int64", "uint8", "bool", "complex128", "U8", "S4",
          "object", "datetime64[s]")  # fmt: skip
#: Option-like junk (never a prefix of --help, which prints text, not JSON, by design).
JUNK_TOKENS = (
    "", " ", "-", "--", "-1", "0", "1e309", "nan", "inf", "-inf", "1.5", "0x10", "½", "日本",
    "\x7f", "null", "[]", "{}", "--bogus", "-x", "--out=", "a,b",
)  # fmt: skip


#: A directory every work directory has (:func:`tests.fuzz.runner.run_case` creates it).
EXISTING = "sub"


@dataclass(frozen=True)
class FileSpec:
    """What to put at a relative path: ``bytes`` content, a ``"dir"`` or nothing (missing)."""

    name: str
    content: bytes | None = None
    directory: bool = False


def materialise(spec: FileSpec, root: Path) -> Path:
    """Create `spec` under `root`; returns its path (which may not exist: a missing file)."""
    path = root / spec.name
    path.parent.mkdir(parents=True, exist_ok=True)
    if spec.directory:
        path.mkdir(exist_ok=True)
    elif spec.content is not None:
        path.write_bytes(spec.content)
    return path


def mostly(valid: st.SearchStrategy[Any], bad: st.SearchStrategy[Any], tenths: int = 8) -> Any:
    """`valid` in `tenths` of ten draws, `bad` otherwise (hypothesis's one_of is uniform)."""
    return st.integers(0, 9).flatmap(lambda k: valid if k < tenths else bad)


# ----------------------------------------------------------------------------- byte mutations
@st.composite
def mutated_bytes(draw: st.DrawFn, data: bytes) -> bytes:
    """`data` as is (most often), empty, truncated, bit-flipped, or with junk spliced in."""
    how = draw(mostly(st.just("same"), st.sampled_from(["empty", "truncate", "flip", "splice"])))
    if how == "same" or not data:
        return data
    if how == "empty":
        return b""
    if how == "truncate":
        return data[: draw(st.integers(0, len(data) - 1))]
    at = draw(st.integers(0, len(data) - 1))
    if how == "flip":
        return data[:at] + bytes([data[at] ^ (1 << draw(st.integers(0, 7)))]) + data[at + 1 :]
    junk = draw(st.sampled_from([b"\xff\xfe", b"\x00", b"\xc3\x28", b"NaN", b"\n,,\n", b"}"]))
    return data[:at] + junk + data[at:]


# ----------------------------------------------------------------------------- contacts
def _valid_contacts(seed: int, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Noisy contacts of one of the paper's bodies (surface points and outward normals)."""
    rng = np.random.default_rng(seed)
    body = list(BODIES.values())[seed % len(BODIES)]
    eta = rng.uniform(-1.4, 1.4, count)
    omega = rng.uniform(-np.pi, np.pi, count)
    points, normals = body.surface(eta, omega)
    return points + rng.normal(0.0, 1e-3, points.shape), normals


def _cast(arr: np.ndarray, dtype: str) -> np.ndarray:
    if dtype == "object":
        return arr.astype(object)
    if dtype.startswith("datetime"):
        return arr.astype(np.int64).astype(dtype)
    if dtype in ("U8", "S4"):
        return arr.astype(dtype)
    with np.errstate(all="ignore"):
        return arr.astype(dtype)


@st.composite
def contact_arrays(draw: st.DrawFn) -> dict[str, np.ndarray]:
    """Arrays of a contacts file: valid ones, then some of the mutations of the module doc."""
    count = draw(mostly(st.sampled_from([13, 40, 150]), st.sampled_from([0, 1, 2, 3, 12, 14])))
    points, normals = _valid_contacts(draw(st.integers(0, 2**16)), count)
    arrays: dict[str, np.ndarray] = {"points": points, "normals": normals}
    for _ in range(draw(mostly(st.just(0), st.integers(1, 3), tenths=5))):
        what = draw(
            st.sampled_from(
                ["scale", "offset", "nan", "inf", "duplicate", "collinear", "planar", "dtype",
                 "shape", "drop", "extra", "zero_normal", "count", "negative_zero", "free_space"]
            )
        )  # fmt: skip
        key = draw(st.sampled_from(["points", "normals"]))
        if key not in arrays and what not in ("extra", "free_space"):
            continue
        try:  # a mutation that does not apply to an earlier one's result is skipped
            arr = arrays.get(key)
            if what == "scale":
                arrays[key] = arr * draw(st.sampled_from(SCALES))
            elif what == "offset":
                arrays[key] = arr + draw(st.sampled_from([1e3, 1e6, 1e9, -1e300]))
            elif what in ("nan", "inf") and arr.size and arr.dtype.kind == "f":
                flat = arr.astype(np.float64).ravel().copy()
                flat[draw(st.integers(0, flat.size - 1))] = np.nan if what == "nan" else -np.inf
                arrays[key] = flat.reshape(arr.shape)
            elif what == "duplicate" and len(arr):
                arrays[key] = np.repeat(arr[:1], len(arr), axis=0)
            elif what == "collinear" and arr.ndim == 2 and arr.shape[1] == 3:
                arrays[key] = np.outer(np.linspace(0.0, 0.1, len(arr)), [1.0, 2.0, 3.0])
            elif what == "planar" and arr.ndim == 2 and arr.shape[1] == 3:
                flat = arr.astype(np.float64).copy()
                flat[:, 2] = 0.0
                arrays[key] = flat
            elif what == "dtype":
                arrays[key] = _cast(arr, draw(st.sampled_from(DTYPES)))
            elif what == "shape":
                shape = draw(st.sampled_from([(-1,), (-1, 2), (-1, 4), (-1, 3, 1), (3, -1), ()]))
                flat = arr.ravel()
                if shape == ():
                    arrays[key] = np.asarray(flat[0] if flat.size else 0.0)
                elif shape[0] == 3:
                    arrays[key] = arr.T.copy() if arr.ndim == 2 else arr
                elif flat.size % int(np.prod([s for s in shape if s > 0])) == 0:
                    arrays[key] = flat.reshape(shape)
            elif what == "drop":
                del arrays[key]
            elif what == "extra":
                name = draw(st.sampled_from(["finger", "force", "x", "normals_clean", "pattern"]))
                size = draw(st.sampled_from([count, count + 1, 0]))
                arrays[name] = np.arange(size)
            elif what == "free_space":  # nML's free-space points: any number of (3,) rows
                free = points[: draw(st.integers(0, len(points)))]
                free = free * draw(st.sampled_from([1.2, 0.0]))
                shape = draw(st.sampled_from(["ok", "ok", "2d", "nan", "flat"]))
                if shape == "2d":
                    free = free[:, :2]
                elif shape == "nan" and free.size:
                    free = free.copy()
                    free[0, 0] = np.nan
                elif shape == "flat":
                    free = free.ravel()
                arrays["free_space"] = free
            elif what == "zero_normal" and key == "normals" and arr.size:
                flat = np.array(arr, dtype=np.float64, copy=True)
                flat.reshape(-1)[:3] = 0.0
                arrays[key] = flat
            elif what == "count" and arr.ndim >= 1 and len(arr) > 1:
                arrays[key] = arr[: draw(st.integers(0, len(arr) - 1))]
            elif what == "negative_zero":
                arrays[key] = -np.zeros_like(arr)
        except (TypeError, ValueError):
            pass
    return arrays


def npz_bytes(arrays: dict[str, np.ndarray]) -> bytes:
    """The bytes of an ``.npz`` with these arrays (object arrays pickled, as NumPy does)."""
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def csv_bytes(arrays: dict[str, np.ndarray], header: str | None = None) -> bytes:
    """The bytes of a contacts ``.csv`` (SPEC §6 layout when the arrays allow it)."""
    pts = np.atleast_2d(np.asarray(arrays.get("points", np.zeros((0, 3))), dtype=object))
    nrm = arrays.get("normals")
    cols = [pts] + ([np.atleast_2d(np.asarray(nrm, dtype=object))] if nrm is not None else [])
    if header is None:
        header = "x,y,z" + (",nx,ny,nz" if nrm is not None else "")
    rows = []
    for k in range(max(len(c) for c in cols)):
        cells = []
        for c in cols:
            cells.extend(str(v) for v in (c[k] if k < len(c) else []))
        rows.append(",".join(cells))
    return (header + "\n" + "\n".join(rows) + "\n").encode("utf-8", errors="replace")


@st.composite
def contacts_files(draw: st.DrawFn, stem: str = "contacts") -> FileSpec:
    """A contacts file (``.npz``, ``.csv``, another suffix), a directory, or nothing."""
    kind = draw(
        mostly(
            st.sampled_from(["npz", "npz", "csv"]),
            st.sampled_from(["txt", "dir", "missing", "json"]),
        )
    )
    if kind == "dir":
        return FileSpec(f"{stem}.npz", directory=True)
    if kind == "missing":
        return FileSpec(f"{stem}.npz")
    arrays = draw(contact_arrays())
    if kind in ("npz", "txt"):
        try:
            data = npz_bytes(arrays)
        except (ValueError, TypeError):
            data = b"PK\x03\x04"
    elif kind == "json":
        data = json.dumps({"points": [[0.0, 0.0, 0.0]]}).encode()
    else:
        header = draw(st.sampled_from([None, None, "x,y,z", "a,b,c", "X, Y, Z,NX,NY,NZ", ""]))
        data = csv_bytes(arrays, header)
    return FileSpec(f"{stem}.{kind if kind != 'dir' else 'npz'}", draw(mutated_bytes(data)))


# ----------------------------------------------------------------------------- JSON values
json_scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(2**70), 2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e-320, 1e-300, 1e300, 0.1, 2.0, 2.0000001]),
    st.text(max_size=8),
)
json_values = st.recursive(
    json_scalars,
    lambda children: st.one_of(
        st.lists(children, max_size=5), st.dictionaries(st.text(max_size=6), children, max_size=4)
    ),
    max_leaves=12,
)


@st.composite
def superquadric_dicts(draw: st.DrawFn) -> Any:
    """A superquadric (or fit-result) dict, valid or with some entries removed or replaced."""
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    from hapticsim.geometry import random_rotation

    data: dict[str, Any] = {
        "a": rng.uniform(0.005, 0.08, 3).tolist(),
        "eps": rng.uniform(0.1, 2.0, 2).tolist(),
        "taper": rng.uniform(-0.5, 0.5, 2).tolist(),
        "rotation": random_rotation(rng).tolist(),
        "center": rng.normal(0.0, 0.05, 3).tolist(),
    }
    for _ in range(draw(mostly(st.just(0), st.integers(1, 3), tenths=5))):
        what = draw(st.sampled_from(["drop", "replace", "add", "scale", "element", "nest"]))
        key = draw(st.sampled_from(sorted(data) or ["a"]))
        if what == "drop" and key in data:
            del data[key]
        elif what == "replace":
            data[key] = draw(json_values)
        elif what == "add":
            data[draw(st.sampled_from(["colour", "superquadric", "A", ""]))] = draw(json_values)
        elif what == "scale" and isinstance(data.get(key), list):
            factor = draw(st.sampled_from([0.0, -1.0, 1e-300, 1e-10, 10.0, 1e10, 1e300]))
            try:
                data[key] = (np.asarray(data[key], dtype=float) * factor).tolist()
            except (TypeError, ValueError):
                pass  # a list an earlier mutation made non-numeric
        elif what == "element" and isinstance(data.get(key), list) and data[key]:
            values = list(data[key])
            values[draw(st.integers(0, len(values) - 1))] = draw(json_scalars)
            data[key] = values
        elif what == "nest":
            data = {"superquadric": data, "method": "nH", "eof": 0.0}
    if draw(st.integers(0, 9)) == 0:
        return draw(json_values)  # not an object at all, most likely
    return data


@st.composite
def json_files(draw: st.DrawFn, stem: str = "shape") -> FileSpec:
    """A superquadric JSON file (mutated), a directory, or nothing."""
    kind = draw(mostly(st.just("json"), st.sampled_from(["dir", "missing", "txt"])))
    if kind == "dir":
        return FileSpec(f"{stem}.json", directory=True)
    if kind == "missing":
        return FileSpec(f"{stem}.json")
    text = json.dumps(draw(superquadric_dicts()), allow_nan=True)
    return FileSpec(f"{stem}.{kind}", draw(mutated_bytes(text.encode())))


# ----------------------------------------------------------------------------- arguments
def ints(valid: tuple[int, int], huge: bool = True) -> st.SearchStrategy[str]:
    """An integer option's value: mostly in `valid`, sometimes out of range or not an int."""
    edge = [str(valid[0] - 1), "-1", "0", "1.5", "1e3", "ten", ""]
    if huge:  # past every limit (counts 10^6, budgets 10^9, any integer 2**62)
        edge += [str(2**70), str(2**62 + 1), "1000001", "1000000001"]
    return mostly(st.integers(*valid).map(str), st.sampled_from(edge))


def floats(valid: tuple[float, float]) -> st.SearchStrategy[str]:
    """A float option's value: mostly in `valid`, sometimes NaN, inf, negative or text."""
    return mostly(
        st.floats(*valid).map(repr),
        st.sampled_from(["nan", "inf", "-inf", "-0.1", "1e309", "1e-320", "x", "", "0x1p-2"]),
    )


def choice(valid: tuple[str, ...], wrong: tuple[str, ...] = ()) -> st.SearchStrategy[str]:
    """A choice option's value: one of `valid` mostly, else a near miss or junk."""
    near = tuple(v.lower() for v in valid) + tuple(v.upper() for v in valid) + wrong
    return mostly(st.sampled_from(valid), st.sampled_from(near))


def out_paths(stem: str, suffix: str) -> st.SearchStrategy[str]:
    """An output path: fine, in a missing directory, an existing directory, odd suffixes."""
    return mostly(
        st.sampled_from([f"{stem}{suffix}", f"{EXISTING}/{stem}{suffix}"]),
        st.sampled_from(
            [f"missing/{stem}{suffix}", ".", EXISTING, f"{stem}.txt", f"{stem}", f"{stem}{suffix}/",
             f"/nonexistent-h14/{stem}{suffix}", f"{stem} {suffix}", ""]
        ),
    )  # fmt: skip


__all__ = [
    "EXISTING",
    "FileSpec",
    "JUNK_TOKENS",
    "choice",
    "contact_arrays",
    "contacts_files",
    "csv_bytes",
    "floats",
    "ints",
    "json_files",
    "json_values",
    "materialise",
    "mostly",
    "mutated_bytes",
    "npz_bytes",
    "out_paths",
    "superquadric_dicts",
]
