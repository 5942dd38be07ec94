"""SuperquadricUnion: volumes with overlaps, samples counted once, JSON, errors (SPEC §10)."""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric, SuperquadricUnion
from hapticsim.metrics import score


def _ball(r: float, x: float = 0.0) -> Superquadric:
    return Superquadric(a=(r, r, r), eps=(1.0, 1.0), center=(x, 0.0, 0.0))


def test_the_volume_counts_an_overlap_once() -> None:
    r, d = 0.02, 0.02  # two balls, centres one radius apart: lens volume pi (4r + d)(2r - d)^2 / 12
    lens = np.pi * (4 * r + d) * (2 * r - d) ** 2 / 12
    union = SuperquadricUnion((_ball(r), _ball(r, d)))
    assert union.volume == pytest.approx(2 * _ball(r).volume - lens, rel=2e-3)
    apart = SuperquadricUnion((_ball(r), _ball(r, 0.1)))
    assert apart.volume == pytest.approx(2 * _ball(r).volume, rel=1e-12)  # exact without overlap
    inside = SuperquadricUnion((_ball(r), _ball(0.5 * r, 0.002)))
    assert inside.volume == pytest.approx(_ball(r).volume, rel=1e-3)


def test_interior_samples_are_uniform_over_the_union() -> None:
    # two balls apart, one twice the other's radius: 8 of 9 samples in the big one
    union = SuperquadricUnion((_ball(0.02), _ball(0.01, 0.1)))
    pts = union.sample_interior(20_000, rng=0)
    share = float(np.mean(pts[:, 0] < 0.05))
    assert share == pytest.approx(8 / 9, abs=0.01)


def test_the_surface_hides_what_another_part_holds() -> None:
    union = SuperquadricUnion((_ball(0.02), _ball(0.02, 0.02)))
    pts, nrm = union.sample_surface(2000, rng=1)
    inner = pts - 1e-6 * nrm
    assert not np.any(union.parts[0].contains(inner) & union.parts[1].contains(inner))
    # the distance to the surface of a point inside both balls is to the outer surface, not the
    # hidden cap: the midpoint is sqrt(r^2 - (d/2)^2) from the seam circle
    mid = np.array([[0.01, 0.0, 0.0]])
    assert union.surface_distance(mid)[0] == pytest.approx(np.sqrt(0.02**2 - 0.01**2), rel=2e-3)


def test_one_part_is_that_superquadric() -> None:
    sq = Superquadric(a=(0.03, 0.02, 0.04), eps=(0.3, 0.9), taper=(0.2, 0.1))
    union = SuperquadricUnion((sq,))
    assert union.volume == pytest.approx(sq.volume, rel=1e-12) and union.size == sq.size
    s = score(union, sq, volume_samples=20_000, chamfer_samples=500)
    assert s.alpha == 0.0 and s.beta == 0.0 and s.chamfer < 1e-4


def test_json_errors_name_the_problem() -> None:
    part = _ball(0.02).to_dict()
    with pytest.raises(InvalidInputError, match="at least one part"):
        SuperquadricUnion.from_dict({"parts": []})
    with pytest.raises(InvalidInputError, match="`parts` list"):
        SuperquadricUnion.from_dict({"a": [1, 2, 3]})
    with pytest.raises(InvalidInputError, match="unknown key"):
        SuperquadricUnion.from_dict({"parts": [part], "colour": "red"})
    bad = dict(part, eps=[5.0, 1.0])
    with pytest.raises(InvalidInputError, match="part 1 of the union"):
        SuperquadricUnion.from_dict({"parts": [part, bad]})
    with pytest.raises(InvalidInputError, match="at least one part"):
        SuperquadricUnion(())
    with pytest.raises(InvalidInputError, match="part 0 of a union must be a Superquadric"):
        SuperquadricUnion(("cube",))  # type: ignore[arg-type]
