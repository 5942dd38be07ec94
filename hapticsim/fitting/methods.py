"""The four estimation schemes of the paper (Section IV, SPEC §3) and their defaults.

=======  ================  ==========================================================
name     data              minimiser
=======  ================  ==========================================================
``LS``   points            least squares from the paper's initial estimate
``H``    points            genetic algorithm, then least squares (hybrid)
``nLS``  points, normals   as LS, EOF with normals
``nH``   points, normals   as H, EOF with normals
=======  ================  ==========================================================

Beyond the paper, :data:`FIT_METHODS` adds ``nML`` (points, normals, optionally free space): the
hybrid search of nH on a maximum-likelihood objective (:mod:`hapticsim.fitting.ml`). The paper
reproduction compares :data:`METHODS` only.
"""

from __future__ import annotations

#: Method names, in the paper's order.
METHODS: tuple[str, ...] = ("LS", "H", "nLS", "nH")
#: Every method :func:`~hapticsim.fitting.fit` accepts: the paper's, then nML.
FIT_METHODS: tuple[str, ...] = (*METHODS, "nML")
#: Methods whose objective uses the contact normals.
NORMAL_METHODS: frozenset[str] = frozenset({"nLS", "nH", "nML"})
#: Methods with the genetic algorithm.
HYBRID_METHODS: frozenset[str] = frozenset({"H", "nH", "nML"})
#: Default evaluation budget of every method (EOF evaluations, SPEC §3). Chosen so that a
#: default nH fit of 150 contacts takes at most 0.5 s (median) on the development machine (2 vCPU
#: Xeon 2.5 GHz: 0.30 s of CPU; wall clock 0.55-0.6 s while other jobs kept the load at 5-6),
#: with the same mean epsilon as at 6000 on the paper's bodies. LS and nLS usually converge in
#: 300-500 evaluations, well within it.
DEFAULT_BUDGET: int = 5000


def uses_normals(method: str) -> bool:
    """Whether `method` fits the normals too (nLS, nH, nML)."""
    return method in NORMAL_METHODS
