"""The benchmark protocol: tasks and splits, a run's per-touch metrics, the leaderboard, bad
input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from hapticsim.bench import get_task, task_names
from hapticsim.bench.report import leaderboard, write_report
from hapticsim.bench.runner import METRICS, run_bench
from hapticsim.cli import main
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import solid_from_dict


def test_tasks_are_named_and_their_splits_fixed() -> None:
    names = task_names()
    assert len(names) == len(set(names)) == 60 and "paper/exact/analytic/t20" in names
    assert "holed/vision/mujoco/t50" in names and "pybullet/exact/analytic/t20" in names
    task = get_task("random/vision/mujoco/t50")
    assert task.name == "random/vision/mujoco/t50"
    assert task.env_kwargs()["skin"] == "vision" and task.env_kwargs()["touch_budget"] == 50
    dev, test = task.seeds("dev", 30), task.seeds("test", 30)
    assert dev == get_task("paper/exact/analytic/t20").seeds("dev", 30)  # every family alike
    assert not set(dev) & set(test) and test == task.seeds("test", 30)
    with pytest.raises(InvalidInputError, match="did you mean 'paper/exact/analytic/t20'"):
        get_task("paper/exact/analytic/t2")
    with pytest.raises(InvalidInputError, match="split"):
        task.seeds("train", 3)


@pytest.fixture(scope="module")
def results() -> dict:
    return run_bench("paper/exact/analytic/t20", "uncertainty", 2, workers=1, progress=False)


def test_a_run_scores_every_touch_and_agrees_with_an_independent_score(results: dict) -> None:
    from hapticsim.metrics import surface_score, volume_overlap

    assert results["protocol"] == "hapticsim-bench/2" and results["seeds"] == [1_000_000,
                                                                                 1_000_001]
    assert {"command", "git", "machine", "packages", "date"} <= set(results["manifest"])
    diffs_iou, diffs_f = [], []
    for episode in results["episodes"]:
        touches = episode["touches"]
        assert len(touches) == 20 and set(METRICS) <= set(touches[0])
        truth = solid_from_dict(episode["truth"])
        for row in touches[::5]:
            if row["estimate"] is None:
                assert row["iou"] == 0.0 and row["epsilon"] == 1.0
                continue
            estimate = solid_from_dict(row["estimate"])
            # other seeds, more samples: the bench's own sampling error is what differs
            # (IoU: 100 000 points, std <= 0.002; F-score: 5 000 surface points, std <= 0.007)
            overlap = volume_overlap(estimate, truth, samples=200_000, rng=99)
            surface = surface_score(estimate, truth, samples=20_000, rng=99)
            diffs_iou.append(abs(row["iou"] - overlap.iou))
            diffs_f.append(abs(row["f_score_2.5"] - surface.f_score[1]))
    assert diffs_iou and np.mean(diffs_iou) <= 0.01 and max(diffs_iou) <= 0.02
    assert np.mean(diffs_f) <= 0.01 and max(diffs_f) <= 0.03
    s = results["summary"]["iou"]
    assert len(s["mean_curve"]) == 20 and len(s["area"]) == 2
    assert s["area_ci95"][0] <= s["area_mean"] <= s["area_ci95"][1]


def test_the_leaderboard_pairs_results_on_their_seeds(results: dict, tmp_path: Path) -> None:
    text = leaderboard([results, results])
    assert "## paper/exact/analytic/t20" in text and "| uncertainty | env-nH | test | 2 |" in text
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    a.write_text(json.dumps(results))
    b.write_text(json.dumps(results))
    files = write_report([a, b], tmp_path / "board")
    assert files["markdown"].read_text() == leaderboard([results, results])
    page = files["html"].read_text()
    assert page.count("<svg") == 1 and "</svg>" in page  # the curves, inline


def test_bad_input_is_one_line_and_no_file(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "r.json"
    cases = [
        (["bench", "run", "nope/exact/analytic/t20", "--policy", "random"], "unknown task"),
        (["bench", "run", "paper/exact/analytic/t20", "--policy", "no_such_lab:Policy"],
         "no_such_lab"),
        (["bench", "run", "paper/exact/analytic/t20", "--policy", "random", "--estimator",
          "nH"], "`estimator` must be one of"),
        (["bench", "run", "paper/exact/analytic/t20", "--policy", "random", "--estimator",
          "no_such_lab:fit"], "no_such_lab"),
        (["bench", "run", "paper/exact/analytic/t20", "--policy", "random", "--estimator",
          "tests.bench.test_bench:failing_fit", "--episodes", "1", "--workers", "1"],
         "the estimator tests.bench.test_bench:failing_fit failed on"),
        (["bench", "run", "paper/exact/analytic/t20", "--policy",
          "tests.bench.test_bench:NanPolicy", "--episodes", "1", "--workers", "1"], "non-finite"),
    ]  # fmt: skip
    for argv, words in cases:
        assert main([*argv, "--out", str(out), "--quiet"] if argv[1] == "run" else argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and words in err[0], err
        assert not out.exists()


def test_fitted_estimators_score_the_same_touches_at_the_stated_points(results: dict) -> None:
    # nML and a lab's fitter on the contacts of env-nH's episodes: the same touches, scored at
    # 5, 10 and 20 only; the environment's multi schedule is scored at every touch
    fitted = run_bench("paper/exact/analytic/t20", "uncertainty", 2, estimator="nML",
                       workers=1, progress=False)  # fmt: skip
    lab = run_bench("paper/exact/analytic/t20", "uncertainty", 2,
                    estimator="tests.suites.lab_plugins:nh_fit", workers=1, progress=False)
    assert fitted["scored_touches"] == lab["scored_touches"] == [5, 10, 20]
    assert results["scored_touches"] == list(range(1, 21))
    for run in (fitted, lab):
        for mine, env in zip(run["episodes"], results["episodes"], strict=True):
            assert [t["contacts"] for t in mine["touches"]] == [
                t["contacts"] for t in env["touches"]]  # the same touches
            assert mine["touches"][5]["iou"] is None and mine["touches"][4]["iou"] is not None
            truth = solid_from_dict(mine["truth"])
            row = mine["touches"][19]
            assert row["fit_wall_s"] > 0 and row["iou"] > 0.5
            from hapticsim.metrics import volume_overlap

            overlap = volume_overlap(solid_from_dict(row["estimate"]), truth, samples=200_000,
                                     rng=5)  # fmt: skip
            assert abs(row["iou"] - overlap.iou) <= 0.02
        curve = run["summary"]["iou"]["mean_curve"]
        assert curve[5] is None and curve[19] is not None
    text = leaderboard([results, fitted, lab])
    assert "| uncertainty | nML (at 5, 10, 20) | test | 2 |" in text
    row = [line for line in text.splitlines() if "nML" in line][0]
    assert row.rstrip().endswith("(2) |")  # paired on the touches both scored
    union = run_bench("paper/exact/analytic/t20", "uncertainty", 1, estimator="env-multi",
                      workers=1, progress=False)  # fmt: skip
    scored = [t for t in union["episodes"][0]["touches"] if t["estimate"] is not None]
    assert len(scored) >= 15 and all("parts" in t["estimate"] for t in scored)


def failing_fit(points: np.ndarray, normals: np.ndarray) -> None:
    """A lab's estimator that fails (for the bad-input test)."""
    raise RuntimeError("no convergence\n(as a lab's fitter might say)")


