"""The supertoroid (a superquadric with a hole): its closed forms against independent
computations, its JSON and its bad input. (The Solid contract: tests/geometry/test_solid.py.)"""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import MeshSolid, Supertoroid, random_rotation, solid_from_dict

RINGS = [
    Supertoroid((0.01, 0.012, 0.015), (0.6, 1.3), 2.5, random_rotation(np.random.default_rng(1)),
                (0.01, 0.0, 0.02)),
    Supertoroid((0.01, 0.01, 0.01), (1.0, 1.0), 2.0),  # a torus
    Supertoroid((0.008, 0.012, 0.01), (0.2, 0.3), 1.5),  # squarish
    Supertoroid((0.012, 0.01, 0.02), (1.8, 0.5), 4.0),
]  # fmt: skip


@pytest.mark.parametrize("ring", RINGS)
def test_the_closed_form_volume_against_a_fine_mesh_and_monte_carlo(ring: Supertoroid) -> None:
    # measured: the 128-longitude mesh within 0.2 %, 4 x 10^6 box samples within 1.5 standard
    # errors (0.1-0.2 %)
    mesh = MeshSolid(*ring.surface_mesh(128))
    assert mesh.volume == pytest.approx(ring.volume, rel=0.01)
    lo, hi = ring.bounds
    pts = np.random.default_rng(0).uniform(lo, hi, (400_000, 3))
    fill = float(np.mean(ring.contains(pts)))
    assert fill * float(np.prod(hi - lo)) == pytest.approx(ring.volume, rel=0.03)


def test_a_torus_is_a_torus() -> None:
    # eps = (1, 1), a1 = a2 = a3 = r, hole h: the torus of tube radius r about a circle of h r
    r, h = 0.01, 2.0
    torus = RINGS[1]
    assert torus.volume == pytest.approx(2 * np.pi**2 * (h * r) * r**2, rel=1e-12)
    theta = np.linspace(0, 2 * np.pi, 50)
    on = np.c_[(h * r + r * np.cos(theta)), np.zeros(50), r * np.sin(theta)]
    np.testing.assert_allclose(torus.inside_outside(on), 1.0, atol=1e-12)
    assert torus.contains(np.zeros((1, 3)))[0] == np.False_  # the hole


@pytest.mark.parametrize("ring", RINGS)
def test_normals_are_the_inside_outside_gradient(ring: Supertoroid) -> None:
    pts, nrm = ring.sample_surface(300, rng=2)
    h = 1e-7
    grad = np.stack([(ring.inside_outside(pts + h * e) - ring.inside_outside(pts - h * e)) / (2 * h)
                     for e in np.eye(3)], axis=1)  # fmt: skip
    grad /= np.linalg.norm(grad, axis=1, keepdims=True)
    assert np.degrees(np.arccos(np.clip(np.sum(grad * nrm, axis=1), -1, 1))).max() < 0.01


def test_a_union_takes_a_ring_part() -> None:
    from hapticsim.geometry import Superquadric, SuperquadricUnion

    union = SuperquadricUnion((Superquadric(a=(0.03, 0.03, 0.04), eps=(0.2, 1.0)), RINGS[1]))
    assert solid_from_dict(json.loads(json.dumps(union.to_dict()))) == union
    assert union.to_dict()["parts"][1]["kind"] == "supertoroid"
    # the ring sits round the cup's waist: their overlap is counted once (box samples within 2 %)
    lo, hi = union.bounds
    pts = np.random.default_rng(3).uniform(lo, hi, (400_000, 3))
    fill = float(np.mean(union.contains(pts)))
    assert fill * float(np.prod(hi - lo)) == pytest.approx(union.volume, rel=0.02)
    assert union.volume < union.parts[0].volume + union.parts[1].volume


def test_json_round_trip_and_the_fine_mesh_stays_home() -> None:
    ring = RINGS[0]
    text = json.dumps(ring.to_dict())
    assert solid_from_dict(json.loads(text)) == ring
    assert json.loads(text)["kind"] == "supertoroid"
    ring.surface_distance(np.zeros((1, 3)))  # builds its fine mesh
    copy = pickle.loads(pickle.dumps(ring))
    assert copy == ring and "_fine_mesh" not in vars(copy)


@pytest.mark.parametrize(
    ("data", "words"),
    [
        ({**RINGS[1].to_dict(), "hole": 0.8}, "at 1 or below the tube reaches the axis"),
        ({**RINGS[1].to_dict(), "hole": 30.0}, "`hole`"),
        ({k: v for k, v in RINGS[1].to_dict().items() if k != "hole"}, "missing required key"),
        ({**RINGS[1].to_dict(), "taper": [0, 0]}, "unknown key"),
        ({**RINGS[1].to_dict(), "kind": "torus"}, "must be one of superquadric, supertoroid"),
        ({"parts": [{**RINGS[1].to_dict(), "hole": 0.9}]}, "part 0 of the union"),
        ({"parts": [{"kind": "blob"}]}, "`kind` must be one of"),
    ],
)
def test_bad_json_names_the_problem(data: dict, words: str) -> None:
    with pytest.raises(InvalidInputError, match=words):
        solid_from_dict(data)


def test_bad_supertoroid_files_end_the_command_with_one_line(tmp_path, capsys) -> None:  # noqa: ANN001
    from hapticsim.cli import main

    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({**RINGS[1].to_dict(), "hole": 0.5}))
    good = tmp_path / "good.json"
    good.write_text(json.dumps(RINGS[1].to_dict()))
    assert main(["score", str(good), str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "hole" in err[0]
