"""Real object meshes from an installed package: pybullet's ``pybullet_data`` (extra ``objects``).

pybullet's wheel ships the models of bullet3's data folder, among them 1,000 procedural objects
(``random_urdfs/000`` ... ``999``, each a few convex blobs fused into one hand-sized shape) and
classic test objects (the duck, the teddy, a lego brick, a soccer ball, ...). hapticsim reads them
from the installed package (``pybullet_data.getDataPath()``) and never copies them; the wheel is
distributed under the zlib license (bullet3's ``LICENSE.txt``; a few model folders carry their own
``license.txt`` beside them).

An object is named ``pybullet:NAME`` (:data:`PREFIX`): NAME is an alias (:data:`ALIASES`:
``duck``, ``teddy``, ``lego``, ``jenga``, ``domino``, ``soccerball``, ``mug``), ``random/NNN``
(a procedural object), or a URDF or mesh file's path inside ``pybullet_data``. A URDF gives the
mesh of its first visual geometry and that mesh's scale (the true surface), and, when its
collision mesh is made of convex bodies (the procedural objects' blobs, the duck's V-HACD hulls),
those as the convex pieces MuJoCo collides with (:attr:`MeshSolid.pieces`: no coacd run, which
takes over a minute on the duck); a mesh file is read in metres.

The models are not all clean closed surfaces: each is repaired as it is read, as every mesh is
(:func:`hapticsim.data.mesh_repair.repair_mesh`: vertices merged across texture seams, small
holes filled, slivers collapsed, its closed bodies fused by manifold3d's boolean union where
they overlap or touch). What still is not one object is refused with a message naming why.
"""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from functools import lru_cache
from pathlib import Path

import numpy as np

from hapticsim.data.mesh_repair import repair_mesh
from hapticsim.errors import InvalidInputError
from hapticsim.geometry.mesh_solid import MeshSolid

#: How a library object's source starts.
PREFIX: str = "pybullet:"
#: Short names of the classic objects: their URDFs inside ``pybullet_data``.
ALIASES: dict[str, str] = {
    "duck": "duck_vhacd.urdf",
    "teddy": "teddy_vhacd.urdf",
    "lego": "lego/lego.urdf",
    "jenga": "jenga/jenga.urdf",
    "domino": "domino/domino.urdf",
    "soccerball": "soccerball.urdf",
    "mug": "objects/mug.urdf",
}
#: Number of procedural objects (``random/000`` ... ``random/999``).
RANDOM_COUNT: int = 1000


def data_path() -> Path:
    """The installed ``pybullet_data`` folder.

    Raises:
        InvalidInputError: pybullet is not installed (the message says how to install it).
    """
    try:
        import pybullet_data
    except ImportError:
        raise InvalidInputError(
            "pybullet objects need pybullet's bundled models: pip install 'hapticsim[objects]'"
        ) from None
    return Path(pybullet_data.getDataPath())


def library_file(name: str) -> Path:
    """The URDF or mesh file of a library object's NAME (module docstring).

    Raises:
        InvalidInputError: pybullet missing, or no such object (the message lists the kinds of
            names).
    """
    root = data_path()
    if name.startswith("random/"):
        number = name.split("/", 1)[1]
        if not (number.isdigit() and len(number) == 3 and int(number) < RANDOM_COUNT):
            raise InvalidInputError(
                f"unknown pybullet object {name!r}: procedural objects are random/000 ... "
                f"random/{RANDOM_COUNT - 1:03d}"
            )
        relative = f"random_urdfs/{number}/{number}.urdf"
    else:
        relative = ALIASES.get(name, name)
    path = (root / relative).resolve()
    if root.resolve() not in path.parents or not path.is_file():
        raise InvalidInputError(
            f"unknown pybullet object {name!r}: give one of {', '.join(ALIASES)}, random/NNN "
            "(000-999), or a .urdf or mesh file inside pybullet_data"
        )
    return path


