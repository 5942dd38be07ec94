"""Object specs: names, superquadric files, random shapes and mesh files, and their errors."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from hapticsim.data.bodies import get_body
from hapticsim.data.example_meshes import EXAMPLE_MESHES, example_mesh, l_block
from hapticsim.data.objects import (
    OBJECT_KINDS,
    ObjectSpec,
    Pose,
    load_mesh,
    random_superquadric,
    resolve_object,
    write_stl,
)
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric, quaternion_to_matrix
from hapticsim.geometry.mesh_solid import MeshSolid


def test_kinds_are_recognised(tmp_path: Path) -> None:
    get_body("cube").to_json(tmp_path / "cube.json")
    write_stl(tmp_path / "part.stl", l_block())
    kinds = {
        "cube": "body", "random": "random", "random_tapered": "random_tapered",
        str(tmp_path / "cube.json"): "superquadric", str(tmp_path / "part.stl"): "mesh",
        "random_composite": "random_composite", "pybullet:duck": "pybullet",
        "random_holed": "random_holed", "random_handled": "random_handled",
    }  # fmt: skip
    for source, kind in kinds.items():
        assert ObjectSpec(source).kind == kind
    assert set(kinds.values()) == set(OBJECT_KINDS)
    assert ObjectSpec(str(tmp_path / "part.stl")).name == "part"


def test_body_and_json_resolve_to_the_same_superquadric(tmp_path: Path) -> None:
    cube = get_body("cube")
    cube.to_json(tmp_path / "c.json")
    assert ObjectSpec("cube").resolve() == cube
    assert ObjectSpec(str(tmp_path / "c.json")).resolve() == cube


def test_random_objects_come_from_the_seed() -> None:
    a = ObjectSpec("random_tapered").resolve(3)
    b = ObjectSpec("random_tapered").resolve(3)
    assert a == b and a != ObjectSpec("random_tapered").resolve(4)
    assert np.any(a.taper != 0) and np.all(ObjectSpec("random").resolve(3).taper == 0)
    # the same draws as the environment's distribution (a, then eps, then taper)
    gen = np.random.default_rng(3)
    assert np.allclose(a.a, gen.uniform(0.02, 0.05, 3)) and np.allclose(
        a.eps, gen.uniform(0.1, 1.0, 2)
    )
    assert random_superquadric(3, tapered=True) == a


def test_scale_and_pose_place_a_superquadric() -> None:
    rot = quaternion_to_matrix(np.array([np.cos(0.3), 0.0, 0.0, np.sin(0.3)]))
    spec = ObjectSpec("cube", scale=2.0, pose=Pose(np.array([0.01, 0.0, 0.02]), rot))
    shape = spec.resolve()
    assert isinstance(shape, Superquadric)
    assert np.allclose(shape.a, 0.06) and np.allclose(shape.center, [0.01, 0.0, 0.02])
    assert np.allclose(shape.rotation, rot)


def test_mesh_is_centred_at_its_centroid_unless_posed(tmp_path: Path) -> None:
    offset = l_block().transformed(np.eye(3), np.array([0.5, 0.2, -0.1]))
    path = write_stl(tmp_path / "l.stl", offset)
    centred = ObjectSpec(str(path)).resolve()
    assert isinstance(centred, MeshSolid)
    assert np.allclose(centred.centroid, 0.0, atol=1e-7)
    assert centred.volume == pytest.approx(1e-4, rel=1e-5)
    posed = ObjectSpec(str(path), pose=Pose.parse("0,0,0.05")).resolve()
    assert np.allclose(posed.centroid, [0.5, 0.2, -0.05], atol=1e-6)  # file coordinates kept
    mm = write_stl(tmp_path / "mm.stl", l_block().scaled(1000.0))
    assert ObjectSpec(str(mm), scale=1e-3).resolve().volume == pytest.approx(1e-4, rel=1e-5)


@pytest.mark.parametrize("suffix", [".obj", ".ply", ".off", ".stl"])
def test_every_mesh_format_reads(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"prism{suffix}"
    example_mesh("hexagonal_prism").to_trimesh().export(path)
    solid = load_mesh(path)
    assert solid.volume == pytest.approx(example_mesh("hexagonal_prism").volume, rel=1e-6)


def test_inverted_mesh_is_turned_outward(tmp_path: Path) -> None:
    mesh = trimesh.creation.box((0.03, 0.03, 0.03))
    mesh.invert()
    mesh.export(tmp_path / "inv.ply")
    # PLY stores float32 vertices: relative volume error ~1e-7
    assert load_mesh(tmp_path / "inv.ply").volume == pytest.approx(0.03**3, rel=1e-6)


def test_bad_mesh_files_name_the_problem(tmp_path: Path) -> None:
    (tmp_path / "empty.stl").write_bytes(b"")
    (tmp_path / "junk.obj").write_text("this is not a mesh\n")
    open_box = trimesh.creation.box((0.03, 0.03, 0.03))
    trimesh.Trimesh(open_box.vertices, open_box.faces[:-2]).export(tmp_path / "open.stl")
    two = trimesh.util.concatenate(
        [trimesh.creation.box((0.02, 0.02, 0.02)),
         trimesh.creation.box((0.02, 0.02, 0.02)).apply_translation((0.05, 0, 0))]
    )  # fmt: skip
    two.export(tmp_path / "two.stl")
    (tmp_path / "part.step").write_text("x")
    cases = {
        "empty.stl": "empty|cannot read",
        "junk.obj": "empty|cannot read",
        "open.stl": "not a closed surface: 1 holes, the largest 30 mm across",
        "two.stl": "2 bodies in 2 pieces, the nearest 30 mm apart",
        "part.step": "unknown object file format '.step'",
        "missing.stl": "not found",
    }
    for name, message in cases.items():
        with pytest.raises(InvalidInputError, match=message):
            ObjectSpec(str(tmp_path / name)).resolve()


@pytest.mark.parametrize(
    ("source", "message"),
    [("sphere", "unknown object 'sphere'"), ("", "non-empty"), ("x.json", "not found")],
)
def test_bad_specs_name_the_problem(source: str, message: str) -> None:
    with pytest.raises(InvalidInputError, match=message):
        ObjectSpec(source)


def test_pose_parsing() -> None:
    assert np.allclose(Pose.parse("0.1, 0, 0.2").position, [0.1, 0.0, 0.2])
    turned = Pose.parse("0,0,0,0,0,0,2")  # normalised: a half turn about z
    assert np.allclose(turned.rotation, np.diag([-1.0, -1.0, 1.0]))
    for bad in ("1,2", "a,b,c", "0,0,0,0,0,0,0", "1,2,3,nan"):
        with pytest.raises(InvalidInputError, match="pose"):
            Pose.parse(bad)
    with pytest.raises(InvalidInputError, match="scale"):
        ObjectSpec("cube", scale=0.0)


def test_resolve_object_and_the_noise_scale() -> None:
    cube = get_body("cube")
    assert resolve_object(cube) is cube and resolve_object("cube") == cube
    assert cube.size == pytest.approx(0.03)
    box = MeshSolid(*(lambda m: (m.vertices, m.faces))(trimesh.creation.box((0.06, 0.04, 0.02))))
    assert box.size == pytest.approx(0.02)
    with pytest.raises(InvalidInputError, match="ObjectSpec"):
        resolve_object(3)  # type: ignore[arg-type]


def test_example_meshes_are_closed_solids_of_hand_size() -> None:
    for name in EXAMPLE_MESHES:
        solid = example_mesh(name)
        assert 0.02 < solid.bounding_radius < 0.06
        assert solid.is_convex == (name != "l_block")
        assert np.allclose(solid.centroid, 0.0, atol=1e-9)


def test_reading_specs_does_not_import_trimesh() -> None:
    import subprocess

    code = (
        "import sys; from hapticsim.data.objects import ObjectSpec; ObjectSpec('cube').resolve();"
        "print('trimesh' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
