"""Free space from the simulated hand: fingertip centres along the run lie outside the object."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data.bodies import get_body
from hapticsim.data.io import FREE_SPACE_KEY, read_contacts
from hapticsim.errors import InvalidInputError
from hapticsim.exploration import explore
from hapticsim.geometry import Superquadric
from hapticsim.sim.free_space import FreeSpaceTrace, near_contacts


@pytest.fixture(scope="module")
def run(tmp_path_factory) -> tuple[Superquadric, np.ndarray, np.ndarray]:
    out = tmp_path_factory.mktemp("free") / "run"
    explore("cube", strategy="patch", noise=0.05, method="nML", seed=2, out_dir=out,
            progress=False, count=30)  # fmt: skip
    contacts = read_contacts(out / "contacts.npz")
    truth = Superquadric.from_json(out / "truth.json")
    return truth, contacts.extra["points_clean"], contacts.extra[FREE_SPACE_KEY]


def test_free_space_is_outside_the_object_and_near_the_contacts(run) -> None:
    truth, points, free = run
    assert free.ndim == 2 and free.shape[1] == 3 and len(free) > 20
    # The fingertip (radius 8 mm) never enters the object: its centre stays outside, by most
    # all of the radius. Measured: 132 points, nearest 7.8 mm from the surface (F >= 64).
    assert np.all(truth.inside_outside(free) > 1.0)
    centre = points.mean(axis=0)
    size = np.max(np.linalg.norm(points - centre, axis=1))
    assert np.all(np.linalg.norm(free - centre, axis=1) <= 1.5 * size + 1e-12)


def test_near_contacts_and_the_trace_validate() -> None:
    assert near_contacts(None, np.zeros((3, 3))).shape == (0, 3)
    far = np.array([[10.0, 0.0, 0.0], [0.01, 0.0, 0.0]])
    pts = get_body("cube").surface(np.zeros(4), np.linspace(0, 3, 4))[0]
    assert len(near_contacts(far, pts)) == 1
    with pytest.raises(InvalidInputError, match="spacing"):
        FreeSpaceTrace(spacing=0.0)
