"""The reconstruction literature's surface measures: F-score at distance thresholds, normal
consistency, and the Chamfer distance, from one draw of surface samples.

Both surfaces are sampled uniformly by area (`samples` points each, with their outward normals;
the generator draws the estimate's first, as :func:`~hapticsim.metrics.chamfer.chamfer` does,
so the Chamfer distance here is the same number). For each sample the distance to the *other*
surface is exact (``Solid.surface_distance``), not the distance to the nearest of the other
surface's samples, which would add the sampling spacing.

- ``precision(tau)``: the fraction of the estimate's samples within tau of the true surface;
  ``recall(tau)``: the fraction of the truth's samples within tau of the estimate;
  ``f_score(tau) = 2 P R / (P + R)`` (0 when both are 0), as Tatarchenko et al. (CVPR 2019)
  define it for shape reconstruction.
- ``normal_consistency``: the mean over both surfaces' samples of ``|n . n'|``, n the sample's
  normal and n' the other surface's normal at its closest point (:func:`normals_at_closest`),
  as Occupancy Networks (Mescheder et al., CVPR 2019) report it: 1 for the same surface, about
  0.5 for unrelated normals.
- ``chamfer``: ``(mean d(estimate samples, truth) + mean d(truth samples, estimate)) / 2`` [m],
  the symmetric mean distance of :func:`~hapticsim.metrics.chamfer.chamfer` (Chamfer-L2 in the
  sense of Euclidean, not squared, distances; a benchmark reports it in mm).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from hapticsim._validate import as_generator, positive_int
from hapticsim.errors import InvalidInputError
from hapticsim.geometry.solid import Solid, solid_arg
from hapticsim.metrics.chamfer import DEFAULT_CHAMFER_SAMPLES

#: F-score thresholds [m]: 1, 2.5 and 5 mm, as touch and reconstruction papers report them for
#: hand-held objects.
DEFAULT_F_THRESHOLDS: tuple[float, ...] = (0.001, 0.0025, 0.005)
#: Longitudes of the surface mesh whose closest points give the normals compared.
NORMAL_MESH_RESOLUTION: int = 96


@dataclass(frozen=True)
class SurfaceScore:
    """Surface measures of an estimate against the truth (module docstring).

    Attributes:
        thresholds: the F-score thresholds [m].
        precision, recall, f_score: one value per threshold, each in [0, 1].
        normal_consistency: in [0, 1].
        chamfer: symmetric mean surface distance [m].
        samples: surface points drawn on each solid.
    """

    thresholds: tuple[float, ...]
    precision: tuple[float, ...]
    recall: tuple[float, ...]
    f_score: tuple[float, ...]
    normal_consistency: float
    chamfer: float
    samples: int

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``f_score``, ``precision`` and ``recall`` keyed by the threshold in mm
        (``"1"``, ``"2.5"``, ``"5"``), ``thresholds_m``, ``normal_consistency``, ``chamfer``
        [m], ``chamfer_mm`` and ``samples``."""
        keys = [f"{1000.0 * t:g}" for t in self.thresholds]
        return {
            "f_score": dict(zip(keys, self.f_score, strict=True)),
            "precision": dict(zip(keys, self.precision, strict=True)),
            "recall": dict(zip(keys, self.recall, strict=True)),
            "thresholds_m": list(self.thresholds),
            "normal_consistency": self.normal_consistency,
            "chamfer": self.chamfer,
            "chamfer_mm": 1000.0 * self.chamfer,
            "samples": self.samples,
        }


def f_score(precision: float, recall: float) -> float:
    """``2 P R / (P + R)``, 0 where both are 0."""
    total = precision + recall
    return 0.0 if total <= 0.0 else float(2.0 * precision * recall / total)


