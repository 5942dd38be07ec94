"""Contour following crosses edges: three fingers sweep a cube edge while the thumb probes the
corner (paper IV), recording on both faces."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.geometry import Superquadric
from hapticsim.perception.vision import vision_estimate
from hapticsim.sim.explorer import Explorer
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.scene import build_scene
from hapticsim.sim.strategies.sweep import plan_sweep, run_sweep

CUBE = Superquadric(a=(0.03, 0.03, 0.03), eps=(0.1, 0.1))
FRONT, TOP = (0, 1.0), (2, 1.0)  # faces +x and +z of the body


@pytest.fixture(scope="module")
def sweep() -> tuple[Explorer, dict[str, np.ndarray]]:
    scene = build_scene(CUBE)
    explorer = Explorer(scene, vision_estimate(CUBE, 0), Recorder())
    run_sweep(explorer, FRONT, TOP, thumb_probes=6, rng=np.random.default_rng(0))
    return explorer, explorer.recorder.arrays()


def test_every_sweeping_finger_records_on_both_faces(sweep) -> None:
    _, arrays = sweep
    normals, finger = arrays["normals_clean"], arrays["finger"]
    for f in (1, 2, 3):
        n = normals[finger == f]
        on_front = np.sum(n @ np.array([1.0, 0, 0]) > np.cos(np.radians(5)))
        on_top = np.sum(n @ np.array([0, 0, 1.0]) > np.cos(np.radians(5)))
        # measured: 5-5 and 5-6 per finger (spacing 4 mm, stripes ~50 mm); >= 3 on each face
        # is what a fit needs to see both faces
        assert on_front >= 3 and on_top >= 3, (f, on_front, on_top)


def test_stripes_cross_the_edge_in_order(sweep) -> None:
    _, arrays = sweep
    sel = arrays["finger"] == 2
    z_of_normal = arrays["normals_clean"][sel][:, 2]
    t = arrays["time"][sel]
    assert np.all(np.diff(t) > 0)
    # first on the front face (normal +x), last on the top face (normal +z); measured: normal
    # z 0.000 first, 1.000 last (angles within 6 deg of each face pass)
    assert z_of_normal[0] < 0.1 and z_of_normal[-1] > 0.99


def test_thumb_touches_the_corner_meanwhile(sweep) -> None:
    _, arrays = sweep
    sel = arrays["finger"] == 0
    assert sel.sum() >= 3  # measured: 6 of the 6 probes recorded
    corners = np.array([[0.03, sy, 0.03] for sy in (0.03, -0.03)])
    dist = np.linalg.norm(arrays["points_clean"][sel][:, None] - corners[None], axis=2).min(1)
    assert np.all(dist < 0.025), dist  # measured: <= 0.0167 m from a corner (cube side 0.06)
    # the thumb's probes overlap the sweep in time
    stripe_t = arrays["time"][arrays["finger"] == 2]
    assert arrays["time"][sel].min() < stripe_t.max()


def test_sweep_contacts_are_accurate(sweep) -> None:
    _, arrays = sweep
    p, n = arrays["points_clean"], arrays["normals_clean"]
    # measured: distance <= 3.8e-6 m, angles median 0.06 deg, max 2.3 deg on the edge
    dist, angle = CUBE.contact_errors(p, n)
    assert np.max(dist) < 2e-4
    assert np.median(angle) < 1.0
    assert np.max(angle) < 10.0


def test_plan_without_reachable_stripes_is_none() -> None:
    # a tiny cube (5 mm half side): no finger can cover 8 mm on both sides of an edge
    tiny = Superquadric(a=(0.005, 0.005, 0.005), eps=(0.1, 0.1))
    explorer = Explorer(build_scene(tiny), vision_estimate(tiny, 0), Recorder())
    assert plan_sweep(explorer, FRONT, TOP) is None
