"""Property-based fuzzing of the readers (issue 14 item 2): contacts files, JSON, superquadric
files and dicts, body names, and the arrays `fit` accepts.

The property: a reader returns a valid value or raises a :class:`HapticsimError` (whose message
is one line once the CLI joins it); never another exception, and no warning (a ResourceWarning
is a leaked file handle, a RuntimeWarning an overflow nobody checked).
"""

from __future__ import annotations

import tempfile
import warnings
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hapticsim._files import read_json
from hapticsim.data.bodies import resolve_body
from hapticsim.data.io import Contacts, read_contacts
from hapticsim.errors import HapticsimError
from hapticsim.fitting import FIT_METHODS, fit
from hapticsim.geometry import Superquadric
from tests.fuzz.inputs import (
    contact_arrays,
    contacts_files,
    json_files,
    materialise,
    superquadric_dicts,
)

_SETTINGS = dict(
    deadline=None, database=None, derandomize=True, suppress_health_check=list(HealthCheck)
)


def _keeps_the_contract(call, *args) -> object | None:
    """`call(*args)`: its value, or None after a HapticsimError; anything else fails."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            value = call(*args)
        except HapticsimError as exc:
            assert str(exc).strip(), "empty error message"
            value = None
    assert not caught, [f"{w.category.__name__}: {w.message}" for w in caught]
    return value


@settings(max_examples=150, **_SETTINGS)
@given(spec=contacts_files())
def test_contacts_reader(spec) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        contacts = _keeps_the_contract(read_contacts, materialise(spec, Path(tmp)))
    if contacts is not None:
        assert isinstance(contacts, Contacts)
        assert contacts.points.dtype == np.float64 and contacts.points.shape[1] == 3
        assert np.all(np.isfinite(contacts.points))
        if contacts.normals is not None:
            np.testing.assert_allclose(np.linalg.norm(contacts.normals, axis=1), 1.0)


@settings(max_examples=150, **_SETTINGS)
@given(spec=json_files())
def test_superquadric_and_json_readers(spec) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = materialise(spec, Path(tmp))
        _keeps_the_contract(read_json, path)
        sq = _keeps_the_contract(Superquadric.from_json, path)
        body = _keeps_the_contract(resolve_body, path)
    assert sq is None or isinstance(sq, Superquadric)
    assert (sq is None) == (body is None)


@settings(max_examples=150, **_SETTINGS)
@given(data=superquadric_dicts())
def test_superquadric_dicts(data) -> None:
    sq = _keeps_the_contract(Superquadric.from_dict, data)
    if sq is not None:  # what was accepted round-trips exactly
        assert Superquadric.from_dict(sq.to_dict()) == sq


@settings(max_examples=40, **_SETTINGS)
@given(arrays=contact_arrays(), method=st.sampled_from(FIT_METHODS), seed=st.integers(0, 9))
def test_fit_on_fuzzed_arrays(arrays, method: str, seed: int) -> None:
    points, normals = arrays.get("points"), arrays.get("normals")
    result = _keeps_the_contract(lambda: fit(points, normals, method=method, budget=300, rng=seed))
    if result is not None:  # multi's budget is its one-part fit's; its parts spend more
        assert np.isfinite(result.eof)
        multi = method in ("multi", "multi+track")
        assert result.evaluations <= 300 or (multi and result.selection.parts > 0)
