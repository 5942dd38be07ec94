"""Quality measures of an estimate against the truth (paper III-B, SPEC §4), for any two solids
(:class:`~hapticsim.geometry.solid.Solid`: superquadrics, unions, meshes; SPEC §10).

- :func:`theta`: minimisation quality ``D(S_e) / (D(S_s) + 1)`` (eq. 10, superquadrics).
- :func:`alpha`, :func:`beta`, :func:`epsilon`, :func:`iou`: volume measures (eqs. 11-12) by
  Monte Carlo with exact volumes (:func:`volume_overlap` computes all at once), or by exact mesh
  booleans (:func:`boolean_overlap`).
- :func:`chamfer`: symmetric Chamfer distance between the surfaces [m].
- :func:`score`: all of them as a :class:`Score` (``hapticsim score`` prints its ``to_dict()``).
- :func:`surface_score`: the reconstruction literature's F-score at distance thresholds (1,
  2.5, 5 mm by default), precision, recall and normal consistency, with the Chamfer distance,
  as a :class:`SurfaceScore`; :func:`anytime_area`: the normalised area under a touch curve.
- :class:`~hapticsim.metrics.episode.TruthScorer`: many estimates against one truth, fast (the
  environment's per-step score).
"""

from hapticsim.metrics.chamfer import chamfer, sample_surface, surface_distance
from hapticsim.metrics.score import Score, score
from hapticsim.metrics.surface import SurfaceScore, anytime_area, surface_score
from hapticsim.metrics.theta import theta
from hapticsim.metrics.volume import (
    VolumeOverlap,
    alpha,
    beta,
    boolean_overlap,
    epsilon,
    iou,
    sample_interior,
    volume_overlap,
)

__all__ = [
    "Score",
    "SurfaceScore",
    "anytime_area",
    "VolumeOverlap",
    "alpha",
    "beta",
    "boolean_overlap",
    "chamfer",
    "epsilon",
    "iou",
    "sample_interior",
    "sample_surface",
    "score",
    "surface_distance",
    "surface_score",
    "theta",
    "volume_overlap",
]
