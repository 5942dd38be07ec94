"""Composite truths: random_composite, synthetic contacts on unions, the pybullet library."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hapticsim.cli import main
from hapticsim.data.objects import (
    COMPOSITE_RADIUS,
    COMPOSITE_SHOWS,
    ObjectSpec,
    random_composite,
)
from hapticsim.data.synthetic import synthetic_dataset
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import MeshSolid, SuperquadricUnion


@pytest.mark.parametrize("seed", range(6))
def test_random_composites_are_hand_held_unions_whose_parts_show(seed: int) -> None:
    union = random_composite(seed)
    assert isinstance(union, SuperquadricUnion) and 2 <= len(union.parts) <= 4
    assert union.bounding_radius <= COMPOSITE_RADIUS
    assert np.allclose(union.center, 0.0, atol=1e-9)
    shows = union._unique_volumes / np.array([p.volume for p in union.parts])
    assert np.all(shows[1:] >= COMPOSITE_SHOWS)
    assert random_composite(seed) == union  # drawn from the seed alone
    assert ObjectSpec("random_composite").resolve(seed) == union


def test_random_composite_bad_part_count() -> None:
    assert len(random_composite(0, parts=2).parts) == 2
    with pytest.raises(InvalidInputError, match="`parts` must be an int in"):
        random_composite(0, parts=5)


def test_synthetic_contacts_of_a_union_lie_on_its_surface() -> None:
    union = random_composite(3)
    c = synthetic_dataset(union, noise=0.0, rng=0, count=300)
    assert len(c) == 300
    assert np.max(union.surface_distance(c.points)) < 5e-4  # the parts' meshes' chords
    hidden = np.zeros(300, dtype=bool)
    for k in range(len(union.parts)):
        others = [p for j, p in enumerate(union.parts) if j != k]
        mine = c.extra["part"] == k
        for o in others:
            hidden[mine] |= o.contains(c.points[mine]) & ~o.outside(c.points[mine])
    assert not np.any(hidden)
    noisy = synthetic_dataset(union, noise=0.05, rng=0, count=300)
    np.testing.assert_array_equal(noisy.extra["points_clean"], c.extra["points_clean"])
    assert np.std(noisy.points - c.points) == pytest.approx(0.05 * union.size, rel=0.15)


def test_synth_cli_draws_a_composite_and_writes_its_union(tmp_path, capsys) -> None:
    out, truth = tmp_path / "c.npz", tmp_path / "t.json"
    args = ["synth", "random_composite", "--seed", "4", "--noise", "0", "--out", str(out),
            "--truth-out", str(truth)]  # fmt: skip
    assert main(args) == 0
    written = json.loads(truth.read_text())
    assert written == random_composite(
        np.random.default_rng(np.random.SeedSequence(4).spawn(1)[0])
    ).to_dict()
    assert json.loads(capsys.readouterr().out)["count"] == 150
    assert main(["synth", str(truth), "--out", str(tmp_path / "d.npz")]) == 0  # a union file
    capsys.readouterr()
    assert main(["synth", "pybullet:duck", "--out", str(tmp_path / "e.npz")]) == 2
    assert "explore it with the hand" in capsys.readouterr().err


def test_library_objects_are_read_from_pybullet_data() -> None:
    pytest.importorskip("pybullet_data")
    from hapticsim.data.library import load_library_object

    duck = ObjectSpec("pybullet:duck").resolve()
    assert isinstance(duck, MeshSolid) and 0.03 < duck.bounding_radius < 0.08
    assert np.allclose(duck.centroid, 0.0, atol=1e-9)
    blob = ObjectSpec("pybullet:random/016")
    assert blob.name == "random-016" and blob.resolve().volume > 0
    assert load_library_object("duck", 2.0).volume == pytest.approx(8 * duck.volume, rel=1e-6)
    for name, words in [
        ("random/1000", "random/000 ... random/999"),
        ("nothing", "unknown pybullet object"),
        ("../../etc/passwd", "unknown pybullet object"),
    ]:
        with pytest.raises(InvalidInputError, match=words):
            load_library_object(name)
    # refused before the repairs (issue 37): the teddy's 15 overlapping hulls fuse into one
    # closed body; the mug's handle is an open tube whose two ends are filled, then fused
    teddy, mug = load_library_object("teddy"), load_library_object("mug")
    assert teddy.repair["fused_bodies"] == 15 and abs(teddy.repair["volume_change"]) < 1e-3
    assert mug.repair["filled_holes"] == 2 and mug.repair["fused_bodies"] == 2
    assert 2e-4 < mug.volume < 2.5e-4  # m^3


def test_library_objects_collide_as_their_own_convex_hulls() -> None:
    pytest.importorskip("pybullet_data")
    duck = ObjectSpec("pybullet:duck").resolve()
    assert duck.pieces is not None and len(duck.pieces) == 5  # its URDF's V-HACD hulls
    pieces, position, _, method = duck.convex_pieces(32)
    assert "5 convex pieces given" in method and np.allclose(position, duck.centroid)
    moved = duck.transformed(np.eye(3), np.array([0.01, 0.0, 0.0])).scaled(2.0)
    assert np.allclose(moved.pieces[0], (duck.pieces[0] + [0.01, 0.0, 0.0]) * 2.0)
    assert moved.shape_key() != duck.shape_key()
    # the hulls stand where the surface is: most of their vertices within 3 mm of it
    hull_vertices = np.concatenate(duck.pieces)
    assert np.median(duck.surface_distance(hull_vertices)) < 3e-3
    with pytest.raises(InvalidInputError, match="`pieces`"):
        MeshSolid(duck.vertices, duck.faces, (np.zeros((2, 3)),))
