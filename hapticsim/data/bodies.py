"""The paper's four test bodies as superquadrics (paper III-A, SPEC §5).

Hand-held sizes of a few centimetres, axis-aligned at the origin so their parameters read like a
table (the synthetic patterns are defined in the body frame, so the pose does not matter to them):

==============  ====================  ==========  ============
name            a [m]                 eps         taper
==============  ====================  ==========  ============
tapered_box     (0.025, 0.035, 0.05)  (0.1, 0.1)  (0.4, 0.3)
cube            (0.03, 0.03, 0.03)    (0.1, 0.1)  (0, 0)
cylinder        (0.03, 0.03, 0.06)    (0.1, 1.0)  (0, 0)
ellipsoid       (0.04, 0.03, 0.05)    (1.0, 1.0)  (0, 0)
==============  ====================  ==========  ============

The tapered box widens along +z: 3 x 4.9 cm at the bottom, 7 x 9.1 cm at the top, 10 cm tall.
The cylinder has eps1 ~ 0.1 (flat ends) and eps2 = 1 (round cross-section), SPEC §1.
"""

from __future__ import annotations

from pathlib import Path
from types import MappingProxyType

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric

#: Names of the paper's bodies, in the paper's order.
BODY_NAMES: tuple[str, ...] = ("tapered_box", "cube", "cylinder", "ellipsoid")

BODIES = MappingProxyType(
    {
        "tapered_box": Superquadric(a=(0.025, 0.035, 0.05), eps=(0.1, 0.1), taper=(0.4, 0.3)),
        "cube": Superquadric(a=(0.03, 0.03, 0.03), eps=(0.1, 0.1)),
        "cylinder": Superquadric(a=(0.03, 0.03, 0.06), eps=(0.1, 1.0)),
        "ellipsoid": Superquadric(a=(0.04, 0.03, 0.05), eps=(1.0, 1.0)),
    }
)


def get_body(name: str) -> Superquadric:
    """The superquadric of a paper body by name (one of :data:`BODY_NAMES`).

    Raises:
        InvalidInputError: an unknown name; the message lists the valid ones.
    """
    if not isinstance(name, str) or name not in BODIES:
        raise InvalidInputError(f"unknown body {name!r}: the bodies are {', '.join(BODY_NAMES)}")
    return BODIES[name]


def resolve_body(name_or_path: str | Path) -> Superquadric:
    """A paper body by name, or a superquadric read from a JSON file (SPEC §6).

    A file may hold a bare superquadric or a fit result with a ``superquadric`` key.

    Args:
        name_or_path: one of :data:`BODY_NAMES`, or the path of a ``.json`` file.

    Raises:
        InvalidInputError: neither a body name nor a readable superquadric JSON file.
    """
    if isinstance(name_or_path, str) and name_or_path in BODIES:
        return BODIES[name_or_path]
    if not isinstance(name_or_path, (str, Path)):
        raise InvalidInputError(
            "`name_or_path` must be a body name or a JSON file path, got "
            f"{type(name_or_path).__name__}"
        )
    path = Path(name_or_path)
    if path.suffix.lower() == ".json" or path.is_file():
        return Superquadric.from_json(path)
    raise InvalidInputError(
        f"unknown body {str(name_or_path)!r}: give one of {', '.join(BODY_NAMES)} "
        "or a superquadric .json file"
    )


__all__ = ["BODIES", "BODY_NAMES", "get_body", "resolve_body"]
