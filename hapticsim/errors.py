"""The one exception root of hapticsim.

Every error that hapticsim raises on purpose derives from :class:`HapticsimError`, so a caller
(and the command line, which turns it into a one-line message and exit status 2) can catch them
all at once. Messages name the argument, what was expected and what came.
"""

from __future__ import annotations


class HapticsimError(ValueError):
    """Base class of all hapticsim errors (bad input, unusable data, failed simulation)."""


class InvalidInputError(HapticsimError):
    """An argument, file or array does not have the expected type, shape, range or content."""


class SimulationError(HapticsimError):
    """The physics simulation cannot do what was asked (unreachable object, instability)."""
