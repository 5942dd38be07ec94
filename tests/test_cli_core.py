"""`hapticsim synth` and `hapticsim score` (SPEC §6)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from hapticsim.cli import main
from hapticsim.data.bodies import get_body
from hapticsim.data.io import write_contacts
from hapticsim.data.synthetic import paper_dataset
from hapticsim.geometry import Superquadric

REPO = Path(__file__).resolve().parents[1]
SPEC_KEYS = {"alpha", "beta", "epsilon", "iou", "chamfer"}


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def assert_bad_input(code: int, out: str, err: str, command: str, match: str) -> None:
    assert code == 2
    assert out == ""  # stdout carries only JSON, and there is none
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"hapticsim {command}: error: ")
    assert match in lines[0]
    assert "Traceback" not in err


# ----------------------------------------------------------------------------- synth
def test_synth_writes_contacts_and_truth(capsys, tmp_path: Path) -> None:
    out, truth = tmp_path / "c.npz", tmp_path / "t.json"
    code, stdout, _ = run(
        capsys, "synth", "tapered_box", "--seed", "3", "--out", str(out), "--truth-out", str(truth)
    )
    assert code == 0
    report = json.loads(stdout)
    assert report["count"] == 150 and report["contacts"] == str(out)
    assert Superquadric.from_dict(report["truth"]) == get_body("tapered_box")
    assert Superquadric.from_json(truth) == get_body("tapered_box")
    with np.load(out) as data:
        assert set(data.files) == {"points", "normals", "points_clean", "normals_clean", "pattern"}
        assert data["points"].shape == (150, 3)
        first = {k: data[k] for k in data.files}
    # Same seed, same file contents bit for bit.
    again = tmp_path / "again.npz"
    assert main(["synth", "tapered_box", "--seed", "3", "--out", str(again)]) == 0
    with np.load(again) as data:
        assert all(np.array_equal(first[k], data[k]) for k in first)


def test_synth_csv_and_json_body(capsys, tmp_path: Path) -> None:
    body = tmp_path / "body.json"
    sq = Superquadric(a=(0.02, 0.03, 0.04), eps=(0.6, 0.9), taper=(0.2, -0.1))
    sq.to_json(body)
    out = tmp_path / "c.csv"
    code, stdout, _ = run(
        capsys, "synth", str(body), "--count", "40", "--noise", "0", "--out", str(out)
    )
    assert code == 0 and json.loads(stdout)["count"] == 40
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    assert table.shape == (40, 6)
    np.testing.assert_allclose(sq.inside_outside(table[:, :3]), 1.0, atol=1e-9)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["sphere"], "tapered_box, cube, cylinder, ellipsoid"),
        (["cube", "--count", "5"], "`count`"),
        (["cube", "--count", "1000001"], "`count` must be <= 1,000,000"),  # no MemoryError
        (["cube", "--noise", "-1"], "`noise`"),
        (["cube", "--noise", "nan"], "`noise`"),
        (["cube", "--out", "c.txt"], "must end in"),
        (["cube", "--out", "missing/c.npz"], "does not exist"),
        (["cube", "--truth-out", "missing/t.json"], "does not exist"),
        (["missing.json"], "not found"),
        (["bad.json"], "`eps`"),
    ],
)
def test_synth_bad_input(capsys, tmp_path: Path, monkeypatch, args: list, match: str) -> None:
    monkeypatch.chdir(tmp_path)
    Path("bad.json").write_text(json.dumps(GOOD | {"eps": [0.01, 1]}))
    code, out, err = run(capsys, "synth", *args)
    assert_bad_input(code, out, err, "synth", match)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.json"]  # nothing written


def test_bad_command_line_is_one_line_and_status_2(capsys) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["synth", "cube", "--seed", "-1"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "--seed" in err


# ----------------------------------------------------------------------------- score
def test_score_prints_the_spec_json(capsys, tmp_path: Path) -> None:
    truth = get_body("cube")
    estimate = truth.replace(a=(0.031, 0.029, 0.03), eps=(0.2, 0.15))
    truth.to_json(tmp_path / "truth.json")
    (tmp_path / "fit.json").write_text(
        json.dumps({"superquadric": estimate.to_dict(), "method": "nH", "eof": 1e-6})
    )
    code, stdout, err = run(
        capsys, "score", str(tmp_path / "fit.json"), str(tmp_path / "truth.json")
    )
    assert code == 0 and err == ""
    result = json.loads(stdout)
    assert set(result) == SPEC_KEYS | {"volume_method"}
    assert result["epsilon"] == pytest.approx(result["alpha"] + result["beta"])
    assert 0 < result["alpha"] < 0.2 and 0 < result["beta"] < 0.2
    code, same, _ = run(capsys, "score", str(tmp_path / "truth.json"), str(tmp_path / "truth.json"))
    assert json.loads(same)["alpha"] == 0.0 and json.loads(same)["iou"] == 1.0


GOOD = {
    "a": [0.03, 0.04, 0.05],
    "eps": [0.1, 0.1],
    "taper": [0, 0],
    "rotation": [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
    "center": [0, 0, 0],
}


@pytest.mark.parametrize(
    ("content", "match"),
    [
        (None, "not found"),
        ("", "empty"),
        ("{", "not valid JSON"),
        ("[1, 2]", "JSON object"),
        ('{"a": [0.03, 0.04, 0.05]}', "missing"),
        (json.dumps(GOOD | {"a": [0.03, -0.04, 0.05]}), "`a`"),
        (json.dumps(GOOD).replace("0.03", "NaN"), "NaN"),
        (json.dumps({k: v for k, v in GOOD.items() if k != "center"}), "required key(s) center"),
        (json.dumps(GOOD | {"a": [0.03, 0.04]}), "`a`"),
        (json.dumps(GOOD | {"eps": [0.1, 2.5]}), "`eps`"),
        (json.dumps(GOOD | {"taper": [1.5, 0.0]}), "`taper`"),
        (json.dumps(GOOD | {"rotation": [[1, 0, 0], [0, 1, 0], [0, 0, 2]]}), "`rotation`"),
        (json.dumps(GOOD | {"rotation": [[1, 0, 0], [0, 1, 0], [0, 0, -1]]}), "`rotation`"),
        (json.dumps(GOOD | {"center": "origin"}), "`center`"),
        (json.dumps({"superquadric": 3}), "JSON object"),
        (b"\xff\xfe\x00{", "UTF-8"),
    ],
)
def test_score_bad_input(capsys, tmp_path: Path, content, match: str) -> None:
    get_body("cube").to_json(tmp_path / "truth.json")
    bad = tmp_path / "estimate.json"
    if isinstance(content, bytes):
        bad.write_bytes(content)
    elif content is not None:
        bad.write_text(content)
    for argv in (["score", str(bad), str(tmp_path / "truth.json")],
                 ["score", str(tmp_path / "truth.json"), str(bad)]):  # fmt: skip
        code, out, err = run(capsys, *argv)
        assert_bad_input(code, out, err, "score", match)


def test_console_process_reports_bad_input_without_traceback(tmp_path: Path) -> None:
    env = os.environ | {"PYTHONPATH": str(REPO)}
    proc = subprocess.run(
        [sys.executable, "-m", "hapticsim.cli", "score", str(tmp_path / "no.json"), "x.json"],
        capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120,
    )  # fmt: skip
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert len(proc.stderr.splitlines()) == 1 and "not found" in proc.stderr


_RUN_WITH_HANDLER = """
import atexit, sys
atexit.register(lambda: print("exit handler ran", file=sys.stderr))
from hapticsim.cli import run
sys.argv = ["hapticsim", *sys.argv[1:]]
run()
"""


def test_the_console_script_ends_quickly_but_keeps_its_contract(tmp_path: Path) -> None:
    # cli.run leaves through os._exit: exit handlers still run, stdout is complete, the status
    # is main's (a fit's JSON on stdout; bad input: status 2 and one line)
    rng = np.random.default_rng(0)
    d = rng.normal(size=(40, 3))
    np.savez(tmp_path / "c.npz", points=0.03 * d / np.linalg.norm(d, axis=1, keepdims=True))
    env = os.environ | {"PYTHONPATH": str(REPO)}
    good = subprocess.run(
        [sys.executable, "-c", _RUN_WITH_HANDLER, "fit", "c.npz", "--method", "LS"],
        capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300,
    )  # fmt: skip
    assert good.returncode == 0, good.stderr
    assert json.loads(good.stdout)["method"] == "LS"
    assert good.stderr.splitlines()[-1] == "exit handler ran"
    bad = subprocess.run(
        [sys.executable, "-c", _RUN_WITH_HANDLER, "fit", "missing.npz"],
        capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300,
    )  # fmt: skip
    assert (bad.returncode, bad.stdout) == (2, "")
    assert bad.stderr.splitlines() == [
        "hapticsim fit: error: contacts file not found: missing.npz", "exit handler ran"
    ]


def test_huge_coordinates_end_in_one_line_not_a_linalg_error(tmp_path: Path) -> None:
    # issue 14: contacts at 1e300 m ended in a LinAlgError traceback after overflow warnings
    rng = np.random.default_rng(0)
    np.savez(tmp_path / "c.npz", points=rng.normal(size=(50, 3)) * 1e300,
             normals=rng.normal(size=(50, 3)))  # fmt: skip
    env = os.environ | {"PYTHONPATH": str(REPO)}
    proc = subprocess.run(
        [sys.executable, "-m", "hapticsim.cli", "fit", "c.npz", "--out", "fit.json"],
        capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120,
    )  # fmt: skip
    assert (proc.returncode, proc.stdout) == (2, "")
    assert proc.stderr.splitlines() == [
        "hapticsim fit: error: `points` must have coordinates within +-1e+06 m, got 2.37e+300 "
        "(metres expected)"
    ]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.npz"]


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        # found by tests/fuzz: --runs 1e20 built a trial list until the machine ran out of memory
        (["reproduce", "fig4", "--runs", str(10**20)], "`runs` must be <= 100,000"),
        (["fit", "c.npz", "--budget", str(2**70)], "`budget` must be <= 1,000,000,000"),
        (["explore", "--count", "1000001"], "`count` must be <= 1,000,000"),
        (["explore", "--seed", str(2**70)], "--seed: must be an integer in"),
    ],
)
def test_huge_integer_arguments_are_refused_up_front(
    capsys, tmp_path: Path, monkeypatch, argv: list, match: str
) -> None:
    monkeypatch.chdir(tmp_path)
    write_contacts("c.npz", paper_dataset(get_body("cube"), rng=0))
    try:
        code = main([*argv, "--out", "out"])
    except SystemExit as exc:  # argparse's own checks
        code = exc.code
    out, err = capsys.readouterr()
    assert_bad_input(code, out, err, argv[0], match)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.npz"]


def test_fit_takes_several_files_and_checks_them_all_first(capsys, tmp_path: Path) -> None:
    from hapticsim.data import get_body

    files = []
    for seed in (0, 1):
        c = paper_dataset(get_body("cube"), noise=0.02, rng=seed)
        path = tmp_path / f"c{seed}.npz"
        np.savez(path, points=c.points, normals=c.normals)
        files.append(str(path))
    code, out, err = run(capsys, "fit", *files, "--budget", "400", "--out", str(tmp_path / "f"))
    assert code == 0
    results = json.loads(out)
    assert [r["contacts"] for r in results] == files
    assert all(r["seconds"] < 5 and "setup_seconds" in r for r in results)
    assert json.loads((tmp_path / "f").read_text()) == results
    one = json.loads(run(capsys, "fit", files[0], "--budget", "400")[1])
    assert "contacts" not in one and one["superquadric"] == results[0]["superquadric"]
    code, out, err = run(capsys, "fit", files[0], str(tmp_path / "none.npz"))
    assert_bad_input(code, out, err, "fit", "none.npz")
