"""One explore run of 150 contacts (the viewer's bar is stated for one), shared by the tests."""

from __future__ import annotations

from pathlib import Path

import pytest

from hapticsim.experiments.explore import explore

#: Contacts of the shared run.
COUNT = 150


@pytest.fixture(scope="session")
def run_dir(tmp_path_factory) -> Path:  # noqa: ANN001
    out = tmp_path_factory.mktemp("view") / "run"
    explore("cube", strategy="paper", seed=0, out_dir=out, progress=False, count=COUNT)
    return out
