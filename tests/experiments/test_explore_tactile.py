"""``explore --sensing tactile``: the files of SPEC §11 and one-line errors for bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from hapticsim.data.io import read_contacts
from hapticsim.exploration import explore
from tests.test_cli_core import assert_bad_input, run


@pytest.fixture(scope="module")
def summary(tmp_path_factory) -> dict:  # noqa: ANN001
    out = tmp_path_factory.mktemp("tactile") / "run"
    return explore("ellipsoid", strategy="patch", seed=1, out_dir=out, progress=False, count=30,
                   sensing="tactile")  # fmt: skip


def test_tactile_explore_writes_tactile_npz_beside_the_contacts(summary) -> None:  # noqa: ANN001
    files = summary["files"]
    assert set(files) == {"contacts", "truth", "fit", "metrics", "report", "tactile", "hand"}
    with np.load(files["tactile"]) as t:
        assert t["images"].shape == (30, 4, 31, 31) and t["images"].dtype == np.float32
        assert t["taxel_position"].shape == (4, 31, 31, 3) and t["finger"].shape == (30,)
        assert json.loads(str(t["skin"]))["name"] == "ideal"
        lit = t["images"][np.arange(30), t["finger"]]
        assert np.all(lit.reshape(30, -1).max(axis=1) > 0)


def test_tactile_contacts_are_the_estimates_and_mujocos_stand_beside(summary) -> None:  # noqa: ANN001
    with np.load(summary["files"]["contacts"]) as c:
        assert str(c["sensing"]) == "tactile"
        # --noise 0: the measured contacts are the estimates as they are
        np.testing.assert_array_equal(c["points"], c["points_clean"])
        assert not np.array_equal(c["points"], c["points_exact"])
        assert np.all(c["sigma"] > 0) and c["normals_exact"].shape == (30, 3)
    assert len(read_contacts(summary["files"]["contacts"])) == 30  # still a SPEC contacts file
    metrics = json.load(open(summary["files"]["metrics"]))
    assert metrics["sensing"] == "tactile" and metrics["skin"]["name"] == "ideal"
    assert metrics["contact_accuracy"]["distance_median"] < 1e-4  # measured 7e-6
    assert metrics["contact_accuracy_exact"]["distance_median"] < 1e-4  # the hull: 1.3e-5
    assert metrics["tactile"]["unfelt"] == summary["unfelt"] == 0


def test_exact_explore_says_so(tmp_path: Path) -> None:
    out = tmp_path / "run"
    explore("ellipsoid", strategy="patch", seed=1, out_dir=out, progress=False, count=20)
    with np.load(out / "contacts.npz") as c:
        assert str(c["sensing"]) == "exact" and "points_exact" not in c.files
    assert not (out / "tactile.npz").exists()


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["--sensing", "tactile", "--skin", "visoin"], "did you mean 'vision'"),
        (["--skin", "vision"], "`skin`, `taxel_model` and `steer_on` are for tactile sensing"),
        (["--steer-on", "contacts"], "`steer_on` are for tactile sensing"),
        (["--sensing", "touchy"], "invalid choice: 'touchy'"),
        (["--sensing", "tactile", "--skin", "MISSING.toml"], "MISSING.toml' not found"),
        (["--sensing", "tactile", "--skin", "BAD.toml"], "not valid TOML"),
        (["--sensing", "tactile", "--skin", "KEY.toml"], "unknown key(s) ['gain']"),
        (["--sensing", "tactile", "--hand", "PAD.toml"], "pad: no geom or site 'nowhere'"),
        (["--sensing", "tactile", "--hand", "GRID.toml"], "`rows` must be a whole number >= 1"),
    ],
)
def test_bad_tactile_input_is_one_line_and_writes_nothing(
    capsys, tmp_path: Path, args: list, match: str
) -> None:  # noqa: ANN001
    from tests.sim.test_hands import TWO_FINGERS

    (tmp_path / "BAD.toml").write_text("name = ")
    (tmp_path / "KEY.toml").write_text("[sensor]\ngain = 2.0\n")
    import textwrap

    hand = textwrap.dedent(TWO_FINGERS)
    (tmp_path / "PAD.toml").write_text(
        hand.replace(
            "sweep = [0.0, 0.35, 1.75]", 'sweep = [0.0, 0.35, 1.75]\npad = { on = "nowhere" }'
        )
    )
    (tmp_path / "GRID.toml").write_text(hand + "\n[pad]\nrows = 0\n")
    args = [str(tmp_path / a) if a.endswith(".toml") else a for a in args]
    out = tmp_path / "run"
    try:
        code, stdout, stderr = run(capsys, "explore", "--count", "20", "--quiet", "--out",
                                   str(out), *args)  # fmt: skip
    except SystemExit as exc:  # argparse's own refusal: the same one line and status
        stdout, stderr = capsys.readouterr()
        code = exc.code
    assert_bad_input(code, stdout, stderr, "explore", match)
    assert not out.exists()
