"""``hapticsim suite report``: the HTML page of a results file, against a baseline."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest

from hapticsim.suites.html_report import write_report
from tests.test_cli_core import assert_bad_input, run

BASELINE = Path(__file__).resolve().parents[2] / "docs" / "suites" / "fit-v1.json"
GROUPS = ("cube/nH", "ellipsoid/nH")


def _two_groups() -> dict:
    """fit-v1's baseline cut to two groups (a results file the comparison accepts)."""
    data = json.loads(BASELINE.read_text())
    data["cases"] = [c for c in data["cases"] if c["group"] in GROUPS]
    data["groups"] = {g: data["groups"][g] for g in GROUPS}
    return data


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> tuple[Path, Path]:  # noqa: ANN001
    root = tmp_path_factory.mktemp("report")
    base = _two_groups()
    worse = copy.deepcopy(base)
    for case in worse["cases"]:
        if case["group"] == "cube/nH":
            case["metrics"]["epsilon"] += 0.05  # every cube case 0.05 worse: a regression
    (root / "base.json").write_text(json.dumps(base))
    (root / "worse.json").write_text(json.dumps(worse))
    return root / "base.json", root / "worse.json"


def test_the_report_shows_the_regression_and_a_picture_per_group(files, tmp_path: Path) -> None:  # noqa: ANN001
    base, worse = files
    index = write_report(worse, tmp_path / "rep", baseline=base)
    page = index.read_text()
    assert "REGRESSION in 1 group(s): cube/nH" in page
    assert page.count("<tr class='worse'>") == 1 and page.count("<tr class='same'>") == 1
    assert "+0.0500" in page  # the change of the cube's mean epsilon
    pictures = sorted(p.name for p in (tmp_path / "rep").glob("*.png"))
    assert pictures == ["group00-cube_nH.png", "group01-ellipsoid_nH.png"]
    for name in pictures:
        assert f"src='{name}'" in page
        assert (tmp_path / "rep" / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "http://" not in page and "https://" not in page  # opens offline


def test_a_report_without_baseline_has_no_comparison(files, tmp_path: Path) -> None:  # noqa: ANN001
    page = write_report(files[0], tmp_path / "rep").read_text()
    assert "Against the baseline" not in page and "<h2>Groups</h2>" in page


def test_suite_report_command_and_its_bad_input(capsys, files, tmp_path: Path) -> None:  # noqa: ANN001
    base, worse = files
    code, out, err = run(capsys, "suite", "report", str(worse), "--baseline", str(base),
                         "--out", str(tmp_path / "r"))  # fmt: skip
    assert code == 0 and json.loads(out)["report"].endswith("index.html")
    (tmp_path / "file").write_text("x")
    (tmp_path / "bad.json").write_text("{}")
    for argv, match in [
        ([str(worse), "--out", str(tmp_path / "file")], "not a directory"),
        ([str(worse), "--out", str(tmp_path / "no" / "r")], "does not exist"),
        ([str(tmp_path / "bad.json"), "--out", str(tmp_path / "r2")], "bad.json"),
        ([str(tmp_path / "missing.json"), "--out", str(tmp_path / "r3")], "missing.json"),
    ]:
        assert_bad_input(*run(capsys, "suite", "report", *argv), "suite report", match)
    assert not (tmp_path / "r2").exists() or not any((tmp_path / "r2").iterdir())
