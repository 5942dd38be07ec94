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
