"""Quality measures of an estimated superquadric (paper III-B, SPEC §4).

- :func:`theta`: minimisation quality ``D(S_e) / (D(S_s) + 1)`` (eq. 10).
- :func:`alpha`, :func:`beta`, :func:`epsilon`, :func:`iou`: volume measures (eqs. 11-12) by
  Monte Carlo with exact volumes (:func:`volume_overlap` computes all at once).
- :func:`chamfer`: symmetric Chamfer distance between the surfaces [m].
- :func:`score`: all of them as a :class:`Score` (``hapticsim score`` prints its ``to_dict()``);
  against a mesh truth (:class:`~hapticsim.geometry.mesh_solid.MeshSolid`) by
  :func:`score_mesh` (:mod:`~hapticsim.metrics.mesh_truth`: Monte Carlo or exact booleans).
"""

from hapticsim.metrics.chamfer import chamfer, sample_surface, surface_distance
from hapticsim.metrics.mesh_truth import (
    MeshScorer,
    mesh_boolean_overlap,
    mesh_chamfer,
    mesh_volume_overlap,
    score_mesh,
)
from hapticsim.metrics.score import Score, score
from hapticsim.metrics.theta import theta
from hapticsim.metrics.volume import (
    VolumeOverlap,
    alpha,
    beta,
    epsilon,
    iou,
    sample_interior,
    volume_overlap,
)

__all__ = [
    "MeshScorer",
    "Score",
    "VolumeOverlap",
    "alpha",
    "beta",
    "chamfer",
    "epsilon",
    "iou",
    "mesh_boolean_overlap",
    "mesh_chamfer",
    "mesh_volume_overlap",
    "sample_interior",
    "sample_surface",
    "score",
    "score_mesh",
    "surface_distance",
    "theta",
    "volume_overlap",
]