class NanPolicy:
    """A lab's policy that returns NaN (for the bad-input test)."""

    def __init__(self, env: object, rng: object = None) -> None:
        self.shape = env.action_space.shape  # type: ignore[attr-defined]

    def reset(self, rng: object = None) -> None:  # noqa: D102
        pass

    def __call__(self, obs: object) -> np.ndarray:
        return np.full(self.shape, np.nan, np.float32)


def test_the_pybullet_family_scores_mesh_truths() -> None:
    # pybullet_data's procedural objects (extra `objects`): a mesh truth, scored per touch by the
    # generic paths; the saved estimates rescored independently
    pytest.importorskip("pybullet_data")
    from hapticsim.bench.runner import EpisodeTask, run_episode
    from hapticsim.metrics import volume_overlap

    task = "pybullet/exact/analytic/t20"
    episode = run_episode(EpisodeTask(task, "uncertainty", 1_000_000))
    assert episode["truth"] is None  # a mesh is not stored; the seed redraws it
    from hapticsim.envs.haptic_explore_tactile_v0 import make_v0

    env = make_v0(**get_task(task).env_kwargs())
    env.reset(seed=1_000_000)
    truth = env.unwrapped.truth
    env.close()
    assert truth.kind == "mesh" and 0.05 < np.ptp(truth.bounds, axis=0).max() < 0.2  # 9-15 cm
    last = episode["touches"][-1]
    # properties, not one trajectory's figure (the board's 30 episodes: final IoU 0.59 on average)
    assert 0 < last["iou"] <= 1 and last["chamfer_mm"] > 0 and 0 < last["normal_consistency"] <= 1
    overlap = volume_overlap(solid_from_dict(last["estimate"]), truth, samples=200_000, rng=3)
    assert abs(last["iou"] - overlap.iou) <= 0.02


def test_a_missing_gpis_extra_is_said_before_any_episode(monkeypatch) -> None:
    # GPIS without scikit-image was scored as "cannot fit yet" at every touch (IoU 0); now one line
    import sys

    monkeypatch.setitem(sys.modules, "skimage", None)
    monkeypatch.setitem(sys.modules, "skimage.measure", None)
    with pytest.raises(InvalidInputError, match="scikit-image"):
        run_bench("paper/exact/analytic/t20", "random", 1, estimator="gpis", progress=False)


def test_the_pybullet_family_draws_again_past_what_is_refused() -> None:
    # random/168 (damaged) and random/019 (two pieces) are refused as read; a draw that lands on
    # them is drawn again, the same way for the same seed
    pytest.importorskip("pybullet_data")
    from hapticsim.data.distributions import ObjectDistribution

    family = ObjectDistribution(kind="random_pybullet")

    class Landing:  # a generator whose first draws are refused objects
        def __init__(self) -> None:
            self.draws = iter([168, 19, 1])

        def integers(self, high: int) -> int:
            return next(self.draws)

    landing = Landing()
    solid = family.sample(landing)
    assert next(landing.draws, None) is None  # all three draws taken: two refused, then 001
    assert solid.kind == "mesh" and np.allclose(solid.centroid, 0.0, atol=1e-9)
    a = family.sample(np.random.default_rng(4))
    b = family.sample(np.random.default_rng(4))
    assert a.volume == b.volume


def test_the_pybullet_family_without_pybullet_is_one_line(monkeypatch) -> None:
    import sys

    monkeypatch.setitem(sys.modules, "pybullet_data", None)
    with pytest.raises(InvalidInputError, match="pip install 'hapticsim\\[objects\\]'"):
        run_bench("pybullet/exact/analytic/t20", "random", 1, progress=False)
