"""Reading any solid from its JSON: a superquadric (SPEC §6), a union (SPEC §10), a supertoroid
(``{"kind": "supertoroid", ...}``, SPEC §10's part kind with a hole), a closed triangle mesh
(``{"mesh": {"vertices": [[x, y, z], ...], "faces": [[i, j, k], ...]}}``, as
:meth:`MeshSolid.to_dict` writes it: a GPIS estimate), or a fit result holding any of them
(``"solid"`` beside ``"superquadric"``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from hapticsim._files import read_json
from hapticsim.errors import InvalidInputError
from hapticsim.geometry.mesh_solid import MeshSolid
from hapticsim.geometry.solid import Solid
from hapticsim.geometry.superquadric import Superquadric
from hapticsim.geometry.supertoroid import Supertoroid
from hapticsim.geometry.union import SuperquadricUnion

#: Part kinds of SPEC §10 and their readers (``"kind"`` absent: a superquadric).
PART_KINDS: dict[str, Any] = {"superquadric": Superquadric.from_dict,
                              "supertoroid": Supertoroid.from_dict}  # fmt: skip


def part_from_dict(data: Any) -> Solid:
    """One part by its ``"kind"`` (SPEC §10; absent: ``"superquadric"``).

    Raises:
        InvalidInputError: an unknown kind (the kinds named), or a malformed part.
    """
    from hapticsim.errors import ChoiceError

    kind = data.get("kind", "superquadric") if isinstance(data, dict) else "superquadric"
    if kind not in PART_KINDS:
        raise ChoiceError("kind", kind, PART_KINDS)
    if kind == "superquadric" and isinstance(data, dict) and "kind" in data:
        data = {k: v for k, v in data.items() if k != "kind"}
    return PART_KINDS[kind](data)


def solid_from_dict(data: Any) -> Solid:
    """The solid a JSON object describes: ``{"parts": [...]}`` a union, ``{"mesh": {...}}`` a
    mesh, a fit result its ``"solid"`` (or ``"superquadric"``), anything else a superquadric
    (SPEC §6's keys).

    Raises:
        InvalidInputError: not a JSON object, or a malformed superquadric, union or mesh (named).
    """
    if isinstance(data, dict) and isinstance(data.get("solid"), dict):
        data = data["solid"]
    if isinstance(data, dict) and "parts" in data:
        return SuperquadricUnion.from_dict(data)
    if isinstance(data, dict) and "mesh" in data:
        mesh = data["mesh"]
        if not (isinstance(mesh, dict) and {"vertices", "faces"} <= set(mesh)):
            raise InvalidInputError(
                'a mesh solid must be {"mesh": {"vertices": [[x, y, z], ...], "faces": '
                "[[i, j, k], ...]}}"
            )

        return MeshSolid(mesh["vertices"], mesh["faces"])
    if not isinstance(data, dict):
        raise InvalidInputError(
            f"a solid must be a JSON object (a superquadric or a union), got "
            f"{type(data).__name__}"
        )
    return part_from_dict(data)


def solid_from_json(path_or_text: str | Path) -> Solid:
    """Read a solid (:func:`solid_from_dict`) from a JSON file path or a JSON string."""

    return solid_from_dict(read_json(path_or_text))


__all__ = ["PART_KINDS", "part_from_dict", "solid_from_dict", "solid_from_json"]
