"""``explore`` on objects from anywhere: mesh files, superquadric files and random shapes, the
truth as it stands in the world, and bad input ending in one line and exit status 2."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh

from hapticsim.cli import main
from hapticsim.data.bodies import get_body
from hapticsim.data.example_meshes import truncated_pyramid
from hapticsim.data.objects import ObjectSpec, Pose, write_stl
from hapticsim.exploration import explore


@pytest.fixture(scope="module")
def mesh_run(tmp_path_factory) -> dict:
    root = tmp_path_factory.mktemp("mesh")
    # a mesh in millimetres, off the origin: --scale 0.001 and --pose place it
    solid = truncated_pyramid().scaled(1000.0).transformed(np.eye(3), np.array([5.0, 0, 0]))
    path = write_stl(root / "frustum.stl", solid)
    return explore(
        str(path), strategy="patch", seed=2, out_dir=root / "run", progress=False, count=30,
        scale=0.001, pose="0.0,0.0,0.01",
    )  # fmt: skip


def test_a_mesh_run_writes_truth_stl_in_the_world(mesh_run) -> None:
    files = mesh_run["files"]
    assert set(files) == {"contacts", "truth", "fit", "metrics", "report", "hand"}
    assert files["truth"].endswith("truth.stl")
    written = trimesh.load(files["truth"], force="mesh")
    # file coordinates kept, then scaled and placed: centroid at (0.005, 0, 0.01) m
    assert np.allclose(written.center_mass, [0.005, 0.0, 0.01], atol=1e-5)
    truth = ObjectSpec(files["truth"], pose=Pose.parse("0,0,0")).resolve()
    with np.load(files["contacts"]) as data:
        points = data["points_clean"]
    # contacts from MuJoCo lie on the mesh written (float32 STL): measured < 1e-6 m
    assert np.max(truth.contact_errors(points, truth.normals(points))[0]) < 1e-5


def test_a_mesh_run_reports_the_method_and_what_the_planner_knew(mesh_run) -> None:
    metrics = json.load(open(mesh_run["files"]["metrics"]))
    assert metrics["truth"] == "truth.stl" and metrics["theta"] is None
    assert metrics["volume_method"].startswith("Monte Carlo against a mesh truth")
    assert metrics["object_spec"]["kind"] == "mesh" and metrics["object_spec"]["scale"] == 0.001
    assert metrics["collision"] == "convex mesh, as it is"
    vision = metrics["vision"]
    assert vision["has_edges"] is True and vision["shape"]["taper"] == [0.0, 0.0]
    assert vision["vision"]["camera"]["depth_noise"] == 0.001
    acc = metrics["contact_accuracy"]
    assert acc["distance_median"] < 5e-4 and "mesh" in acc["against"]
    assert 0.0 <= metrics["iou"] <= 1.0


def test_a_superquadric_file_and_random_shapes_explore(tmp_path: Path) -> None:
    get_body("cylinder").to_json(tmp_path / "cyl.json")
    a = explore(str(tmp_path / "cyl.json"), strategy="patch", seed=0, out_dir=tmp_path / "a",
                progress=False, count=20)  # fmt: skip
    assert json.load(open(a["files"]["truth"])) == get_body("cylinder").to_dict()
    b = explore("random_tapered", strategy="patch", seed=5, out_dir=tmp_path / "b",
                progress=False, count=20)  # fmt: skip
    c = explore("random_tapered", strategy="patch", seed=5, out_dir=tmp_path / "c",
                progress=False, count=20)  # fmt: skip
    truth_b = json.load(open(b["files"]["truth"]))
    assert truth_b == json.load(open(c["files"]["truth"]))  # drawn from the seed
    assert truth_b["taper"] != [0.0, 0.0]
    assert b["metrics"]["theta"] is not None


def _bad_meshes(root: Path) -> dict[str, Path]:
    (root / "empty.stl").write_bytes(b"")
    box = trimesh.creation.box((0.03, 0.03, 0.03))
    trimesh.Trimesh(box.vertices, box.faces[:-1]).export(root / "open.stl")
    (root / "part.3mf").write_bytes(b"PK")
    write_stl(root / "big.stl", truncated_pyramid().scaled(10.0))
    return {
        "empty": root / "empty.stl",
        "open": root / "open.stl",
        "format": root / "part.3mf",
        "big": root / "big.stl",
    }


@pytest.mark.parametrize(
    ("case", "extra", "message"),
    [
        ("empty", [], "empty|cannot read"),
        ("open", [], "not a closed surface"),
        ("format", [], "unknown object file format '.3mf'"),
        ("big", [], "too large for the hand"),
        ("far", ["--pose", "0.6,0,0"], "too far for the hand"),
    ],
)
def test_bad_objects_end_in_one_line_and_nothing_written(
    capsys, tmp_path: Path, case: str, extra: list[str], message: str
) -> None:
    paths = _bad_meshes(tmp_path)
    source = paths.get(case, paths["big"].with_name("ok.stl"))
    if case == "far":
        write_stl(source, truncated_pyramid())
    out = tmp_path / "out"
    status = main(["explore", "--object", str(source), "--quiet", "--out", str(out), *extra])
    captured = capsys.readouterr()
    assert status == 2
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hapticsim explore: error:")
    assert __import__("re").search(message, lines[0]), lines[0]
    assert not out.exists()


def test_bad_scale_and_pose_are_refused(capsys) -> None:
    with pytest.raises(SystemExit) as exc:  # argparse's own error: one line, status 2
        main(["explore", "--scale", "-1", "--quiet"])
    assert exc.value.code == 2 and "--scale" in capsys.readouterr().err
    assert main(["explore", "--pose", "1,2", "--quiet"]) == 2
    assert "pose" in capsys.readouterr().err


def test_help_lists_object_kinds_and_strategies(capsys) -> None:
    with pytest.raises(SystemExit):
        main(["explore", "--help"])
    text = capsys.readouterr().out
    for word in ("random_tapered", "superquadric", ".stl", "mesh", "paper", "patch", "stripe",
                 "sweep", "--scale", "--pose"):  # fmt: skip
        assert word in text, word


def test_score_takes_the_written_truth_stl(mesh_run, capsys) -> None:
    files = mesh_run["files"]
    assert main(["score", files["fit"], files["truth"], "--seed", "2"]) == 0
    printed = json.loads(capsys.readouterr().out)
    metrics = json.load(open(files["metrics"]))
    # the same solid (the STL rounds vertices to float32) and seed: equal to 1e-3
    assert printed["epsilon"] == pytest.approx(metrics["epsilon"], abs=1e-3)
    assert printed["volume_method"].startswith("Monte Carlo against a mesh truth")
