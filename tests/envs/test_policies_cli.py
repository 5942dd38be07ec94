"""``hapticsim policies evaluate``: the JSON of SPEC §6, pairing by seed, bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hapticsim.cli import main
from hapticsim.envs.estimator import FitSchedule
from hapticsim.envs.evaluation import compare_policies, evaluate_policy
from tests.envs.test_learned import random_actor

FAST_FIT = FitSchedule(full_budget=1500, refine_budget=200, full_every=10)


def run_cli(capsys, *args: str) -> tuple[int, str, str]:  # noqa: ANN001
    try:
        code = main(["policies", "evaluate", *args])
    except SystemExit as exc:  # argparse's errors
        code = int(exc.code or 0)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_evaluate_prints_the_spec_json(capsys) -> None:  # noqa: ANN001
    code, out, _ = run_cli(
        capsys, "--policy", "random", "--episodes", "2", "--touches", "3", "--seed", "4",
        "--workers", "1", "--quiet",
    )  # fmt: skip
    assert code == 0
    data = json.loads(out)  # stdout holds only the JSON
    assert set(data) == {
        "policy", "backend", "objects", "episodes", "touches", "seed", "epsilon",
        "episodes_epsilon",
    }  # fmt: skip
    assert (data["policy"], data["backend"], data["objects"]) == ("random", "analytic", "random")
    assert (data["episodes"], data["touches"], data["seed"]) == (2, 3, 4)
    assert set(data["epsilon"]) == {"mean", "std", "median"}
    assert all(len(v) == 3 for v in data["epsilon"].values())
    table = np.array(data["episodes_epsilon"])
    assert table.shape == (2, 3)
    np.testing.assert_allclose(data["epsilon"]["mean"], table.mean(axis=0))
    np.testing.assert_allclose(data["epsilon"]["median"], np.median(table, axis=0))
    np.testing.assert_allclose(data["epsilon"]["std"], table.std(axis=0, ddof=1))


def test_same_seed_same_objects_for_every_policy_and_any_worker_count(tmp_path) -> None:  # noqa: ANN001
    weights = random_actor().save(tmp_path / "w.npz")
    cmp = compare_policies(
        ["random", f"learned:{weights}", "uncertainty"], ["random"], episodes=2, seed=7,
        workers=1, progress=False, fresh_envs=True, backend="analytic", touch_budget=2,
        fit=FAST_FIT,
    )  # fmt: skip
    truths = {}
    for r in cmp.episodes:
        truths.setdefault(r["episode"], []).append(json.dumps(r["truth"], sort_keys=True))
    for same in truths.values():
        assert len(same) == 3 and len(set(same)) == 1
    assert len({t[0] for t in truths.values()}) == 2
    one = evaluate_policy("uncertainty", episodes=2, touches=2, seed=7, workers=1,
                          progress=False, fit=FAST_FIT)  # fmt: skip
    two = evaluate_policy("uncertainty", episodes=2, touches=2, seed=7, workers=2,
                          progress=False, fit=FAST_FIT)  # fmt: skip
    assert one == two
    np.testing.assert_array_equal(one["episodes_epsilon"], cmp.epsilon("uncertainty", "random"))


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--policy", "greedy"],
         "information, learned, learned-touch or 'learned:PATH'"),
        (["--policy", "learned:/no/such/file.npz"], "does not exist"),
        (["--policy", "random", "--episodes", "0"], "--episodes: must be an integer >= 1"),
        (["--policy", "random", "--objects", "cubes"], "invalid choice: 'cubes'"),
        (["--policy", "random", "--seed", "-1"], "--seed: must be an integer in [0,"),
        (["--policy", "random", "--noise", "3"], "`noise` must be in [0.0, 1.0], got 3.0"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(capsys, args: list[str], message: str) -> None:  # noqa: ANN001
    code, out, err = run_cli(capsys, *args, "--quiet")
    assert code == 2
    assert out == ""
    assert message in err
    assert len(err.strip().splitlines()) == 1
    assert "Traceback" not in err


def test_weights_for_another_env_version_are_refused_on_the_command_line(capsys, tmp_path) -> None:  # noqa: ANN001
    path = random_actor(env_id="hapticsim/HapticExplore-v0", obs_dim=40).save(tmp_path / "old.npz")
    code, out, err = run_cli(capsys, "--policy", f"learned:{path}", "--quiet")
    assert code == 2 and out == ""
    assert "trained for hapticsim/HapticExplore-v0 with observation size 40" in err
    assert "hapticsim/HapticExploreCompact-v0" in err


def test_noise_reaches_the_environment(capsys) -> None:  # noqa: ANN001
    runs = {}
    for noise in ("0", "0.1"):
        code, out, _ = run_cli(capsys, "--policy", "random", "--episodes", "1", "--touches", "6",
                               "--workers", "1", "--noise", noise, "--quiet")  # fmt: skip
        assert code == 0
        runs[noise] = json.loads(out)["episodes_epsilon"][0]
    assert runs["0"] != runs["0.1"]


def test_tactile_sensing_runs_tactile_actors_and_exact_refuses_them(capsys, tmp_path) -> None:  # noqa: ANN001
    from hapticsim.envs.haptic_explore_touch_v0 import TACTILE_ENV_ID, TACTILE_SETS
    from tests.envs.test_haptic_explore_touch_v0 import random_set_actor

    path = random_set_actor(env_id=TACTILE_ENV_ID, sets=TACTILE_SETS).save(tmp_path / "t.npz")
    code, out, err = run_cli(capsys, "--policy", f"learned:{path}", "--quiet")
    assert code == 2 and out == "" and "feels the pads' images" in err
    runs = {}
    for sensing in ("exact", "tactile"):
        code, out, _ = run_cli(capsys, "--policy", "random", "--episodes", "1", "--touches", "8",
                               "--workers", "1", "--sensing", sensing, "--quiet")  # fmt: skip
        assert code == 0
        runs[sensing] = json.loads(out)["episodes_epsilon"][0]
    assert runs["exact"] != runs["tactile"]  # the pads' estimates are not the exact contacts
    code, out, _ = run_cli(capsys, "--policy", "random", "--episodes", "1", "--touches", "8",
                           "--workers", "1", "--sensing", "tactile", "--skin", "capacitive",
                           "--quiet")  # fmt: skip
    assert code == 0 and json.loads(out)["episodes_epsilon"][0] != runs["tactile"]
    code, out, err = run_cli(capsys, "--policy", "random", "--skin", "vision", "--quiet")
    assert code == 2 and "--skin is for --sensing tactile" in err
    code, out, _ = run_cli(capsys, "--policy", f"learned:{path}", "--episodes", "1", "--touches",
                           "3", "--workers", "1", "--sensing", "tactile", "--quiet")  # fmt: skip
    assert code == 0 and len(json.loads(out)["episodes_epsilon"][0]) == 3
