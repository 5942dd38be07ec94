"""Small-vector helpers for the control loop (internal).

On (3,) arrays numpy's per-call overhead dominates (``numpy.cross`` costs tens of microseconds);
these work on plain floats and return new (3,) float arrays.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def cross(a: Array, b: Array) -> Array:
    """Cross product of two (3,) vectors."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def norm(a: Array) -> float:
    """Euclidean norm of a (3,) vector."""
    a0, a1, a2 = a.tolist()
    return math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)


def dot(a: Array, b: Array) -> float:
    """Dot product of two (3,) vectors."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return a0 * b0 + a1 * b1 + a2 * b2
