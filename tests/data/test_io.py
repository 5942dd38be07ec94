"""Contact files and JSON (SPEC §6)."""

from __future__ import annotations

import gc
import warnings
from pathlib import Path

import numpy as np
import pytest

from hapticsim.data.io import (
    Contacts,
    check_output_path,
    read_contacts,
    read_json,
    write_contacts,
    write_json,
)
from hapticsim.errors import HapticsimError


def _contacts(count: int = 5, normals: bool = True) -> Contacts:
    rng = np.random.default_rng(0)
    n = rng.normal(size=(count, 3)) if normals else None
    extra = {"finger": np.arange(count), "points_clean": rng.normal(size=(count, 3))}
    return Contacts(points=rng.normal(size=(count, 3)), normals=n, extra=extra)


def test_npz_round_trip_keeps_every_array(tmp_path: Path) -> None:
    c = _contacts()
    write_contacts(tmp_path / "c.npz", c)
    back = read_contacts(tmp_path / "c.npz")
    assert np.array_equal(back.points, c.points)
    # Normals are normalised again on reading: equal to the last bit or two.
    np.testing.assert_allclose(back.normals, c.normals, rtol=1e-15, atol=1e-16)
    assert set(back.extra) == {"finger", "points_clean"}
    assert np.array_equal(back.extra["finger"], c.extra["finger"])
    assert not list(tmp_path.glob(".*tmp"))  # no temporary file left behind


@pytest.mark.parametrize("normals", [True, False])
def test_csv_round_trip_is_exact(tmp_path: Path, normals: bool) -> None:
    c = _contacts(normals=normals)
    write_contacts(tmp_path / "c.csv", c)
    back = read_contacts(tmp_path / "c.csv")
    assert np.array_equal(back.points, c.points)
    assert (back.normals is None) == (not normals)
    if normals:
        np.testing.assert_allclose(back.normals, c.normals, rtol=1e-15)


def test_json_round_trip(tmp_path: Path) -> None:
    data = {"a": [1.0, 2.0], "b": {"c": "d"}}
    write_json(tmp_path / "x.json", data)
    assert read_json(tmp_path / "x.json") == data
    assert read_json('{"a": 1}') == {"a": 1}


def _write(path: Path, content: bytes | str) -> Path:
    if isinstance(content, str):
        path.write_text(content)
    else:
        path.write_bytes(content)
    return path


@pytest.mark.parametrize(
    ("name", "content", "match"),
    [
        ("missing.npz", None, "not found"),
        ("empty.npz", b"", "empty"),
        ("bad.npz", b"not a zip", "cannot read"),
        ("c.txt", "x,y,z\n1,2,3\n", "must end in"),
        ("header.csv", "a,b,c\n1,2,3\n", "header"),
        ("nodata.csv", "x,y,z\n", "no contacts"),
        ("nan.csv", "x,y,z\n1,nan,3\n", "NaN"),
        ("text.csv", "x,y,z\n1,two,3\n", "non-numeric"),
        ("ragged.csv", "x,y,z\n1,2\n", "3 values"),
        ("zero.csv", "x,y,z,nx,ny,nz\n1,2,3,0,0,0\n", "zero length"),
        ("binary.csv", b"\xff\xfe\x00x", "UTF-8"),
    ],
)
def test_bad_contact_files_raise_one_clear_error(
    tmp_path: Path, name: str, content: bytes | str | None, match: str
) -> None:
    path = tmp_path / name
    if content is not None:
        _write(path, content)
    with pytest.raises(HapticsimError, match=match):
        read_contacts(path)


@pytest.mark.parametrize(
    ("points", "match"),
    [
        (np.ones((4, 3)) + 1j, "must be real, got complex"),  # issue 14: was cast silently
        (np.ones((4, 3), dtype=bool), "must be numeric, got bool"),
        (np.full((4, 3), "1.0"), "must be numeric, got <U3"),
        (np.zeros((4, 3), dtype="datetime64[s]"), "must be numeric"),
    ],
)
def test_npz_arrays_of_the_wrong_dtype_are_refused(
    tmp_path: Path, points: np.ndarray, match: str
) -> None:
    np.savez(tmp_path / "c.npz", points=points)
    with pytest.raises(HapticsimError, match=match):
        read_contacts(tmp_path / "c.npz")
    np.savez(tmp_path / "n.npz", points=np.eye(4)[:, :3], normals=points)
    with pytest.raises(HapticsimError, match=match.replace("`points`", "`normals`")):
        read_contacts(tmp_path / "n.npz")


