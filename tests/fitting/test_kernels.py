"""Getting the fitter's kernels ready: parts per method, markers, workers, and fit timing."""

from __future__ import annotations

import io
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from hapticsim import _jit_cache
from hapticsim.errors import InvalidInputError
from hapticsim.fitting import fit, kernels


def test_parts_follow_the_methods() -> None:
    assert kernels.parts_for("LS") == ("eof-lm",)
    assert kernels.parts_for("nH") == ("eof-lm", "eof-ga")
    assert kernels.parts_for(["nH", "nML"]) == kernels.PARTS
    assert set(kernels.METHOD_PARTS) >= {"LS", "H", "nLS", "nH", "nML", "multi"}
    with pytest.raises(InvalidInputError, match="unknown method 'NH'"):
        kernels.parts_for("NH")


def test_a_warm_cache_starts_no_worker(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    tag = kernels.target_tag()
    for part in kernels.parts_for("nH"):
        _jit_cache.mark(part, tag)
    monkeypatch.setattr(kernels, "_ready", set())
    assert kernels.start_background("nH", stream=io.StringIO()) is None


def test_the_work_is_dealt_to_the_workers() -> None:
    assert kernels._split(kernels.PARTS, 2) == [("eof-lm", "ml-lm"), ("eof-ga", "ml-ga")]
    groups = kernels._split(kernels.PARTS, 2)
    assert kernels.Background(groups=groups).parts == ("eof-lm", "ml-lm", "eof-ga", "ml-ga")
    assert kernels._split(("eof-lm",), 4) == [("eof-lm",)]


def test_a_failed_worker_is_reported_and_waiting_ends() -> None:
    proc = subprocess.Popen([sys.executable, "-c", "raise SystemExit(3)"])
    lines: list[str] = []
    kernels.Background(groups=[("eof-ga",)], procs=[proc]).wait(say=lines.append)
    assert len(lines) == 1 and "eof-ga failed (exit 3)" in lines[0]


def test_the_worker_refuses_an_unknown_part() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "hapticsim.fitting.kernels", "eof-xx"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 2 and "unknown part 'eof-xx'" in done.stderr


def test_a_fit_reports_its_set_up_apart_and_once() -> None:
    rng = np.random.default_rng(0)
    normals = rng.normal(size=(40, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    points = 0.02 * normals
    first = fit(points, normals, method="nH", budget=300, rng=0)
    again = fit(points, normals, method="nH", budget=300, rng=0)
    assert first.setup_seconds >= 0.0 and again.setup_seconds == 0.0
    assert again.to_dict()["setup_seconds"] == 0.0
    assert np.array_equal(first.superquadric.to_vector(), again.superquadric.to_vector())


def test_stopping_ends_the_workers() -> None:
    proc = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    background = kernels.Background(groups=[("eof-ga",)], procs=[proc])
    background.stop()
    assert proc.poll() is not None


def test_a_second_start_of_running_parts_returns_the_same_workers(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))  # nothing marked: cold
    monkeypatch.setattr(kernels, "_ready", set())
    started: list[list[str]] = []

    class _Proc:
        def __init__(self, argv, **kwargs) -> None:  # noqa: ANN001, ANN003
            started.append(argv)

        def poll(self) -> int:
            return 0

    monkeypatch.setattr(kernels.subprocess, "Popen", _Proc)
    monkeypatch.setattr(kernels, "_running", None)
    first = kernels.start_background("nH", jobs=2, stream=io.StringIO())
    again = kernels.start_background("nH", jobs=2, stream=io.StringIO())
    assert first is again and len(started) == 2
    assert kernels.start_background("nML", jobs=2, stream=io.StringIO()) is not first
