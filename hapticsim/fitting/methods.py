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
hybrid search of nH on a maximum-likelihood objective (:mod:`hapticsim.fitting.ml`),
``multi`` (points, normals): a union of 1..K superquadrics (:mod:`hapticsim.fitting.multi`,
SPEC §10), and ``gpis`` (points, normals): the field's Gaussian-process implicit surface, a mesh
(:mod:`hapticsim.fitting.gpis`, extra ``gpis``), and ``supertoroid`` (points, normals): a
superquadric with a hole (:mod:`hapticsim.fitting.toroid`), and ``nH+track`` and ``multi+track``
(points in recording order, normals): the shape of an object that moved during the exploration,
fitted jointly with its pose at every contact (:mod:`hapticsim.fitting.track`, SPEC §12). The
paper reproduction compares
:data:`METHODS` only.
"""

from __future__ import annotations

#: Method names, in the paper's order.
METHODS: tuple[str, ...] = ("LS", "H", "nLS", "nH")
#: Every method :func:`~hapticsim.fitting.fit` accepts: the paper's, then nML, multi, gpis,
#: supertoroid and the two that track a moving object's pose.
FIT_METHODS: tuple[str, ...] = (*METHODS, "nML", "multi", "gpis", "supertoroid", "nH+track",
                                "multi+track")  # fmt: skip
#: Methods that fit the object's pose at every contact with its shape (SPEC §12).
TRACK_METHODS: frozenset[str] = frozenset({"nH+track", "multi+track"})
#: Methods whose objective uses the contact normals.
NORMAL_METHODS: frozenset[str] = frozenset({"nLS", "nH", "nML", "multi", "gpis", "supertoroid",
                                            *TRACK_METHODS})  # fmt: skip
#: Methods whose estimate may be a solid other than one superquadric (a union, a mesh, a
#: supertoroid), or that track poses: they have no Laplace uncertainty.
SOLID_METHODS: frozenset[str] = frozenset({"multi", "gpis", "supertoroid", *TRACK_METHODS})
#: Methods with the genetic algorithm.
HYBRID_METHODS: frozenset[str] = frozenset({"H", "nH", "nML"})
#: Default evaluation budget of every method (EOF evaluations, SPEC §3). A default nH fit of
#: 150 contacts takes a median 0.017 s of CPU on an AMD Zen 5 core (0.028 s before the GA share
#: fell to 0.05, see :mod:`hapticsim.fitting.hybrid`; 0.055 s on the first development machine,
#: a 2 vCPU Xeon, before the Jacobian was vectorised), and the budget buys robustness: on the
#: hardest random tapered cases found by ``scripts/global_minimum.py`` the share of fits missing
#: the lowest EOF fell from 42 % at 5000 to 13 % at 7500 (3 % at 10 000), measured with the
#: earlier GA share of 0.4. LS and nLS usually converge in 300-500 evaluations, well within it.
DEFAULT_BUDGET: int = 7500
#: The budget of the paper reproduction (Figs. 4 and 5, ``hapticsim reproduce``): every method
#: at the same budget, as in the paper's Section IV; kept at the value RESULTS.md was made with.
PAPER_BUDGET: int = 5000


def uses_normals(method: str) -> bool:
    """Whether `method` fits the normals too (nLS, nH, nML, multi, gpis, supertoroid)."""
    return method in NORMAL_METHODS
