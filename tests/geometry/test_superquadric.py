"""The Superquadric value: construction, parameter vector, JSON, pose (SPEC §1, §6)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from hapticsim.errors import HapticsimError
from hapticsim.geometry import N_PARAMS, PARAM_NAMES, Superquadric
from tests.core_helpers import random_rigid, random_superquadric

FAST = settings(max_examples=100, deadline=None, database=None)

vectors = st.builds(
    lambda a, eps, taper, rotvec, center: np.concatenate([a, eps, taper, rotvec, center]),
    arrays(np.float64, 3, elements=st.floats(1e-3, 1.0)),
    arrays(np.float64, 2, elements=st.floats(0.1, 2.0)),
    arrays(np.float64, 2, elements=st.floats(-1.0, 1.0)),
    arrays(np.float64, 3, elements=st.floats(-1.8, 1.8)),  # angle < pi: a unique rotvec
    arrays(np.float64, 3, elements=st.floats(-10.0, 10.0)),
)


@FAST
@given(vector=vectors)
def test_vector_round_trip(vector: np.ndarray) -> None:
    sq = Superquadric.from_vector(vector)
    assert len(PARAM_NAMES) == N_PARAMS == 13
    np.testing.assert_allclose(sq.to_vector(), vector, atol=1e-9)
    assert Superquadric.from_vector(sq.to_vector()).to_vector() == pytest.approx(sq.to_vector())


@FAST
@given(vector=vectors)
def test_json_round_trip_is_exact(vector: np.ndarray) -> None:
    sq = Superquadric.from_vector(vector)
    back = Superquadric.from_json(sq.to_json())
    assert back == sq
    assert Superquadric.from_dict(json.loads(json.dumps(sq.to_dict()))) == sq


def test_json_files_and_fit_results(tmp_path: Path) -> None:
    sq = random_superquadric(np.random.default_rng(0))
    sq.to_json(tmp_path / "sq.json")
    assert Superquadric.from_json(tmp_path / "sq.json") == sq
    fit = {"superquadric": sq.to_dict(), "method": "nH", "eof": 1e-6, "evaluations": 10}
    (tmp_path / "fit.json").write_text(json.dumps(fit))
    assert Superquadric.from_json(tmp_path / "fit.json") == sq
    untapered = {k: v for k, v in sq.to_dict().items() if k != "taper"}
    assert np.all(Superquadric.from_dict(untapered).taper == 0)  # the one optional key
    assert set(sq.to_dict()) == {"a", "eps", "taper", "rotation", "center"}


def test_quaternion_constructor_and_property() -> None:
    q = np.array([np.cos(0.3), 0.0, np.sin(0.3), 0.0])
    sq = Superquadric.from_quaternion((0.01, 0.02, 0.03), (1, 1), q, (1, 2, 3))
    np.testing.assert_allclose(sq.quaternion, q, atol=1e-12)
    np.testing.assert_allclose(
        Superquadric.from_quaternion((1, 1, 1), (1, 1), -2 * q, (0, 0, 0)).quaternion, q
    )


def test_value_semantics() -> None:
    sq = random_superquadric(np.random.default_rng(1))
    assert sq == sq.replace() and hash(sq) == hash(sq.replace())
    assert sq != sq.replace(a=sq.a * 2)
    with pytest.raises(ValueError, match="read-only"):
        sq.a[0] = 1.0
    with pytest.raises(AttributeError):
        sq.a = np.ones(3)  # type: ignore[misc]
    assert "Superquadric(" in repr(sq)


def test_transformed_moves_the_solid() -> None:
    rng = np.random.default_rng(2)
    sq = random_superquadric(rng)
    rot, shift = random_rigid(rng)
    moved = sq.transformed(rot, shift)
    body = rng.uniform(-1, 1, (50, 3)) * sq.a
    np.testing.assert_allclose(moved.to_world(body), sq.to_world(body) @ rot.T + shift, atol=1e-12)
    np.testing.assert_allclose(moved.to_body(moved.to_world(body)), body, atol=1e-12)


def test_contains_project_and_bounding_radius() -> None:
    rng = np.random.default_rng(3)
    for _ in range(20):
        sq = random_superquadric(rng)
        points = sq.center + rng.normal(0, float(np.mean(sq.a)), (200, 3))
        inside = sq.contains(points)
        assert np.array_equal(inside, sq.inside_outside(points) <= 1)
        np.testing.assert_allclose(sq.inside_outside(sq.project(points)), 1.0, atol=1e-9)
        vertices = sq.to_mesh(32).vertices
        assert np.all(
            np.linalg.norm(vertices - sq.center, axis=1) <= sq.bounding_radius * (1 + 1e-12)
        )


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"a": (0.01, -0.02, 0.03)}, "a"),
        ({"a": (0.01, 0.0, 0.03)}, "a"),
        ({"a": (0.01, 0.02)}, "a"),
        ({"a": (0.01, np.nan, 0.03)}, "a"),
        ({"a": "big"}, "a"),
        ({"eps": (0.05, 1.0)}, "eps"),
        ({"eps": (1.0, 2.5)}, "eps"),
        ({"taper": (1.2, 0.0)}, "taper"),
        ({"taper": (0.0, -1.01)}, "taper"),
        ({"rotation": np.diag([1.0, 1.0, 2.0])}, "rotation"),
        ({"rotation": np.diag([1.0, 1.0, -1.0])}, "rotation"),
        ({"rotation": np.eye(2)}, "rotation"),
        ({"center": (0.0, np.inf, 0.0)}, "center"),
    ],
)
def test_bad_parameters_raise_naming_the_argument(kwargs: dict, name: str) -> None:
    args = {"a": (0.01, 0.02, 0.03), "eps": (1.0, 1.0)} | kwargs
    with pytest.raises(HapticsimError, match=f"`{name}`"):
        Superquadric(**args)


_POSE = {"rotation": np.eye(3).tolist(), "center": [0.0, 0.0, 0.0]}


@pytest.mark.parametrize(
    ("data", "match"),
    [
        ([1, 2, 3], "JSON object"),
        ({"a": [1, 1, 1]}, "missing required key.s. eps, rotation, center"),
        ({**_POSE, "a": [1, 1, 1], "eps": [1, 1], "colour": "red"}, "unknown"),
        ({"superquadric": 3}, "JSON object"),
        ({**_POSE, "a": [1, 1, None], "eps": [1, 1]}, "`a`"),
        ({**_POSE, "a": [1, 1, 1j], "eps": [1, 1]}, "`a`"),
        ({**_POSE, "a": [1, 1, True], "eps": [1, 1]}, "`a` must be numeric"),
        ({**_POSE, "a": [1, 1, 1e300], "eps": [1, 1]}, "`a` must lie in"),
        ({**_POSE, "a": [1, 1, 1e-300], "eps": [1, 1]}, "`a` must lie in"),
        ({**_POSE, "a": [1, 1, 1], "eps": [1, 1], "center": [0, 1e300, 0]}, "`center` must lie"),
    ],
)
def test_bad_dicts(data, match: str) -> None:
    with pytest.raises(HapticsimError, match=match):
        Superquadric.from_dict(data)


@pytest.mark.parametrize("key", ["a", "eps", "rotation", "center"])
def test_a_missing_required_key_is_named(key: str) -> None:
    data = Superquadric(a=(0.01, 0.02, 0.03), eps=(1.0, 1.0)).to_dict()
    del data[key]
    with pytest.raises(HapticsimError, match=f"missing required key.s. {key} "):
        Superquadric.from_dict(data)


def test_bad_arguments_of_methods() -> None:
    sq = Superquadric(a=(0.01, 0.02, 0.03), eps=(1.0, 1.0))
    cases = [
        (lambda: Superquadric.from_vector(np.zeros(12)), "vector"),
        (
            lambda: Superquadric.from_quaternion((1, 1, 1), (1, 1), np.zeros(4), (0, 0, 0)),
            "quaternion",
        ),
        (lambda: sq.inside_outside(np.zeros((3, 2))), "points_world"),
        (lambda: sq.to_world(np.zeros(3)), "points_body"),
        (lambda: sq.surface([0.0, 1.0], [0.0]), "eta"),
        (lambda: sq.surface([0.0], [np.nan]), "omega"),
        (lambda: sq.surface([0.0], [0.0], "spherical"), "parametrization"),
        (lambda: sq.transformed(np.eye(3), (0, 0)), "translation"),
        (lambda: sq.to_mesh(4), "resolution"),
    ]
    for call, name in cases:
        with pytest.raises(HapticsimError, match=f"`{name}`"):
            call()


def test_a_superquadric_and_its_surface_meshes_are_freed_together() -> None:
    # The surface meshes sampling and Chamfer build are kept with their superquadric; a table
    # keyed weakly by it whose values held it never let either go (Dask workers grew to 9 GB).
    import gc
    import pickle
    import weakref

    sq = Superquadric(a=[0.03, 0.04, 0.05], eps=[0.5, 0.8])
    sq.sample_surface(10, 0)
    sq.surface_distance(np.zeros((1, 3)))
    copy = pickle.loads(pickle.dumps(sq))  # the meshes do not travel with it
    assert copy == sq and not any(k.startswith("_") for k in vars(copy))
    ref = weakref.ref(sq)
    del sq
    gc.collect()
    assert ref() is None


@pytest.mark.parametrize("seed", range(4))
def test_compiled_segment_depths_are_the_generic_ones(seed: int) -> None:
    """The taxel depth model's compiled pass on a superquadric (its inside test and ray cast in
    one kernel) gives the generic answer of ``contains`` and ``first_hits``: points within a
    few millimetres of a random tapered body, normals tilted up to about 20 degrees."""
    from hapticsim.data.objects import random_superquadric as drawn
    from hapticsim.geometry.solid import Solid
    from hapticsim.perception.tactile.depth import TAXEL_GRIDS

    rng = np.random.default_rng(seed)
    sq = drawn(rng, tapered=True)
    points, normals = sq.sample_surface(400, rng)
    points = points + normals * rng.uniform(-0.002, 0.0005, (400, 1))
    tilted = normals + rng.normal(0.0, 0.2, (400, 3))
    tilted /= np.linalg.norm(tilted, axis=1, keepdims=True)
    fast = sq.segment_depths(points, tilted, 0.008, TAXEL_GRIDS)
    generic = Solid.segment_depths(sq, points, tilted, 0.008, TAXEL_GRIDS)
    assert np.count_nonzero(fast) > 200
    np.testing.assert_allclose(fast, generic, rtol=0, atol=1e-12)