def test_a_corrupt_npz_leaves_no_file_handle_open(tmp_path: Path) -> None:
    # found by tests/fuzz: np.load kept its handle on a non-zip file (a ResourceWarning)
    (tmp_path / "c.npz").write_bytes(b"PK\x03\x04 not really a zip")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(HapticsimError, match="cannot read"):
            read_contacts(tmp_path / "c.npz")
        gc.collect()  # an unclosed file warns when it is collected


def test_npz_content_errors(tmp_path: Path) -> None:
    np.savez(tmp_path / "nopoints.npz", normals=np.eye(3))
    with pytest.raises(HapticsimError, match="no `points`"):
        read_contacts(tmp_path / "nopoints.npz")
    np.savez(tmp_path / "shape.npz", points=np.zeros((4, 2)))
    with pytest.raises(HapticsimError, match=r"`points` must be \(n, 3\) float, got \(4, 2\)"):
        read_contacts(tmp_path / "shape.npz")
    np.savez(tmp_path / "mismatch.npz", points=np.zeros((4, 3)), normals=np.eye(3))
    with pytest.raises(HapticsimError, match="one row per point"):
        read_contacts(tmp_path / "mismatch.npz")


@pytest.mark.parametrize(
    ("content", "match"),
    [("", "empty"), ("{", "not valid JSON"), (b"\xff\xfe", "UTF-8")],
)
def test_bad_json_files(tmp_path: Path, content: str | bytes, match: str) -> None:
    path = _write(tmp_path / "x.json", content)
    with pytest.raises(HapticsimError, match=match):
        read_json(path)


def test_writes_fail_cleanly(tmp_path: Path) -> None:
    with pytest.raises(HapticsimError, match="does not exist"):
        write_json(tmp_path / "no" / "x.json", {})
    with pytest.raises(HapticsimError, match="is a directory"):
        write_json(tmp_path, {})
    with pytest.raises(HapticsimError, match="must end in"):
        write_contacts(tmp_path / "c.txt", _contacts())
    with pytest.raises(HapticsimError, match="must end in"):
        check_output_path(tmp_path / "c.txt", (".npz", ".csv"))
    assert check_output_path(tmp_path / "c.npz", (".npz",)) == tmp_path / "c.npz"
    assert list(tmp_path.iterdir()) == []


def test_contacts_validate_their_arrays() -> None:
    with pytest.raises(HapticsimError, match="`points`"):
        Contacts(points=np.zeros((3, 4)))
    with pytest.raises(HapticsimError, match="`finger`"):
        Contacts(points=np.zeros((3, 3)), extra={"finger": np.arange(2)})
    c = Contacts(points=np.zeros((3, 3)), normals=2 * np.eye(3))
    np.testing.assert_allclose(np.linalg.norm(c.normals, axis=1), 1.0)


def test_written_files_get_the_permissions_open_would_give(tmp_path: Path) -> None:
    import os
    import stat

    from hapticsim._files import write_json

    mask = os.umask(0o022)
    os.umask(mask)
    write_json(tmp_path / "new.json", {"a": 1})  # mkstemp's 0600 would hide it from others
    assert stat.S_IMODE((tmp_path / "new.json").stat().st_mode) == 0o666 & ~mask
    (tmp_path / "old.json").write_text("{}")
    (tmp_path / "old.json").chmod(0o640)
    write_json(tmp_path / "old.json", {"a": 2})  # an existing file keeps its mode
    assert stat.S_IMODE((tmp_path / "old.json").stat().st_mode) == 0o640


def test_huge_normals_are_normalised_without_overflow(tmp_path: Path) -> None:
    # found by the fuzz test in a full run: |n|^2 of 1e300 overflowed with a RuntimeWarning
    rng = np.random.default_rng(0)
    points = rng.normal(0.0, 0.03, (13, 3))
    normals = rng.normal(size=(13, 3))
    unit = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    normals[3] *= 1e300
    np.savez(tmp_path / "c.npz", points=points, normals=normals)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        contacts = read_contacts(tmp_path / "c.npz")
    np.testing.assert_allclose(contacts.normals, unit, atol=1e-15)
