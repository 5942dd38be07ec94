"""Names one edit away (or another case) get a suggestion in the error message."""

from __future__ import annotations

import pytest

from hapticsim._validate import did_you_mean, suggestion
from hapticsim.cli import main


@pytest.mark.parametrize(
    ("name", "meant"),
    [("Cube", "cube"), ("cueb", "cube"), ("cub", "cube"), ("cubes", "cube"), ("cuba", "cube"),
     ("CYLINDER", "cylinder"), ("cube", None), ("cbe2", None), ("sphere", None), (3, None)],
)  # fmt: skip
def test_one_edit_or_case(name: object, meant: str | None) -> None:
    assert suggestion(name, ("tapered_box", "cube", "cylinder", "ellipsoid")) == meant


def test_two_near_choices_suggest_nothing() -> None:
    assert suggestion("pach", ("patch", "peach")) is None
    assert did_you_mean("nh", ("nH", "H")) == " (did you mean 'nH'?)"


@pytest.mark.parametrize(
    ("argv", "hint"),
    [(["explore", "--object", "Cube"], "'cube'"), (["explore", "--strategy", "papr"], "'paper'"),
     (["fit", "c.npz", "--method", "nh"], "'nH'"), (["suite", "run", "fitv1", "--out", "x"],
     "'fit-v1'"), (["explore", "--hand", "shadw"], "'shadow'"), (["fti"], "'fit'"),
     (["policies", "evaluate", "--policy", "randm"], "'random'")],
)  # fmt: skip
def test_the_command_line_suggests(capsys, tmp_path, monkeypatch, argv, hint) -> None:  # noqa: ANN001
    monkeypatch.chdir(tmp_path)
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own errors exit from the parser
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and f"(did you mean {hint}?)" in err