def _urdf_mesh(path: Path, element: str) -> tuple[Path, np.ndarray] | None:
    """The mesh file and scale (3,) of a URDF's first `element` (visual, collision) geometry,
    or None when it has none."""
    try:
        root = ElementTree.parse(path).getroot()
    except ElementTree.ParseError as exc:
        raise InvalidInputError(f"cannot read {path}: {exc}") from exc
    mesh = root.find(f".//{element}/geometry/mesh")
    if mesh is None or not mesh.get("filename"):
        return None
    scale = np.array([float(v) for v in mesh.get("scale", "1 1 1").split()])
    if scale.shape != (3,) or not np.all(np.isfinite(scale)) or np.any(scale <= 0):
        raise InvalidInputError(f"{path}: its mesh scale must be three numbers > 0")
    return path.parent / mesh.get("filename", ""), scale


def _load(path: Path) -> object:
    """A mesh file through trimesh, its vertices merged across texture seams."""
    import trimesh

    try:
        mesh = trimesh.load(str(path), force="mesh", process=False)
    except Exception as exc:  # noqa: BLE001 - trimesh raises many kinds on bad files
        raise InvalidInputError(f"cannot read the mesh {path}: {exc}") from exc
    mesh.merge_vertices(merge_tex=True, merge_norm=True)
    return mesh


@lru_cache(maxsize=32)
def _hulls(path: Path, scale: tuple[float, float, float]) -> tuple[np.ndarray, ...] | None:
    """The convex bodies of a collision mesh (vertex arrays in metres), or None when one of them
    is not convex (coacd then decomposes the object instead)."""
    bodies = _load(path).split(only_watertight=False)  # type: ignore[attr-defined]
    if not bodies or not all(b.is_convex for b in bodies):
        return None
    return tuple(np.asarray(b.vertices, np.float64) * np.asarray(scale) for b in bodies)


@lru_cache(maxsize=32)
def _repaired(path: Path, scale: tuple[float, float, float]) -> MeshSolid:
    """The closed solid of a mesh file, repaired (:func:`~hapticsim.data.mesh_repair.
    repair_mesh`), in metres."""
    import trimesh

    try:
        mesh = trimesh.load(str(path), force="mesh", process=False)
    except Exception as exc:  # noqa: BLE001 - trimesh raises many kinds on bad files
        raise InvalidInputError(f"cannot read the mesh {path}: {exc}") from exc
    vertices = np.asarray(mesh.vertices, np.float64) * np.asarray(scale)
    vertices, faces, report = repair_mesh(vertices, mesh.faces, path.name)
    return MeshSolid(vertices, faces, repair=report.to_dict())


def load_library_object(name: str, scale: float = 1.0) -> MeshSolid:
    """A library object (module docstring), in metres times `scale`, centroid at the origin.

    Raises:
        InvalidInputError: pybullet missing, an unknown name, or a model that is not one closed
            body after repair.
    """
    path = library_file(name)
    mesh_scale, hulls = np.ones(3), None
    if path.suffix.lower() == ".urdf":
        visual = _urdf_mesh(path, "visual")
        if visual is None:
            raise InvalidInputError(f"{path} has no visual mesh")
        collision = _urdf_mesh(path, "collision")
        if collision is not None and collision[0].is_file():
            hulls = _hulls(collision[0], tuple(float(v) for v in collision[1] * scale))
        path, mesh_scale = visual
        if not path.is_file():
            raise InvalidInputError(f"the mesh {path} of pybullet object {name!r} is missing")
    solid = _repaired(path, tuple(float(v) for v in mesh_scale * scale))
    if hulls is not None:  # the model's own convex collision hulls: no decomposition needed
        solid = MeshSolid(solid.vertices, solid.faces, hulls, solid.repair)
    return solid.transformed(np.eye(3), -solid.centroid)


__all__ = ["ALIASES", "PREFIX", "RANDOM_COUNT", "data_path", "library_file", "load_library_object"]
