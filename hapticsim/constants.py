"""Tolerances and default ranges gathered in one place."""

from __future__ import annotations

#: Default bounds of the shape exponents eps1, eps2 (SPEC §1).
EPS_MIN: float = 0.1
EPS_MAX: float = 2.0
#: Bounds of the tapering parameters tx, ty (paper eq. 2).
TAPER_MAX: float = 1.0
#: Tolerance for R^T R = I and det R = 1 when validating rotations.
ROTATION_TOL: float = 1e-6
#: Smallest tapering factor 1 + t*z/a3 used when untapering (avoids division by zero at an apex).
MIN_TAPER_FACTOR: float = 1e-6
#: Lambda weighting the normal term of the EOF (paper Section IV).
DEFAULT_LAMBDA: float = 0.5
#: Largest |coordinate| [m] accepted in contact points and superquadric files: far beyond any
#: workspace; the fitter overflows from about 1e50 m (measured: contacts scaled to 1e40 m fit,
#: 1e60 m overflow).
MAX_COORDINATE: float = 1e6
#: Smallest extent [m] of a contact set and smallest semi-axis read from a file: a nanometre;
#: the fitter's bounds underflow below about 1e-150 m (measured: 1e-100 m fits, 1e-150 m fails).
MIN_LENGTH: float = 1e-9
#: Largest integer argument accepted anywhere (int64-exact; counts have tighter limits).
MAX_INT: int = 2**62
#: Most contacts a data set, an exploration or a sweep setting may ask for (arrays are sized by
#: it: 10^6 contacts are 24 MB per (n, 3) array).
MAX_CONTACTS: int = 1_000_000
#: How contacts are sensed: MuJoCo's exact contacts, or estimated from taxel pads (SPEC §11).
SENSINGS: tuple[str, ...] = ("exact", "tactile")
#: What a tactile hand's controllers steer on (SPEC §11): the skin's estimated contacts, or
#: MuJoCo's contact list (as before the skin closed the loop).
STEERINGS: tuple[str, ...] = ("skin", "contacts")
#: Contacts an exploration must gather to count as a success (a fit needs 13).
MIN_CONTACTS: int = 20
#: Contacts an exploration gathers by default (paper IV).
DEFAULT_CONTACTS: int = 150
#: Largest budget of EOF evaluations (10^9 evaluations of 150 contacts take about a day).
MAX_BUDGET: int = 1_000_000_000
#: Most runs (data sets) per setting of a sweep (``reproduce --runs``).
MAX_RUNS: int = 100_000
#: Interior samples per solid (alpha, beta) and Chamfer points per surface of the per-step
#: scorer (``TruthScorer``, any solids) and of the environment by default: quasi-random,
#: RMS error of epsilon 0.0032 and of the Chamfer distance 1.2 % (docs/fast-loop).
SCORE_SAMPLES: int = 4096
SCORE_CHAMFER_POINTS: int = 128
#: Fingertip radius [m] of hapticsim's own hand (``models/hand.xml``, class ``tip``): its MuJoCo
#: fingertips, the analytic backend's tactile pads and the support's clearance.
FINGERTIP_RADIUS: float = 0.008
#: Coulomb friction of fingertip/object contacts (the MuJoCo scene's, the analytic backend's
#: skin traction); contacts stay clean at <= 0.3.
DEFAULT_FRICTION: float = 0.2
