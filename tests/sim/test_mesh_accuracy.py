"""Contacts on the collision hull against the analytic surface (the hull-resolution benchmark)."""

from __future__ import annotations

from hapticsim.data.bodies import get_body
from hapticsim.sim.scene import DEFAULT_MESH_RESOLUTION
from lab.benchmarks.sim import mesh_contact_accuracy


def test_face_normals_of_the_default_hull_are_within_a_degree() -> None:
    # issue 9.5: keep the median normal error on faces <= 1 degree (the limit is the issue's;
    # the probes are seeded, so the value is fixed). Measured at the default resolution (128),
    # 300 probes: cube 0.0004, ellipsoid 0.91 deg (2000 probes: 0.93); the ellipsoid is the worst.
    for name, limit in (("cube", 0.1), ("ellipsoid", 1.0)):
        acc = mesh_contact_accuracy(get_body(name), DEFAULT_MESH_RESOLUTION, samples=300)
        assert acc["missed"] == 0 and acc["faces"]["median"] <= limit, (name, acc["faces"])
        assert acc["distance_median"] < 5e-5


def test_a_coarse_hull_is_measurably_worse() -> None:
    # measured (ellipsoid): 2.5 deg median at resolution 48 against 0.93 at 128
    coarse = mesh_contact_accuracy(get_body("ellipsoid"), 48, samples=300)
    assert coarse["faces"]["median"] > 1.5 and coarse["edges"] is None


def test_box_edges_are_told_apart_from_faces() -> None:
    acc = mesh_contact_accuracy(get_body("cube"), 64, samples=300)
    # measured: ~10 % of uniform (eta, omega) samples of the cube fall on its rounded edges,
    # (26 of 300), with a median normal error of 1.1 deg there against 0.0004 on the faces
    assert 0.03 < acc["edges"]["count"] / 300 < 0.3
    assert acc["edges"]["median"] > acc["faces"]["median"]
