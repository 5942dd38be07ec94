"""bench record: a policy's episodes as a Minari dataset that minari.load_dataset reads back."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

minari = pytest.importorskip("minari")

from hapticsim.bench.record import record_dataset  # noqa: E402
from hapticsim.cli import main  # noqa: E402


def _round_trip(tmp_path: Path, episodes: int, monkeypatch: pytest.MonkeyPatch) -> None:
    out = record_dataset("paper/exact/analytic/t20", "uncertainty", episodes,
                         "hapticsim/paper-unc-v0", root=tmp_path, progress=False)  # fmt: skip
    assert out["episodes"] == episodes and out["steps"] == 20 * episodes
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path))
    data = minari.load_dataset("hapticsim/paper-unc-v0")
    assert data.total_episodes == episodes and data.total_steps == 20 * episodes
    episode = next(data.iterate_episodes())
    assert episode.actions.shape == (20, 5) and np.all(np.abs(episode.actions) <= 1.0)
    assert episode.observations["points"].shape[0] == 21  # the reset's and 20 touches'
    assert "paper/exact/analytic/t20" in data.storage.metadata["description"]


def test_a_dataset_round_trips(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    _round_trip(tmp_path, 3, monkeypatch)


@pytest.mark.slow  # ~2-5 min: 100 episodes of 20 touches
def test_a_dataset_of_100_episodes_round_trips(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _round_trip(tmp_path, 100, monkeypatch)


def test_bad_input_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    base = ["bench", "record", "paper/exact/analytic/t20", "--policy", "random", "--episodes",
            "1", "--root", str(tmp_path), "--quiet"]  # fmt: skip
    assert main([*base, "--dataset", "no-version"]) == 2
    assert "NAMESPACE/NAME-vN" in capsys.readouterr().err
    assert main([*base, "--dataset", "hapticsim/one-v0"]) == 0
    capsys.readouterr()
    assert main([*base, "--dataset", "hapticsim/one-v0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "exists already" in err[0]
