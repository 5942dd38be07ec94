"""Explore runs shared by the viewer's tests: 40 contacts for the default tests, 150 (the viewer's
bar is stated for 150) for the browser tests behind the slow marker."""

from __future__ import annotations

from pathlib import Path

import pytest

from hapticsim.exploration import explore

#: Contacts of the default tests' run.
COUNT = 40


def _run(tmp_path_factory, count: int) -> Path:  # noqa: ANN001
    out = tmp_path_factory.mktemp("view") / "run"
    explore("cube", strategy="paper", seed=0, out_dir=out, progress=False, count=count)
    return out


@pytest.fixture(scope="session")
def run_dir(tmp_path_factory) -> Path:  # noqa: ANN001
    return _run(tmp_path_factory, COUNT)


@pytest.fixture(scope="session")
def run_dir_150(tmp_path_factory) -> Path:  # noqa: ANN001
    return _run(tmp_path_factory, 150)
