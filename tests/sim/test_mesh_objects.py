"""Mesh objects in the scene: convex meshes collide as they are, non-convex ones by parts."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from hapticsim.data.example_meshes import l_block, truncated_pyramid
from hapticsim.errors import SimulationError
from hapticsim.geometry import mesh_solid
from hapticsim.geometry.mesh_solid import MeshSolid
from hapticsim.perception.vision import vision_estimate
from hapticsim.sim.controllers import Probe
from hapticsim.sim.explorer import Explorer
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.scene import build_scene
from hapticsim.sim.workspace import Workspace


def _probe(solid: MeshSolid, aims: np.ndarray, directions: np.ndarray) -> dict:
    scene = build_scene(solid)
    explorer = Explorer(scene, vision_estimate(solid, 0), Recorder())
    for aim, d in zip(aims, directions, strict=True):
        explorer.probe_patch(1, [Probe(aim, d / np.linalg.norm(d))])
    return {"scene": scene, **explorer.recorder.arrays()}


def _closest(solid: MeshSolid, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    mesh = solid.to_trimesh()
    _, dist, face = trimesh.proximity.closest_point(mesh, points)
    return dist, mesh.face_normals[face]


def test_a_convex_mesh_is_one_geom_and_contacts_lie_on_it() -> None:
    solid = truncated_pyramid()
    aims = np.array([[0.0, 0.0, 0.025], [0.03, 0.0, 0.0], [0.0, -0.026, -0.01]])
    run = _probe(solid, aims, np.array([[0, 0, -1.0], [-1.0, 0, 0.2], [0, 1.0, 0.1]]))
    assert run["scene"].object_geom_ids == (run["scene"].object_geom_id,)
    assert run["scene"].collision_method == "convex mesh, as it is"
    assert len(run["points_clean"]) == 3
    dist, normal = _closest(solid, run["points_clean"])
    # MuJoCo's hull is the mesh itself: measured < 1e-9 m and 0.0 degrees
    assert np.all(dist < 1e-4), dist
    assert np.all(np.einsum("ij,ij->i", normal, run["normals_clean"]) > np.cos(np.radians(1)))


def test_a_non_convex_mesh_is_split_and_touched_in_its_corner() -> None:
    pytest.importorskip("coacd")
    solid = l_block()  # centroid at the origin; the inner corner faces +x and -y
    scene = build_scene(solid)
    assert len(scene.object_geom_ids) >= 2 and "coacd" in scene.collision_method
    # probe the two inner faces of the L, which the convex hull of the whole would cover
    inner = solid.centroid + np.array([0.008, -0.012, 0.0])
    aims = np.array([inner + [0.012, 0.0, 0.01], inner + [0.0, -0.012, -0.01]])
    run = _probe(solid, aims, np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]))
    assert len(run["points_clean"]) == 2
    dist, normal = _closest(solid, run["points_clean"])
    # measured: the decomposition reproduces the two bars; contacts < 1e-9 m, 0.0 degrees
    assert np.all(dist < 5e-4), dist
    assert np.all(np.einsum("ij,ij->i", normal, run["normals_clean"]) > np.cos(np.radians(2)))


def test_without_coacd_a_non_convex_mesh_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    import builtins

    real_import = builtins.__import__

    def no_coacd(name: str, *args: object, **kwargs: object) -> object:
        if name == "coacd":
            raise ImportError("no coacd")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_coacd)
    monkeypatch.setattr(mesh_solid, "_decompositions", {})
    with pytest.raises(SimulationError, match="not convex.*hapticsim\\[meshes\\]"):
        build_scene(l_block())


def test_mesh_too_large_or_too_far_is_refused() -> None:
    with pytest.raises(SimulationError, match="too large.*--scale 0.001"):
        build_scene(l_block().scaled(1000.0))
    with pytest.raises(SimulationError, match="too far"):
        build_scene(l_block().transformed(np.eye(3), np.array([0.5, 0.0, 0.0])))
    assert Workspace().max_object_radius > l_block().bounding_radius


def test_the_stand_is_under_the_centroid_of_a_flat_bottom() -> None:
    scene = build_scene(truncated_pyramid())
    foot = scene.model.geom_pos[scene.stand_geom_id]
    assert np.allclose(foot[:2], 0.0, atol=1e-9)  # not under a corner vertex
