"""Suite files: the shipped suites load and are what their descriptions say; bad files are named."""

from __future__ import annotations

from pathlib import Path

import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.suites import list_suites, load_suite, suite_names
from hapticsim.suites.cases import _seeds

SMALL = """
name = "tiny"
version = 2
kind = "fit"
description = "two cases"
seed = 5
id = "{body}/{method}/run={run}"
group = "{body}"

[[grid]]
body = "cube"
method = ["LS", "nH"]
noise = 0.05
runs = 1
"""


def _write(tmp_path: Path, text: str, name: str = "tiny-v2.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_the_shipped_suites() -> None:
    assert suite_names() == ("explore-v1", "fit-v1", "fit-v2", "objects-v1", "policy-v1")
    suites = {s.id: s for s in list_suites()}
    # fit-v1: 5 bodies x 4 methods x 4 noise levels x 8 runs (fit-v2: 5 methods, nML added);
    # explore-v1: 4 x 4 strategies x 3 noise levels x 3 runs; policy-v1: 3 policies x 2 object
    # sets x 2 backends x 10 runs; objects-v1: (3 objects x 2 strategies + random composites x 1)
    # x 2 methods x 5 runs.
    assert {k: len(s.cases) for k, s in suites.items()} == {
        "fit-v1": 640, "fit-v2": 800, "explore-v1": 144, "objects-v1": 70, "policy-v1": 120,
    }  # fmt: skip
    assert {k: s.kind for k, s in suites.items()} == {
        "fit-v1": "fit", "fit-v2": "fit", "explore-v1": "explore", "objects-v1": "objects",
        "policy-v1": "policy",
    }  # fmt: skip
    for suite in suites.values():
        ids = [c.id for c in suite.cases]
        assert len(set(ids)) == len(ids)
        sizes = [sum(c.group == g for c in suite.cases) for g in suite.groups]
        # A one-sided paired Wilcoxon test on n cases can reach p < 0.01 only for n >= 7.
        assert min(sizes) >= 9, (suite.id, sizes)
    fit = suites["fit-v1"]
    assert {c.params["body"] for c in fit.cases} >= {"cube", "random_tapered"}
    assert {c.params["noise"] for c in fit.cases} == {0.0, 0.02, 0.05, 0.1}
    assert {c.params["count"] for c in fit.cases} == {150}
    # fit-v2 is fit-v1 plus nML: the shared cases are the same cases (ids, parameters, seeds)
    v2 = {c.id: c for c in suites["fit-v2"].cases}
    assert all(v2[c.id].items == c.items and v2[c.id].seed == c.seed for c in fit.cases)
    assert {c.params["method"] for c in v2.values()} - {"LS", "H", "nLS", "nH"} == {"nML"}


def test_cases_that_differ_in_method_share_their_data_seed() -> None:
    suite = load_suite("fit-v1")
    by_id = {c.id: c for c in suite.cases}
    ls, nh = by_id["cube/LS/noise=0.1/run=3"], by_id["cube/nH/noise=0.1/run=3"]
    assert _seeds(ls)[0].spawn_key == _seeds(nh)[0].spawn_key  # same contacts
    assert _seeds(ls)[1].spawn_key != _seeds(nh)[1].spawn_key  # own fit randomness
    other_run = by_id["cube/LS/noise=0.1/run=4"]
    assert _seeds(ls)[0].spawn_key != _seeds(other_run)[0].spawn_key


def test_policies_of_one_run_meet_the_same_episode() -> None:
    suite = load_suite("policy-v1")
    by_id = {c.id: c for c in suite.cases}
    a, b = by_id["random/paper/mujoco/run=2"], by_id["uncertainty/paper/mujoco/run=2"]
    assert _seeds(a)[0].spawn_key == _seeds(b)[0].spawn_key


def test_a_suite_file_by_path_and_case_selection(tmp_path: Path) -> None:
    suite = load_suite(_write(tmp_path, SMALL))
    assert suite.id == "tiny-v2" and suite.seed == 5
    assert [c.id for c in suite.cases] == ["cube/LS/run=0", "cube/nH/run=0"]
    assert suite.cases[0].params == {
        "body": "cube", "method": "LS", "noise": 0.05, "count": 150, "pattern": "paper",
        "budget": "default", "run": 0,
    }  # fmt: skip
    assert [c.id for c in suite.select("*/nH/*")] == ["cube/nH/run=0"]
    with pytest.raises(InvalidInputError, match="matches no case of tiny-v2"):
        suite.select("sphere/*")


def test_unknown_suite_lists_the_suites() -> None:
    shipped = "explore-v1, fit-v1, fit-v2, objects-v1, policy-v1"
    with pytest.raises(InvalidInputError, match=f"the suites are {shipped}"):
        load_suite("fit-v9")


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("seed = 5", "seed = 5\ncolour = 1"), r"unknown key\(s\) \['colour'\]"),
        (('kind = "fit"', 'kind = "fitting"'),
         "`kind` must be one of fit, explore, objects, policy"),  # fmt: skip
        (('method = ["LS", "nH"]', 'method = ["LS", "XX"]'), "grid 1: `method` must be one of LS"),
        (('method = ["LS", "nH"]', 'method = ["LS", "LS"]'), "lists a value twice"),
        (('method = ["LS", "nH"]', "method = []"), "`method` is an empty list"),
        (("noise = 0.05", "noise = 2.0"), r"`noise` must be a number in \[0, 1\]"),
        (("noise = 0.05\n", ""), "missing `noise`"),
        (("runs = 1", "runs = 0"), "`runs` must be an integer >= 1"),
        (("runs = 1", "runs = 1\nstrategy = 'paper'"), "`strategy` is not a parameter of fit"),
        (('id = "{body}/{method}/run={run}"', 'id = "{body}/run={run}"'), "two cases have the id"),
        (('group = "{body}"', 'group = "{shape}"'), r"names \{shape\}"),
        (('name = "tiny"', 'name = "Tiny!"'), "`name` must be lower-case"),
        (("version = 2", "version = 0"), "`version` must be an integer >= 1"),
        (("[[grid]]", "[[grids]]"), r"unknown key\(s\) \['grids'\]"),
        (("seed = 5", 'seed = "five"'), "`seed` must be an integer >= 0"),
        (('kind = "fit"', 'kind = "fit'), "cannot read suite file"),
    ],
)
def test_bad_suite_files_are_named(tmp_path: Path, change: tuple[str, str], message: str) -> None:
    old, new = change
    assert old in SMALL
    with pytest.raises(InvalidInputError, match=message):
        load_suite(_write(tmp_path, SMALL.replace(old, new)))
