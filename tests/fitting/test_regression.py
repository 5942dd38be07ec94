"""Reconstruction quality on the paper's four bodies (fixed synthetic data sets, default nH).

Thresholds come from measurement (written next to them) with a margin of about 0.05 in epsilon,
so that a real loss of quality (a wrong basin costs 0.2-0.4) fails while Monte Carlo noise of the
score (standard error <= 0.0035 with 20 000 samples) and platform rounding do not.
"""

from __future__ import annotations

import numpy as np
import pytest

from hapticsim.data.bodies import get_body
from hapticsim.data.synthetic import paper_dataset
from hapticsim.fitting import fit
from hapticsim.metrics import volume_overlap
from tests.fitting.conftest import posed

# Measured epsilon of default nH (default budget, 7500) at sigma_N = 0.1, data seed 0 (pose and
# noise), over fit seeds 0-9 (min-max; scripts/measure_bounds.py --section regression), with
# nLS from the paper's initial estimate, nH at budget 300 (median over fit seeds) and the oracle
# (nLS from the truth) on the same data:
#   tapered_box nH 0.198-0.207   nLS 0.305   nH300 0.416   oracle 0.199
#   cube        nH 0.099-0.101   nLS 0.323   nH300 0.159   oracle 0.075
#   cylinder    nH 0.166-0.175   nLS 0.178   nH300 0.165   oracle 0.166
#   ellipsoid   nH 0.098-0.116   nLS 0.104   nH300 0.105   oracle 0.105
# At this noise the round bodies' paper data cannot tell the methods apart (their oracle scores
# the same): ONE_SIDED below does. Earlier measurements over data seeds 0, 1, 2 (budget 5000,
# before the compiled fitter), nH / oracle:
#   tapered_box 0.204 0.184 0.161   oracle 0.205 0.184 0.167
#   cube        0.100 0.090 0.124   oracle 0.076 0.077 0.120
#   cylinder    0.167 0.143 0.176   oracle 0.168 0.152 0.160
#   ellipsoid   0.109 0.093 0.237   oracle 0.105 0.093 0.159
# and at sigma_N = 0.02:
#   tapered_box 0.028 0.033 0.028   oracle 0.009 0.034 0.030
#   cube        0.010 0.038 0.023   oracle 0.013 0.022 0.023
#   cylinder    0.023 0.057 0.035   oracle 0.015 0.031 0.035
#   ellipsoid   0.039 0.019 0.033   oracle 0.023 0.019 0.032
NOISY = {"tapered_box": 0.25, "cube": 0.13, "cylinder": 0.22, "ellipsoid": 0.16}
MEAN_LIMITS = {0.1: 0.19, 0.02: 0.08}  # means of the tables above: 0.149 and 0.031


def _nh_epsilon(name: str, noise: float, seed: int) -> float:
    truth = posed(get_body(name), seed)
    data = paper_dataset(truth, noise=noise, rng=seed)
    result = fit(data.points, data.normals, method="nH", rng=seed)
    overlap = volume_overlap(result.superquadric, truth, samples=20_000, rng=0)
    return overlap.alpha + overlap.beta


@pytest.mark.parametrize("name", sorted(NOISY))
def test_paper_body_at_paper_noise(name: str) -> None:
    assert _nh_epsilon(name, 0.1, 0) < NOISY[name]


#: One-sided clean contacts where the global search matters: (body, data seed, patterns of
#: paper_patterns kept) -> limit on nH's epsilon. Measured with scripts/measure_bounds.py at the
#: default budget 7500 (nH over fit seeds 0-9 | nLS from the paper's initial estimate | nH at
#: budget 300 over fit seeds 0-9, min-median-max):
#:   cylinder  seed 0, thumb + index patches (77 contacts): nH 0.000 | nLS 0.764 |
#:             nH300 0.528-0.637-0.637
#:   ellipsoid seed 4, thumb + index patches (101):        nH 0.000 | nLS 0.286 |
#:             nH300 0.000-0.021-0.283
#:   ellipsoid seed 4, thumb patch (51):                   nH 0.000 | nLS 0.000 |
#:             nH300 0.179-0.193-0.337
#: The limits keep a margin of >= 0.015 (20 000 Monte Carlo samples: standard error <= 0.0035)
#: and fail nLS (first two cases) and nH at budget 300 (first and third).
ONE_SIDED = {
    ("cylinder", 0, (0, 1)): 0.05,
    ("ellipsoid", 4, (0, 1)): 0.02,
    ("ellipsoid", 4, (0,)): 0.02,
}


@pytest.mark.parametrize(("case", "limit"), ONE_SIDED.items(), ids=lambda v: str(v))
def test_round_bodies_from_one_sided_clean_contacts(case: tuple, limit: float) -> None:
    name, seed, patterns = case
    truth = posed(get_body(name), seed)
    data = paper_dataset(truth, noise=0.0, rng=seed)
    keep = np.isin(data.extra["pattern"], patterns)
    result = fit(data.points[keep], data.normals[keep], method="nH", rng=0)
    overlap = volume_overlap(result.superquadric, truth, samples=20_000, rng=0)
    assert overlap.alpha + overlap.beta < limit


@pytest.mark.slow
@pytest.mark.parametrize("noise", sorted(MEAN_LIMITS))
def test_mean_quality_over_bodies_and_seeds(noise: float) -> None:
    eps = [_nh_epsilon(name, noise, seed) for name in NOISY for seed in range(3)]
    assert np.mean(eps) < MEAN_LIMITS[noise]
    assert max(eps) < 0.3  # no fit in a wrong basin (those score 0.33 and more)
