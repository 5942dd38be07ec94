"""Fitting a supertoroid, and multi's choice between a ring and a union (``holes=True``)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hapticsim.cli import main
from hapticsim.data import get_body
from hapticsim.data.io import Contacts, write_contacts
from hapticsim.data.objects import random_composite, random_holed
from hapticsim.errors import InvalidInputError
from hapticsim.fitting import fit
from hapticsim.fitting.toroid import RING_OUTSIDE_SHARE
from hapticsim.metrics import score


def _contacts(truth, seed: int, noise: float = 3e-4):  # noqa: ANN001, ANN202
    gen = np.random.default_rng(seed)
    points, normals = truth.sample_surface(300, rng=seed)
    return points + gen.normal(0.0, noise, points.shape), normals


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_random_ring_is_recovered(seed: int) -> None:
    # 300 surface contacts, 0.3 mm noise: measured IoU 0.989-0.997 over seeds 0-5
    ring = random_holed(seed)
    points, normals = _contacts(ring, seed)
    result = fit(points, normals, method="supertoroid")
    assert result.solid.kind == "supertoroid" and result.evaluations > 0
    assert score(result.solid, ring, rng=0, volume_samples=50_000).iou > 0.93
    assert "superquadric" not in result.to_dict()


@pytest.mark.parametrize(
    ("kind", "seed"),
    [("ring", 0), ("ring", 3), ("body", 1), ("body", 4), ("composite", 2), ("composite", 5)],
)
def test_multi_keeps_a_ring_only_where_there_is_a_hole(kind: str, seed: int) -> None:
    # measured on 12 cases (4 of each): rings win by 1,000-2,300 (union 1,245-2,553 against
    # 85-213), their inner walls hold 7-35 % of the contacts; no body or composite chose a ring
    # (their inner share 0-2 %, the 5 % bar between)
    truth = {"ring": random_holed, "composite": random_composite}.get(kind)
    truth = truth(seed) if truth else get_body(("cube", "cylinder", "ellipsoid",
                                                 "tapered_box")[seed % 4])  # fmt: skip
    points, normals = _contacts(truth, seed)
    result = fit(points, normals, method="multi", holes=True, rng=seed)
    holes = result.selection.holes
    assert set(holes) == {"costs", "inner_share", "outside_share", "chosen", "evaluations"}
    assert set(holes["outside_share"]) == set(holes["costs"]) - {"union"}
    if kind == "ring":  # a true ring lies where its contacts are (measured: 0.0 on seeds 0, 3)
        assert holes["outside_share"]["supertoroid"] <= RING_OUTSIDE_SHARE
    assert result.solid.kind == ("supertoroid" if kind == "ring" else "union")
    assert holes["chosen"] == result.solid.kind  # "supertoroid" (a ring alone) or "union"
    assert score(result.solid, truth, rng=0, volume_samples=50_000).iou > 0.9
    assert result.to_dict()["selection"]["holes"]["chosen"] == result.solid.kind


def test_the_commands_and_bad_input(tmp_path, capsys) -> None:  # noqa: ANN001
    ring = random_holed(7)
    points, normals = _contacts(ring, 7)
    path = write_contacts(tmp_path / "ring.npz", Contacts(points, normals))
    assert main(["fit", str(path), "--method", "multi", "--holes"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["solid"]["kind"] == "supertoroid"
    assert main(["fit", str(path), "--method", "nH", "--holes"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--holes is for --method multi only" in err[0]
    with pytest.raises(InvalidInputError, match="`holes` is for method multi only"):
        fit(points, normals, method="nH", holes=True)
    with pytest.raises(InvalidInputError, match="needs `normals`"):
        fit(points, method="supertoroid")


@pytest.mark.parametrize("seed", [0, 2])
def test_a_handle_becomes_a_ring_part(seed: int) -> None:
    # bodies with a ring handle (300 surface contacts): measured IoU 0.987 / 0.964 with the
    # ring part, multi's blobs 0.915 / 0.859; what is asserted is the kind of answer and that
    # it is no worse than multi's
    from hapticsim.data.objects import random_handled

    truth = random_handled(seed)
    points, normals = _contacts(truth, seed)
    holed = fit(points, normals, method="multi", holes=True, rng=seed)
    plain = fit(points, normals, method="multi", rng=seed)
    assert holed.solid.kind == "union"
    assert [p.kind for p in holed.solid.components].count("supertoroid") == 1
    assert holed.selection.holes["chosen"].endswith("a ring")
    iou = score(holed.solid, truth, rng=0, volume_samples=50_000).iou
    assert iou > 0.93 and iou >= score(plain.solid, truth, rng=0, volume_samples=50_000).iou
