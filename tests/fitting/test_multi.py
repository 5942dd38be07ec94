"""method="multi": a union of superquadrics from contacts with normals (SPEC §10)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hapticsim.cli import main
from hapticsim.data import get_body, paper_dataset
from hapticsim.data.io import Contacts, write_contacts
from hapticsim.errors import InvalidInputError
from hapticsim.fitting import fit
from hapticsim.geometry import Superquadric, SuperquadricUnion, solid_from_dict
from hapticsim.metrics import score

#: two boxes in an L (their corner shared) and a ball on top of one: three parts
L_PARTS = (
    Superquadric(a=(0.03, 0.01, 0.025), eps=(0.2, 0.2), center=(0.0, 0.0, 0.0)),
    Superquadric(a=(0.01, 0.03, 0.025), eps=(0.2, 0.2), center=(-0.02, 0.02, 0.0)),
)
L_SHAPE = SuperquadricUnion(L_PARTS)


def _run(args: list[str]) -> int:
    try:
        return main(args)
    except SystemExit as exc:  # argparse's own checks
        return int(exc.code)


def test_one_part_object_gets_nh_itself() -> None:
    c = paper_dataset(get_body("cube"), noise=0.0, rng=3)
    multi = fit(c.points, c.normals, "multi", rng=5)
    single = fit(c.points, c.normals, "nH", rng=5)
    assert multi.selection.parts == 1 and len(multi.solid.parts) == 1
    assert multi.selection.baseline.superquadric == single.superquadric == multi.solid.parts[0]
    assert multi.selection.candidates[0]["parts"] == 1
    d = multi.to_dict()
    assert d["method"] == "multi" and d["solid"] == {"parts": [single.superquadric.to_dict()]}
    # one estimate: the union; the one-part fit is the selection's baseline, not a second answer
    assert "superquadric" not in d
    assert d["selection"]["baseline"]["superquadric"] == single.superquadric.to_dict()
    with pytest.raises(AttributeError, match=r"use \.solid; its one-part nH fit is"):
        multi.superquadric  # noqa: B018


def test_an_l_of_two_boxes_gets_two_parts() -> None:
    # contacts all round (area samples): measured IoU 0.98-0.99 over seeds 0-2, nH's 0.70-0.72
    pts, nrm = L_SHAPE.sample_surface(300, rng=0)
    result = fit(pts, nrm, "multi", rng=0)
    assert result.selection.parts >= 2
    assert score(result.solid, L_SHAPE, volume_samples=20_000, chamfer_samples=500).iou > 0.9
    baseline = result.selection.baseline.superquadric
    assert score(baseline, L_SHAPE, volume_samples=20_000).iou < 0.8
    again = fit(pts, nrm, "multi", rng=0)
    assert again.solid == result.solid  # the same seed, the same union


def test_a_part_count_asked_for_is_fitted() -> None:
    pts, nrm = L_SHAPE.sample_surface(200, rng=1)
    two = fit(pts, nrm, "multi", rng=1, parts=2)
    assert len(two.solid.parts) == 2 and two.selection.parts == 2
    one = fit(pts, nrm, "multi", rng=1, parts=1)
    assert one.solid.parts == (fit(pts, nrm, "nH", rng=1).superquadric,)
    with pytest.raises(InvalidInputError, match="cannot fit 12 parts"):
        fit(pts, nrm, "multi", rng=1, parts=12)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"method": "multi", "parts": 0}, "`parts` must be in"),
        ({"method": "multi", "parts": "two"}, "`parts` must be an int or 'auto'"),
        ({"method": "nH", "parts": 2}, "for method multi only"),
        ({"method": "multi", "sigma": np.ones(150)}, "nML only"),
    ],
)
def test_bad_arguments_name_the_problem(kwargs: dict, match: str) -> None:
    c = paper_dataset(get_body("cube"), noise=0.0, rng=0)
    with pytest.raises(InvalidInputError, match=match):
        fit(c.points, c.normals, **kwargs)
    with pytest.raises(InvalidInputError, match="needs `normals`"):
        fit(c.points, method="multi")


def test_cli_fit_multi_and_score_the_union(tmp_path, capsys) -> None:
    pts, nrm = L_SHAPE.sample_surface(200, rng=2)
    contacts = write_contacts(tmp_path / "l.npz", Contacts(pts, nrm))
    truth = tmp_path / "truth.json"
    truth.write_text(json.dumps(L_SHAPE.to_dict()))
    out = tmp_path / "fit.json"
    assert main(["fit", str(contacts), "--method", "multi", "--out", str(out)]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["solid"]["parts"] and printed["selection"]["parts"] >= 2
    assert isinstance(solid_from_dict(printed), SuperquadricUnion)
    assert main(["score", str(out), str(truth)]) == 0
    assert json.loads(capsys.readouterr().out)["iou"] > 0.85
    for args, words in [
        (["--parts", "0"], "--parts"),
        (["--parts", "x"], "--parts"),
        (["--method", "nH", "--parts", "2"], "multi only"),
    ]:
        base = ["fit", str(contacts)] + (["--method", "multi"] if args[0] != "--method" else [])
        assert _run(base + args) == 2
        err = capsys.readouterr().err.strip()
        assert words in err and "\n" not in err and "Traceback" not in err
    empty = tmp_path / "empty.json"
    empty.write_text('{"parts": []}')
    assert main(["score", str(empty), str(truth)]) == 2
    err = capsys.readouterr().err.strip()
    assert "at least one part" in err and "\n" not in err
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"parts": [L_PARTS[0].to_dict(), dict(L_PARTS[1].to_dict(),
                                                                     eps=[3.0, 1.0])]}))
    assert main(["score", str(out), str(bad)]) == 2
    assert "part 1 of the union" in capsys.readouterr().err


def _bar_data(points: np.ndarray, normals: np.ndarray):
    from hapticsim.fitting import multi

    data = multi._Data(points, normals, None, None, 0.02)
    data.allowed = np.stack([points.min(axis=0), points.max(axis=0)]) + [[-1.0], [1.0]]
    return multi, data


def test_an_end_nobody_touched_is_retracted_to_the_contacts() -> None:
    # a bar along z touched on its sides only, for z in [-0.03, 0.01], and a ball beside it:
    # the bar's ends reach +-0.05, beyond the contacts' box, where nothing says it is there
    bar = Superquadric(a=(0.008, 0.008, 0.05), eps=(0.3, 1.0))
    phi = np.linspace(0.0, 2.0 * np.pi, 40, endpoint=False)
    z = np.linspace(-0.03, 0.01, 10)
    pts = np.array([[0.008 * np.cos(p), 0.008 * np.sin(p), h] for p in phi for h in z])
    nrm = np.array([[np.cos(p), np.sin(p), 0.0] for p in phi for h in z])
    ball = Superquadric(a=(0.01, 0.01, 0.01), eps=(1.0, 1.0), center=(0.05, 0.0, -0.01))
    bp, bn = ball.sample_surface(100, rng=0)
    multi, data = _bar_data(np.vstack([pts, bp]), np.vstack([nrm, bn]))
    owner = np.r_[np.zeros(len(pts), int), np.ones(len(bp), int)]
    out = multi._clip_unsupported(data, np.stack([bar.to_vector(), ball.to_vector()]), owner)
    clipped = Superquadric.from_vector(out[0])
    reach = multi.CLIP_MARGIN * data.size
    top = clipped.center[2] + clipped.a[2]
    bottom = clipped.center[2] - clipped.a[2]
    assert top == pytest.approx(0.01 + reach) and bottom == pytest.approx(-0.03 - reach)
    assert np.allclose(clipped.a[:2], bar.a[:2]) and np.allclose(clipped.rotation, bar.rotation)
    assert np.array_equal(out[1], ball.to_vector())  # touched all round: unchanged


def test_an_end_touched_or_inside_another_part_stays() -> None:
    # the same bar touched on its top face too, its bottom end inside a second part
    bar = Superquadric(a=(0.008, 0.008, 0.05), eps=(0.3, 1.0))
    base = Superquadric(a=(0.03, 0.03, 0.02), eps=(0.5, 0.5), center=(0.0, 0.0, -0.06))
    pts, nrm = bar.sample_surface(300, rng=1)
    keep = pts[:, 2] > -0.03
    bp, bn = base.sample_surface(300, rng=2)
    bp_keep = bp[:, 2] < -0.045  # nothing near the bar's end
    multi, data = _bar_data(np.vstack([pts[keep], bp[bp_keep]]),
                            np.vstack([nrm[keep], bn[bp_keep]]))  # fmt: skip
    owner = np.r_[np.zeros(int(keep.sum()), int), np.ones(int(bp_keep.sum()), int)]
    vectors = np.stack([bar.to_vector(), base.to_vector()])
    assert np.array_equal(multi._clip_unsupported(data, vectors, owner), vectors)
