"""The superquadric parameter vector's layout: the one place that spells its order.

``Superquadric.to_vector`` / ``from_vector`` (SPEC §1) and every compiled kernel read the 13
numbers through these names, numpy code by the slices, numba code by the first indices (plain
ints, which numba folds into constants):

=====  ===========  ======================================================  ==========
index  name         meaning                                                 unit
=====  ===========  ======================================================  ==========
0-2    ``a``        semi-axes a1, a2, a3                                    [m]
3-4    ``eps``      shape exponents eps1, eps2                              [1]
5-6    ``taper``    tapers tx, ty                                           [1]
7-9    ``rotvec``   rotation vector of R (axis times angle)                 [rad]
10-12  ``center``   centre x0                                               [m]
=====  ===========  ======================================================  ==========

Nothing here imports numpy or numba.
"""

from __future__ import annotations

#: Length of the parameter vector (paper: 13 parameters).
N_PARAMS: int = 13
#: First index of each field.
I_A, I_EPS, I_TAPER, I_ROTVEC, I_CENTER = 0, 3, 5, 7, 10
#: Slices of the fields.
SLICE_A = slice(I_A, I_A + 3)
SLICE_EPS = slice(I_EPS, I_EPS + 2)
SLICE_TAPER = slice(I_TAPER, I_TAPER + 2)
SLICE_ROTVEC = slice(I_ROTVEC, I_ROTVEC + 3)
SLICE_CENTER = slice(I_CENTER, I_CENTER + 3)
#: Names of the 13 entries, in order.
PARAM_NAMES: tuple[str, ...] = (
    "a1", "a2", "a3", "eps1", "eps2", "tx", "ty", "rx", "ry", "rz", "x0", "y0", "z0",
)  # fmt: skip

__all__ = [
    "I_A",
    "I_CENTER",
    "I_EPS",
    "I_ROTVEC",
    "I_TAPER",
    "N_PARAMS",
    "PARAM_NAMES",
    "SLICE_A",
    "SLICE_CENTER",
    "SLICE_EPS",
    "SLICE_ROTVEC",
    "SLICE_TAPER",
]
