"""Scoring many estimates against one truth quickly: :class:`TruthScorer` (the environment's
per-step alpha, beta, epsilon, IoU and Chamfer).

Everything random is drawn once, when the scorer is made, so that scoring an estimate costs only
compiled loops (about 1 ms for the default 4096 samples and 128 Chamfer points):

- **samples**: the rejection sampler of :func:`~hapticsim.metrics.volume.sample_interior`
  (candidates in the cube ``[-1, 1]^3`` of scaled untapered body coordinates, kept when inside
  the unit shape and passing the taper acceptance) run on fixed *quasi-random* candidates: a
  scrambled Sobol sequence in four dimensions (three coordinates, one acceptance number). A
  solid's interior sample is what it keeps of the first ``samples / acceptance`` candidates
  (its acceptance is known in closed form), about `samples` points;
- **beta**: the truth's interior sample (its own scrambled sequence), fixed; beta is the
  fraction outside the estimate;
- **alpha**: each estimate's interior sample from the shared candidates, tested in the truth.
  Successive estimates are thus scored with common random numbers: their difference (the
  environment's reward) has far less noise than either score;
- **IoU**: from alpha, beta and the exact volumes, as :func:`~hapticsim.metrics.volume_overlap`;
- **Chamfer** (SPEC §4, the mean of both directions' mean distances): fixed directions spread
  evenly on the sphere (a randomly turned Fibonacci lattice) map one-to-one onto each surface
  (the surface point on each ray), and each point carries its area element
  (:func:`~hapticsim.metrics._compiled.surface_sample`), so the weighted means are area means;
  the distances to the other exact surface come from foot-point iteration
  (:func:`~hapticsim.metrics._compiled.surface_distances`), not from a mesh.

Accuracy, measured against 3 x 10^6 Monte Carlo samples and a 20 000-point Chamfer distance on
30 estimate/truth pairs (random tapered and paper bodies, 4 scorer seeds; ``docs/fast-loop``):
RMS error of epsilon 0.0032 at 4096 samples (0.0018 at 10 000), largest 0.0098; of the Chamfer
distance 1.2 % at 128 points. (The former plain Monte Carlo scorer, 10 000 samples and 200
random directions: 0.0059, largest 0.018, and 4.7 %.)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import as_generator, positive_int
from hapticsim.constants import SCORE_CHAMFER_POINTS, SCORE_SAMPLES
from hapticsim.geometry import Superquadric
from hapticsim.geometry._eof_compiled import TINY
from hapticsim.geometry.superquadric import superquadric_arg
from hapticsim.metrics import _compiled as kernel
from hapticsim.metrics.volume import _max_taper_jacobian, intersection_and_iou

Array = NDArray[np.float64]

#: Angular step [rad] of the differences behind the area weights of surface points.
AREA_STEP: float = 1e-4
#: Foot-point iterations per distance (converged to < 1e-9 m near the surface after 3-4).
FOOT_ITERATIONS: int = 6
#: Candidates drawn per interior sample of an estimate: an estimate uses ``samples /
#: acceptance`` of them, and any superquadric with eps <= 2 keeps at least 1/6 (untapered) or
#: about 1/16 (fully tapered); if one ever keeps less, it is scored with the samples it has.
CANDIDATES_PER_SAMPLE: int = 16


@dataclass(frozen=True)
class EstimateScore:
    """Quality measures of one estimate (SPEC §4).

    Attributes:
        alpha, beta, epsilon, iou: volume measures; chamfer: [m].
        samples: interior points behind alpha (the estimate's) and beta (the truth's).
    """

    alpha: float
    beta: float
    epsilon: float
    iou: float
    chamfer: float
    samples: tuple[int, int]

    def to_dict(self) -> dict[str, float]:
        """``{"alpha", "beta", "epsilon", "iou", "chamfer"}``."""
        return {
            "alpha": self.alpha, "beta": self.beta, "epsilon": self.epsilon, "iou": self.iou,
            "chamfer": self.chamfer,
        }  # fmt: skip


def sobol_points(dimensions: int, count: int, gen: np.random.Generator) -> Array:
    """The first ``2^m >= count`` points of a scrambled Sobol sequence in [0, 1)^dimensions
    (scrambling seeded by `gen`), (2^m, dimensions): a balanced prefix. The sequence is the same
    whatever `count`, so a longer set starts with a shorter one."""
    from scipy.stats import qmc

    sobol = qmc.Sobol(dimensions, scramble=True, seed=gen)
    return sobol.random_base2(int(np.ceil(np.log2(max(count, 1)))))


def quasi_random_candidates(count: int, gen: np.random.Generator) -> tuple[Array, Array, Array]:
    """At least `count` candidates of the rejection sampler from :func:`sobol_points` in four
    dimensions: the first three coordinates mapped to the cube [-1, 1]^3 (``unit``, with
    ``log(|u| + TINY)``), the fourth the acceptance numbers."""
    sobol = sobol_points(4, count, gen)
    unit = np.ascontiguousarray(2.0 * sobol[:, :3].T - 1.0)
    return unit, np.log(np.abs(unit) + TINY), np.ascontiguousarray(sobol[:, 3])


def _sphere_lattice(count: int, gen: np.random.Generator) -> Array:
    """(3, count) unit directions spread evenly over the sphere: a Fibonacci lattice (equal-area
    bands in z, the golden angle between successive points) turned by a random rotation."""
    k = np.arange(count) + 0.5
    z = 1.0 - 2.0 * k / count
    r = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    phi = np.pi * (3.0 - np.sqrt(5.0)) * k
    lattice = np.stack([r * np.cos(phi), r * np.sin(phi), z])
    q, upper = np.linalg.qr(gen.standard_normal((3, 3)))
    q = q * np.sign(np.diag(upper))  # a uniformly random orthogonal matrix
    return np.ascontiguousarray(q @ lattice)


def interior_sample(
    candidates: tuple[Array, Array, Array], sq: Superquadric, samples: int
) -> Array:
    """About `samples` points uniform inside `sq`, (3, k) [m, world]: what the rejection sampler
    keeps of the first ``samples / acceptance`` of the fixed `candidates`
    (:func:`quasi_random_candidates`)."""
    unit, log_unit, accept = candidates
    top = _max_taper_jacobian(sq.taper)
    count = _candidate_count(sq, top, samples, accept.shape[0])
    return kernel.interior_points(unit, log_unit, accept, top, count, *kernel.unpack(sq))


def _candidate_count(sq: Superquadric, top: float, samples: int, available: int | None) -> int:
    """Candidates for about `samples` kept points of `sq` (its acceptance is
    ``V / (8 a1 a2 a3 top)``), at most `available` (None: no limit)."""
    acceptance = sq.volume / (8.0 * float(np.prod(sq.a)) * top)
    count = int(np.ceil(samples / acceptance))
    return count if available is None else min(available, count)


class TruthScorer:
    """Scores estimates against one fixed truth, fast (module docstring).

    Args:
        truth: the true superquadric.
        samples: interior points per solid for alpha and beta (about; module docstring), >= 100.
        chamfer_samples: surface points per shape for the Chamfer distance, >= 10.
        rng: seed or generator of every random number (drawn here, once).
    """

    def __init__(
        self,
        truth: Superquadric,
        samples: int = SCORE_SAMPLES,
        chamfer_samples: int = SCORE_CHAMFER_POINTS,
        rng: np.random.Generator | int | None = 0,
    ) -> None:
        self.truth = superquadric_arg(truth, "truth")
        self.samples = positive_int(samples, "samples", minimum=100)
        self.chamfer_samples = positive_int(chamfer_samples, "chamfer_samples", minimum=10)
        gen = as_generator(rng)
        self._unit, self._log_unit, self._accept = quasi_random_candidates(
            CANDIDATES_PER_SAMPLE * self.samples, gen
        )
        self._directions = _sphere_lattice(self.chamfer_samples, gen)
        self._set_truth(self.truth, gen)

    def _set_truth(self, truth: Superquadric, gen: np.random.Generator) -> None:
        self.truth = truth
        self._truth_params = kernel.unpack(truth)
        # only as many candidates as the truth's own acceptance needs (the scrambled sequence
        # starts the same whatever its length, so the sample is that of the full set)
        need = _candidate_count(truth, _max_taper_jacobian(truth.taper), self.samples, None)
        candidates = quasi_random_candidates(min(need, CANDIDATES_PER_SAMPLE * self.samples), gen)
        self._truth_inside = interior_sample(candidates, truth, self.samples)
        self._truth_surface = self._surface(self._truth_params)

    def with_truth(
        self, truth: Superquadric, rng: np.random.Generator | int | None = 0
    ) -> TruthScorer:
        """A scorer for another truth that shares this one's truth-independent random numbers
        (the estimate-side candidates and the surface directions): cheaper than a new one.

        Args:
            truth: the new truth.
            rng: seed or generator of the new truth's interior points.
        """
        other = object.__new__(TruthScorer)
        other.__dict__.update(self.__dict__)
        other._set_truth(superquadric_arg(truth, "truth"), as_generator(rng))
        return other

    def score(self, estimate: Superquadric) -> EstimateScore:
        """alpha, beta, epsilon, IoU and Chamfer of `estimate` against the truth."""
        est = superquadric_arg(estimate, "estimate")
        shape, rot, center = kernel.unpack(est)
        t_shape, t_rot, t_center = self._truth_params
        top = _max_taper_jacobian(est.taper)
        count = _candidate_count(est, top, self.samples, self._accept.shape[0])
        outside_e, kept = kernel.interior_outside(
            self._unit, self._log_unit, self._accept, top, count, shape, rot, center, t_shape,
            t_rot, t_center,
        )  # fmt: skip
        outside_s = kernel.count_outside(self._truth_inside, shape, rot, center)
        n_e, n_s = max(kept, 1), max(self._truth_inside.shape[1], 1)
        alpha, beta = outside_e / n_e, outside_s / n_s
        _, iou = intersection_and_iou(alpha, beta, est.volume, self.truth.volume, n_s)
        distance = self._chamfer((shape, rot, center))
        return EstimateScore(
            alpha=float(alpha), beta=float(beta), epsilon=float(alpha + beta), iou=float(iou),
            chamfer=float(distance), samples=(int(kept), n_s),
        )  # fmt: skip

    def _surface(self, params: tuple[Array, Array, Array]) -> tuple[Array, Array]:
        """Surface points (3, K) [m, world] of the fixed directions, and their area weights."""
        points = np.empty((3, self.chamfer_samples))
        weights = np.empty(self.chamfer_samples)
        kernel.surface_sample(self._directions, AREA_STEP, *params, points, weights)
        return points, weights

    def _chamfer(self, params: tuple[Array, Array, Array]) -> float:
        """Area-weighted mean distances between the two surfaces, averaged (SPEC §4) [m]."""
        points, weights = self._surface(params)
        to_truth = np.empty(self.chamfer_samples)
        kernel.surface_distances(points, *self._truth_params, FOOT_ITERATIONS, to_truth)
        truth_points, truth_weights = self._truth_surface
        to_estimate = np.empty(self.chamfer_samples)
        kernel.surface_distances(truth_points, *params, FOOT_ITERATIONS, to_estimate)
        return 0.5 * (
            float(np.average(to_truth, weights=weights))
            + float(np.average(to_estimate, weights=truth_weights))
        )
