"""The GPIS baseline: a closed mesh estimate scored like any solid, and its errors."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from hapticsim.data.bodies import BODIES
from hapticsim.data.synthetic import paper_dataset
from hapticsim.errors import InvalidInputError
from hapticsim.fitting.gpis import fit_gpis
from hapticsim.geometry import MeshSolid
from hapticsim.metrics import score


@pytest.fixture(scope="module")
def ellipsoid_fit():  # noqa: ANN201
    pytest.importorskip("skimage")
    data = paper_dataset(BODIES["ellipsoid"], 0.05, rng=1, count=40)
    return fit_gpis(data.points, data.normals, resolution=20)


def test_gpis_gives_a_closed_mesh_near_the_ellipsoid(ellipsoid_fit) -> None:  # noqa: ANN001
    g = ellipsoid_fit
    assert isinstance(g.solid, MeshSolid)
    s = score(g.solid, BODIES["ellipsoid"], rng=0)
    assert s.iou > 0.8 and s.epsilon < 0.2  # measured: IoU 0.92, eps 0.08
    assert 0.005 < g.length_scale < 0.2 and np.isfinite(g.log_likelihood)
    assert set(g.to_dict()) >= {"method", "length_scale", "value_noise", "gradient_noise"}


@pytest.mark.slow
def test_gpis_is_deterministic(ellipsoid_fit) -> None:  # noqa: ANN001
    data = paper_dataset(BODIES["ellipsoid"], 0.05, rng=1, count=40)
    again = fit_gpis(data.points, data.normals, resolution=20)
    np.testing.assert_array_equal(again.solid.vertices, ellipsoid_fit.solid.vertices)


def test_gpis_bad_input(monkeypatch) -> None:  # noqa: ANN001
    pytest.importorskip("skimage")
    data = paper_dataset(BODIES["cube"], 0.0, rng=1, count=20)
    with pytest.raises(InvalidInputError, match="normals"):
        fit_gpis(data.points, data.normals[:5])
    with pytest.raises(InvalidInputError, match="resolution"):
        fit_gpis(data.points, data.normals, resolution=4)
    many = paper_dataset(BODIES["cube"], 0.0, rng=1, count=401)
    with pytest.raises(InvalidInputError, match="at most 400 contacts"):
        fit_gpis(many.points, many.normals)
    monkeypatch.setitem(sys.modules, "skimage.measure", None)
    with pytest.raises(InvalidInputError, match=r"hapticsim\[gpis\]"):
        fit_gpis(data.points, data.normals)


def test_fit_method_gpis_is_its_mesh_alone(tmp_path, capsys) -> None:  # noqa: ANN001
    pytest.importorskip("skimage")
    import json

    from hapticsim.cli import main
    from hapticsim.data.io import Contacts, write_contacts
    from hapticsim.fitting import fit
    from hapticsim.geometry.solid_io import solid_from_dict

    data = paper_dataset(BODIES["ellipsoid"], 0.05, rng=1, count=40)
    result = fit(data.points, data.normals, method="gpis", rng=3)
    assert isinstance(result.solid, MeshSolid) and result.method == "gpis"
    # one estimate: no nH fit beside the mesh; its EOF is the contacts' distance to the mesh
    assert result.evaluations == 0 and len(result.history[0]) == 0
    distance = result.solid.surface_distance(data.points)
    assert result.eof == pytest.approx(float(np.mean(distance**2)))
    assert np.sqrt(result.eof) < 0.1 * BODIES["ellipsoid"].size
    assert "superquadric" not in result.to_dict()
    with pytest.raises(AttributeError, match="is a mesh, not one superquadric"):
        result.superquadric  # noqa: B018
    # the JSON's solid reads back as the same mesh, and scores as one
    back = solid_from_dict(json.loads(json.dumps(result.to_dict())))
    np.testing.assert_allclose(back.vertices, result.solid.vertices)
    assert result.to_dict()["model"]["length_scale"] > 0
    assert score(back, BODIES["ellipsoid"], rng=0).iou > 0.8  # measured: IoU 0.920
    with pytest.raises(InvalidInputError, match="uncertainty"):
        fit(data.points, data.normals, method="gpis", uncertainty=True)
    path = write_contacts(tmp_path / "c.npz", Contacts(data.points, data.normals))
    assert main(["fit", str(path), "--method", "gpis", "--seed", "3"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["method"] == "gpis" and "mesh" in printed["solid"]
