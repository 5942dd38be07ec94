"""Meshes as labs have them: what the loader repairs, what it says, what it refuses."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from hapticsim.data.mesh_repair import repair_mesh
from hapticsim.data.objects import load_mesh
from hapticsim.errors import InvalidInputError

trimesh = pytest.importorskip("trimesh")


def _box_with_a_cap_sliver() -> tuple[np.ndarray, np.ndarray]:
    """A 40 x 30 x 20 mm box as an exporter writes one with a T-junction: one face split at the
    midpoint m of an edge a-b, closed by the zero-area triangle (a, b, m)."""
    box = trimesh.creation.box((40.0, 30.0, 20.0))
    v, f = np.asarray(box.vertices), np.asarray(box.faces).tolist()
    a, b, c = f[0]
    other = next(g for g in f[1:] if a in g and b in g)
    m = len(v)
    v = np.vstack([v, 0.5 * (v[a] + v[b])])
    f = [g for g in f if g not in ([a, b, c], other)]
    d = next(x for x in other if x not in (a, b))
    s = other.index(d)
    f += [[a, m, c], [m, b, c], [d, other[(s + 1) % 3], other[(s + 2) % 3]], [a, b, m]]
    return v, np.asarray(f)


def _write(mesh: object, path: Path) -> Path:
    mesh.export(str(path))  # type: ignore[attr-defined]
    return path


def test_a_sliver_is_collapsed_without_opening_the_surface(tmp_path: Path, capsys) -> None:  # noqa: ANN001
    v, f = _box_with_a_cap_sliver()
    mesh = trimesh.Trimesh(v, f, process=False)
    assert mesh.is_watertight  # as read: closed, with one zero-area face
    path = _write(mesh, tmp_path / "package.stl")  # float32 coordinates, millimetres
    solid = load_mesh(path, scale=0.001)
    assert solid.volume == pytest.approx(40 * 30 * 20 * 1e-9, rel=1e-6)
    assert solid.repair["collapsed_slivers"] == 1
    assert abs(solid.repair["volume_change"]) < 1e-6
    err = capsys.readouterr().err
    assert err.startswith("hapticsim: repaired mesh package.stl:") and "collapsed 1 slivers" in err


def test_a_convex_fruit_in_float32_millimetres_is_convex(tmp_path: Path) -> None:
    fruit = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    fruit.apply_scale((41.3, 37.9, 44.1))  # mm
    solid = load_mesh(_write(fruit, tmp_path / "fruit.stl"), scale=0.001)
    assert solid.is_convex  # 1e-7 of the bounding radius refused float32 rounding
    from hapticsim.data.example_meshes import EXAMPLE_MESHES

    assert not EXAMPLE_MESHES["l_block"]().is_convex


def test_holes_winding_and_duplicate_shells_are_mended_and_recorded() -> None:
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.03)
    v, f = np.asarray(sphere.vertices), np.asarray(sphere.faces)
    holed = np.delete(f, [5, 77], axis=0)  # two one-face holes
    flipped = holed.copy()
    flipped[::7] = flipped[::7, ::-1]  # every seventh face wound the wrong way
    doubled_v, doubled_f = np.vstack([v, v]), np.vstack([flipped, flipped + len(v)])
    out_v, out_f, report = repair_mesh(doubled_v, doubled_f, "scan.ply")
    closed = trimesh.Trimesh(out_v, out_f, process=False)
    assert closed.is_watertight and closed.is_winding_consistent and closed.volume > 0
    # the copy's vertices are the original's exactly: welded without counting (an STL repeats
    # every vertex), and its faces go as repeats
    assert report.merged_vertices == 0 and report.dropped_faces == len(holed)
    assert report.fixed_winding and report.filled_holes == 2 and report.hole_faces == 6
    assert abs(closed.volume - sphere.volume) < 0.002 * sphere.volume
    text = report.summary()
    assert "dropped" in text and "filled 2 holes" in text and "fixed the faces' winding" in text
    jittered = v + np.random.default_rng(0).normal(0, 1e-9, v.shape)  # float rounding
    welded = repair_mesh(np.vstack([v, jittered]), np.vstack([f, f + len(v)]), "j")[2]
    assert welded.merged_vertices == len(v)
    _, _, clean = repair_mesh(v, f, "sphere.ply")
    assert not clean.changed and clean.summary().startswith("nothing")
    assert clean.volume_change == pytest.approx(0.0, abs=1e-12)


def test_an_obj_of_several_groups_and_a_glb_load(tmp_path: Path) -> None:
    box = trimesh.creation.box((0.04, 0.03, 0.02))
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in box.vertices]
    for k, face in enumerate(box.faces):
        if k % 6 == 0:
            lines.append(f"g part{k // 6}")
        lines.append("f " + " ".join(str(i + 1) for i in face))
    (tmp_path / "groups.obj").write_text("\n".join(lines) + "\n")
    assert load_mesh(tmp_path / "groups.obj").volume == pytest.approx(0.04 * 0.03 * 0.02)
    scan = trimesh.creation.icosphere(subdivisions=2, radius=0.03)
    glb = load_mesh(_write(trimesh.Scene(scan), tmp_path / "scan.glb"))
    assert glb.volume == pytest.approx(scan.volume, rel=1e-5)


def test_what_is_not_one_solid_is_refused_saying_why(tmp_path: Path) -> None:
    a = trimesh.creation.box((0.02, 0.02, 0.02))
    b = a.copy()
    b.apply_translation((0.1, 0, 0))
    apart = _write(trimesh.util.concatenate([a, b]), tmp_path / "two.stl")
    with pytest.raises(InvalidInputError, match=r"2 bodies in 2 pieces, the nearest 80 mm apart"):
        load_mesh(apart)
    touching = b.copy()
    touching.apply_translation((-0.085, 0, 0))  # boxes overlapping by 5 mm: one object, fused
    fused = load_mesh(_write(trimesh.util.concatenate([a, touching]), tmp_path / "t.stl"))
    assert fused.repair["fused_bodies"] == 2
    assert fused.volume == pytest.approx((0.035 * 0.02 * 0.02), rel=1e-4)
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.03)
    cap = sphere.vertices[sphere.faces].mean(axis=1)[:, 2] > 0.02  # the top cap cut off
    cut = trimesh.Trimesh(sphere.vertices, sphere.faces[~cap])
    with pytest.raises(InvalidInputError, match=r"1 holes, the largest \d+(\.\d+)? mm across"):
        load_mesh(_write(cut, tmp_path / "bowl.stl"))
    box = trimesh.creation.box((0.02, 0.02, 0.02))
    damaged = np.asarray(box.vertices, dtype=float)
    damaged[3] = np.nan  # as pybullet_data's random/168.obj holds only NaN vertices
    with pytest.raises(InvalidInputError, match=r"mesh m has 1 of 8 vertices with non-finite"):
        repair_mesh(damaged, np.asarray(box.faces), "m")