def thresholds_arg(thresholds: Any) -> tuple[float, ...]:
    """Distance thresholds [m]: a non-empty sequence of finite values > 0."""
    try:
        values = tuple(float(t) for t in thresholds)
    except (TypeError, ValueError):
        raise InvalidInputError(
            f"`thresholds` must be a sequence of distances [m], got {thresholds!r}"
        ) from None
    if not values or not all(np.isfinite(t) and t > 0 for t in values):
        raise InvalidInputError(
            f"`thresholds` must be one or more finite distances > 0 [m], got {thresholds!r}"
        )
    return values


def surface_score(
    estimate: Solid,
    truth: Solid,
    thresholds: Any = DEFAULT_F_THRESHOLDS,
    samples: int = DEFAULT_CHAMFER_SAMPLES,
    rng: np.random.Generator | int | None = 0,
) -> SurfaceScore:
    """F-score, precision and recall at each threshold, normal consistency and the Chamfer
    distance of `estimate` against `truth`, any two solids (module docstring).

    Args:
        estimate: the estimated solid.
        truth: the true solid.
        thresholds: F-score thresholds [m] (default 1, 2.5 and 5 mm).
        samples: surface points per solid, >= 1.
        rng: seed or generator (default seed 0: the same pair gives the same numbers).
    """
    estimate = solid_arg(estimate, "estimate")
    truth = solid_arg(truth, "truth")
    taus = thresholds_arg(thresholds)
    n = positive_int(samples, "samples")
    gen = as_generator(rng)
    p_est, n_est = estimate.sample_surface(n, gen)
    p_true, n_true = truth.sample_surface(n, gen)
    to_truth = truth.surface_distance(p_est)
    to_estimate = estimate.surface_distance(p_true)
    precision = tuple(float(np.mean(to_truth <= t)) for t in taus)
    recall = tuple(float(np.mean(to_estimate <= t)) for t in taus)
    agree_est = np.abs(np.sum(n_est * normals_at_closest(truth, p_est), axis=1))
    agree_true = np.abs(np.sum(n_true * normals_at_closest(estimate, p_true), axis=1))
    return SurfaceScore(
        thresholds=taus,
        precision=precision,
        recall=recall,
        f_score=tuple(f_score(p, r) for p, r in zip(precision, recall, strict=True)),
        normal_consistency=float(0.5 * (np.mean(agree_est) + np.mean(agree_true))),
        chamfer=float(0.5 * (np.mean(to_truth) + np.mean(to_estimate))),
        samples=n,
    )


def normals_at_closest(solid: Solid, points_world: np.ndarray) -> np.ndarray:
    """(n, 3) float, the solid's outward normal at the point of its surface closest to each
    point: the closest point of its surface mesh (:data:`NORMAL_MESH_RESOLUTION` longitudes),
    then ``Solid.normals`` there (a superquadric's own normal on its surface, a mesh's face)."""
    from hapticsim.geometry.triangles import TriangleSearch

    vertices, faces = solid.surface_mesh(NORMAL_MESH_RESOLUTION)
    search = TriangleSearch(np.asarray(vertices)[np.asarray(faces)], solid.bounding_radius / 16)
    closest, _ = search.nearest(points_world, exact=False)  # the 16 nearest pieces, as Chamfer
    return solid.normals(closest)


def anytime_area(values: Any) -> float:
    """The normalised area under a touch curve: the mean of a measure after touches 1..T
    (each touch counts alike; a measure that is 1 after every touch has area 1)."""
    v = np.asarray(values, dtype=float)
    if v.ndim != 1 or len(v) == 0 or not np.all(np.isfinite(v)):
        raise InvalidInputError(
            f"`values` must be a non-empty 1-d sequence of finite numbers, got shape {v.shape}"
        )
    return float(np.mean(v))


__all__ = [
    "DEFAULT_F_THRESHOLDS", "NORMAL_MESH_RESOLUTION", "SurfaceScore", "anytime_area", "f_score",
    "normals_at_closest", "surface_score", "thresholds_arg",
]  # fmt: skip
