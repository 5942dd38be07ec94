"""The paper's four bodies."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from hapticsim.data.bodies import BODIES, BODY_NAMES, get_body, resolve_body
from hapticsim.errors import HapticsimError
from hapticsim.geometry import Superquadric


def test_names_and_shapes_follow_spec() -> None:
    assert BODY_NAMES == ("tapered_box", "cube", "cylinder", "ellipsoid")
    assert set(BODIES) == set(BODY_NAMES)
    box, cube, cyl, ell = (get_body(n) for n in BODY_NAMES)
    assert np.all(box.eps == 0.1) and np.all(np.abs(box.taper) >= 0.3)
    assert box.a[0] != box.a[1]
    assert np.all(cube.eps == 0.1) and np.all(cube.a == cube.a[0]) and np.all(cube.taper == 0)
    assert cyl.eps.tolist() == [0.1, 1.0]  # SPEC §1: eps1 ~ 0.1, eps2 = 1
    assert ell.eps.tolist() == [1.0, 1.0]
    for name in BODY_NAMES:
        sq = get_body(name)
        # Hand-held: every extent between 2 cm and 20 cm.
        extent = 2 * sq.a * np.array([1 + abs(sq.taper[0]), 1 + abs(sq.taper[1]), 1])
        assert np.all(extent > 0.02) and np.all(extent < 0.2)


def test_resolve_body_by_name_and_by_json(tmp_path: Path) -> None:
    assert resolve_body("cube") == get_body("cube")
    sq = Superquadric(a=(0.01, 0.02, 0.03), eps=(0.5, 0.7), taper=(0.1, -0.2))
    bare = tmp_path / "truth.json"
    sq.to_json(bare)
    assert resolve_body(str(bare)) == sq
    assert resolve_body(bare) == sq
    fit = tmp_path / "fit.json"
    fit.write_text(json.dumps({"superquadric": sq.to_dict(), "method": "nH", "eof": 0.1}))
    assert resolve_body(fit) == sq


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda tmp: get_body("sphere"), "tapered_box, cube, cylinder, ellipsoid"),
        (lambda tmp: get_body(3), "unknown body 3"),
        (lambda tmp: resolve_body("sphere"), "tapered_box, cube, cylinder, ellipsoid"),
        (lambda tmp: resolve_body(str(tmp / "missing.json")), "not found"),
        (lambda tmp: resolve_body(None), "`name_or_path`"),
    ],
)
def test_bad_names_raise_listing_the_valid_ones(call, match: str, tmp_path: Path) -> None:
    with pytest.raises(HapticsimError, match=match):
        call(tmp_path)
