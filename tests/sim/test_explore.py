"""``explore``: files, keys and the quality targets of the issue."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hapticsim.data.bodies import BODY_NAMES
from hapticsim.data.io import read_contacts
from hapticsim.exploration import explore

NPZ_KEYS = {"points", "normals", "points_clean", "normals_clean", "finger", "force", "time"}


@pytest.fixture(scope="module")
def summary(tmp_path_factory) -> dict:
    out = tmp_path_factory.mktemp("explore") / "run"
    return explore(
        "ellipsoid", strategy="patch", noise=0.05, method="nLS", seed=1, out_dir=out,
        progress=False, count=30,
    )  # fmt: skip


def test_explore_writes_every_file(summary) -> None:
    files = summary["files"]
    assert set(files) == {"contacts", "truth", "fit", "metrics", "report", "hand"}
    for path in files.values():
        assert open(path, "rb").read(8)  # non-empty
    assert open(files["report"], "rb").read(8) == b"\x89PNG\r\n\x1a\n"


def test_contacts_file_has_the_spec_keys(summary) -> None:
    with np.load(summary["files"]["contacts"]) as data:
        assert NPZ_KEYS <= set(data.files)
        n = len(data["points"])
        assert n == 30 and data["finger"].dtype.kind == "i" and data["force"].shape == (n,)
        assert np.all(data["force"] > 0) and np.all(np.diff(data["time"]) >= 0)
        # noise is added to the measured values only
        assert not np.allclose(data["points"], data["points_clean"])
    contacts = read_contacts(summary["files"]["contacts"])
    assert len(contacts) == 30 and contacts.normals is not None


def test_metrics_report_quality_and_contact_accuracy(summary) -> None:
    metrics = json.load(open(summary["files"]["metrics"]))
    for key in ("alpha", "beta", "epsilon", "iou", "chamfer", "theta"):
        assert key in metrics
    acc = metrics["contact_accuracy"]
    for key in ("distance_median", "distance_p95", "angle_median_deg", "angle_p95_deg"):
        assert key in acc
    assert acc["distance_median"] < 5e-4 and acc["angle_median_deg"] < 2.0
    fit = json.load(open(summary["files"]["fit"]))
    assert fit["method"] == "nLS" and "superquadric" in fit
    assert summary["contacts"] == 30 and json.loads(json.dumps(summary)) == summary


@pytest.mark.slow
@pytest.mark.parametrize("body", BODY_NAMES)
def test_paper_exploration_meets_the_targets(body: str, tmp_path) -> None:
    """Issue targets: clean contacts median distance <= 0.5 mm, median angle <= 2 deg, p95 <= 10
    deg; nH on noise-free data epsilon <= 0.10. Measured (seed 0): distances ~1e-5 m, angles
    median 0.02-0.9 deg, p95 < 1.8 deg; epsilon < 0.001."""
    summary = explore(body, "paper", noise=0.0, method="nH", seed=0, out_dir=tmp_path,
                      progress=False)  # fmt: skip
    acc = summary["contact_accuracy"]
    assert summary["contacts"] == 150
    assert acc["distance_median"] <= 5e-4
    assert acc["angle_median_deg"] <= 2.0 and acc["angle_p95_deg"] <= 10.0
    assert summary["metrics"]["epsilon"] <= 0.10


#: Default-run explorations (body, strategy, contacts) -> limits on epsilon of the nH fit and
#: the median distance [m] and 95th percentile normal angle [deg] of the clean contacts.
#: Measured (scripts/measure_bounds.py --section explore, noise 0, seeds 0-1): cube/paper/150
#: epsilon 0.0000-0.0001, distance 3e-7 m, angle p95 1.2 deg; cylinder/stripe/60 epsilon
#: 0.0004-0.0005, distance 4-6e-6 m, angle p95 1.4-1.6 deg. Contacts 1 mm off the surface
#: would score epsilon ~0.1 and a distance of 1e-3 m (the limits fail them).
DEFAULT_RUNS = {
    ("cube", "paper", 150): (0.03, 1e-4, 5.0),
    ("cylinder", "stripe", 60): (0.03, 1e-4, 5.0),
}


@pytest.mark.parametrize(("run", "limits"), DEFAULT_RUNS.items(), ids=lambda v: str(v))
def test_explore_fit_quality_is_bounded(run: tuple, limits: tuple, tmp_path) -> None:
    body, strategy, count = run
    max_epsilon, max_distance, max_angle = limits
    summary = explore(body, strategy, noise=0.0, method="nH", seed=0, out_dir=tmp_path,
                      progress=False, count=count)  # fmt: skip
    assert summary["complete"] and summary["contacts"] == count
    assert summary["metrics"]["epsilon"] < max_epsilon
    acc = summary["contact_accuracy"]
    assert acc["distance_median"] < max_distance and acc["angle_p95_deg"] < max_angle
    with np.load(summary["files"]["contacts"]) as data:  # the strategy's own patterns
        kinds = set(data["pattern_kind"].tolist())
    assert "stripe" in kinds


def test_rings_are_explored_and_their_holes_found(tmp_path) -> None:
    # random rings drawn from five trials' seeds, 100 contacts of the uncertainty policy each. One
    # trajectory is no test (numba's rounding differs between CPUs, and an episode that takes
    # another path may see too little of the inner wall to choose the ring): measured on AMD
    # family 26 (znver5), seeds 101-110: the ring chosen 8 times in 10 (seeds 103 and 109 saw 3 %
    # of their contacts on the inner wall), IoU 0.98-0.997 where chosen, 0.85 and 0.92 where not.
    # The bars: a majority of the five, and medians over them.
    chosen, ious, distances = [], [], []
    for seed in range(101, 106):
        out = tmp_path / str(seed)
        summary = explore("random_holed", "uncertainty", method="multi", holes=True, seed=seed,
                          out_dir=out, progress=False, count=100)  # fmt: skip
        truth = json.loads((out / "truth.json").read_text())
        fit = json.loads((out / "fit.json").read_text())
        assert truth["kind"] == "supertoroid"
        holes = fit["selection"]["holes"]
        assert holes["chosen"] in holes["costs"]
        ring = holes["chosen"] == "supertoroid"
        assert ring == (fit["solid"].get("kind") == "supertoroid")
        chosen.append(ring)
        ious.append(summary["metrics"]["iou"])
        distances.append(summary["contact_accuracy"]["distance_median"])
    assert sum(chosen) >= 3, chosen
    assert np.median(ious) > 0.9, ious
    assert np.median(distances) < 1e-4, distances
