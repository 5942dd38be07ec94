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

The models are not all clean closed surfaces: each is repaired as it is read (vertices merged
across texture seams, zero-area faces dropped, its closed bodies fused by manifold3d's boolean
union; blobs that only touch, within :data:`TOUCH_GAP`, stay one rigid object of several
closed bodies). What still is not one object is refused with a message naming the problem (the
teddy, for one: its fused convex hulls do not close; the mug is open).
"""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from functools import lru_cache
from pathlib import Path

import numpy as np

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
#: Closed bodies of one model nearer than this [m] (nearest vertices) are one object: the
#: procedural objects' blobs touch at points and edges, which a boolean union leaves apart.
TOUCH_GAP: float = 1e-3
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
    """The closed solid of a mesh file, repaired (module docstring), in metres."""
    import manifold3d
    import trimesh

    mesh = _load(path)
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.remove_unreferenced_vertices()
    bodies = mesh.split(only_watertight=False)
    open_bodies = [b for b in bodies if not b.is_watertight]
    if open_bodies or not bodies:
        raise InvalidInputError(
            f"{path.name} is not a closed surface ({len(open_bodies)} of its {len(bodies)} "
            "bodies are open): it cannot be an object"
        )
    total = None
    for body in bodies:
        if body.volume < 0:
            body.invert()
        part = manifold3d.Manifold(manifold3d.Mesh(
            vert_properties=np.asarray(body.vertices, np.float32) * np.float32(scale),
            tri_verts=np.asarray(body.faces, np.uint32),
        ))  # fmt: skip
        total = part if total is None else total + part
    assert total is not None
    fused = total.to_mesh()
    out = trimesh.Trimesh(np.asarray(fused.vert_properties[:, :3], np.float64),
                          np.asarray(fused.tri_verts, np.int64))  # fmt: skip
    out.update_faces(out.nondegenerate_faces())
    out.remove_unreferenced_vertices()
    if not out.is_watertight:
        raise InvalidInputError(f"{path.name} is not a closed surface after its repair")
    pieces = _apart(out.split(only_watertight=False))
    if pieces > 1:
        raise InvalidInputError(
            f"{path.name} falls apart into {pieces} pieces more than {TOUCH_GAP * 1e3:g} mm "
            "apart: it is not one object"
        )
    return MeshSolid(np.asarray(out.vertices), np.asarray(out.faces))


def _apart(bodies: list) -> int:
    """How many groups the closed bodies form when bodies within :data:`TOUCH_GAP` of each
    other (nearest vertices) belong together."""
    from scipy.spatial import cKDTree

    group = list(range(len(bodies)))

    def root(i: int) -> int:
        while group[i] != i:
            i = group[i]
        return i

    trees = [cKDTree(np.asarray(b.vertices)) for b in bodies]
    for i in range(len(bodies)):
        for j in range(i + 1, len(bodies)):
            if trees[i].query(np.asarray(bodies[j].vertices))[0].min() <= TOUCH_GAP:
                group[root(j)] = root(i)
    return len({root(i) for i in range(len(bodies))})


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
        solid = MeshSolid(solid.vertices, solid.faces, hulls)
    return solid.transformed(np.eye(3), -solid.centroid)


__all__ = ["ALIASES", "PREFIX", "RANDOM_COUNT", "data_path", "library_file", "load_library_object"]
