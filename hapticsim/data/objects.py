"""Objects from anywhere: body names, superquadric and union files, random shapes, mesh files and
a library of real objects.

An *object spec* names where an object comes from; :meth:`ObjectSpec.resolve` turns it into the
ground truth posed in the world, a solid (:class:`~hapticsim.geometry.solid.Solid`: a
superquadric, a union of superquadrics or a mesh). The kinds (:data:`OBJECT_KINDS`):

====================  ========================================================================
``body``              one of the paper's bodies by name (:data:`~hapticsim.data.bodies.BODY_NAMES`)
``superquadric``      a JSON file: a superquadric (SPEC §6), a union (SPEC §10) or a fit result
``random``            a random superquadric without taper, drawn from the seed
``random_tapered``    a random tapered superquadric, drawn from the seed
``random_composite``  a union of 2-4 overlapping random superquadrics (:func:`random_composite`)
``random_holed``      a random ring, a supertoroid (:func:`random_holed`)
``random_handled``    a random body with a ring handle (:func:`random_handled`)
``mesh``              a mesh file (STL, OBJ, PLY, OFF, GLB or glTF, read by trimesh), metres
                      times ``scale``
``pybullet``          ``pybullet:NAME``, a model of the installed ``pybullet_data``
                      (:mod:`hapticsim.data.library`, extra ``objects``)
====================  ========================================================================

Placement: a superquadric or union stands where its parameters put it (bodies and random shapes
at the origin); a mesh is moved so that its centroid is at the origin. A :class:`Pose` places
the object instead: ``x_world = R @ (scale * x_file) + t``, applied to the file's own
coordinates (a mesh is then *not* re-centred). A mesh is repaired into one closed solid as it is
read (:mod:`hapticsim.data.mesh_repair`); what is not one solid is refused, saying why.

Nothing here imports trimesh until a mesh is read or written.
"""

from __future__ import annotations

import io as _io
import json
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._files import atomic_write
from hapticsim._validate import as_generator, did_you_mean, finite_array, finite_float
from hapticsim.constants import EPS_MAX, EPS_MIN, TAPER_MAX
from hapticsim.data.bodies import BODY_NAMES, get_body
from hapticsim.data.library import PREFIX, load_library_object
from hapticsim.data.mesh_repair import repair_mesh
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import (
    Superquadric,
    SuperquadricUnion,
    quaternion_to_matrix,
    random_rotation,
    solid_from_json,
)
from hapticsim.geometry.mesh_solid import MeshSolid
from hapticsim.geometry.solid import Solid

Array = NDArray[np.float64]

#: Object kinds an :class:`ObjectSpec` can name.
OBJECT_KINDS: tuple[str, ...] = (
    "body", "superquadric", "random", "random_tapered", "random_composite", "random_holed",
    "random_handled", "mesh", "pybullet",
)  # fmt: skip
#: Names of the random kinds (drawn from a seed).
RANDOM_KINDS: tuple[str, ...] = (
    "random", "random_tapered", "random_composite", "random_holed", "random_handled",
)  # fmt: skip
#: Mesh file formats (suffixes) read through trimesh.
MESH_SUFFIXES: tuple[str, ...] = (".stl", ".obj", ".ply", ".off", ".glb", ".gltf")
#: Default ranges of random superquadrics: semi-axes [m], exponents, tapers.
RANDOM_A_RANGE: tuple[float, float] = (0.02, 0.05)
RANDOM_EPS_RANGE: tuple[float, float] = (0.1, 1.0)
RANDOM_TAPER_RANGE: tuple[float, float] = (-0.4, 0.4)

#: One line naming every object kind, for help texts.
OBJECT_HELP: str = (
    "a paper body (tapered_box, cube, cylinder, ellipsoid), a superquadric or union .json "
    "file, random / random_tapered / random_composite / random_holed / random_handled (drawn "
    "from the seed), a "
    "mesh file (.stl, .obj, .ply, .off, .glb; metres unless scaled), or pybullet:NAME (duck, "
    "mug, random/017, ...; extra objects)"
)

Truth = Solid


def _check_range(name: str, value: Any, low: float, high: float) -> tuple[float, float]:
    try:
        pair = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        pair = ()
    if len(pair) != 2 or not all(np.isfinite(pair)) or not low <= pair[0] <= pair[1] <= high:
        raise InvalidInputError(
            f"`{name}` must be a (low, high) pair with {low} <= low <= high <= {high}, "
            f"got {value!r}"
        )
    return pair  # type: ignore[return-value]


def random_superquadric(
    rng: np.random.Generator | int | None,
    tapered: bool = False,
    a_range: tuple[float, float] = RANDOM_A_RANGE,
    eps_range: tuple[float, float] = RANDOM_EPS_RANGE,
    taper_range: tuple[float, float] = RANDOM_TAPER_RANGE,
) -> Superquadric:
    """A random superquadric at the origin, axis-aligned.

    Draws, in this order, the semi-axes (3, uniform in `a_range` [m]), the exponents (2, uniform
    in `eps_range`) and, when `tapered`, the tapers (2, uniform in `taper_range`).

    Args:
        rng: seed or generator.
        tapered: draw tapers (else none).
        a_range: (low, high) semi-axis range [m].
        eps_range: (low, high) exponent range, within [0.1, 2].
        taper_range: (low, high) taper range, within [-1, 1].
    """
    gen = as_generator(rng)
    a_lo, a_hi = _check_range("a_range", a_range, 1e-4, 10.0)
    e_lo, e_hi = _check_range("eps_range", eps_range, EPS_MIN, EPS_MAX)
    t_lo, t_hi = _check_range("taper_range", taper_range, -TAPER_MAX, TAPER_MAX)
    a = gen.uniform(a_lo, a_hi, size=3)
    eps = gen.uniform(e_lo, e_hi, size=2)
    taper = gen.uniform(t_lo, t_hi, size=2) if tapered else np.zeros(2)
    return Superquadric(a=a, eps=eps, taper=taper)


#: Parts of a random composite (at least, at most).
COMPOSITE_PARTS: tuple[int, int] = (2, 4)
#: Semi-axis range [m] of a random composite's parts.
COMPOSITE_A_RANGE: tuple[float, float] = (0.008, 0.03)
#: Largest bounding radius [m] of a random composite (hand-held; the hand takes up to 0.12).
COMPOSITE_RADIUS: float = 0.08
#: Least share of each part's volume outside the other parts (every part shows).
COMPOSITE_SHOWS: float = 0.4


#: Ranges of a random ring: the tube's half-widths [m], its exponents, the hole ratio.
HOLED_A_RANGE: tuple[float, float] = (0.008, 0.016)
HOLED_EPS_RANGE: tuple[float, float] = (0.3, 1.2)
HOLED_HOLE_RANGE: tuple[float, float] = (1.6, 3.2)


def random_holed(rng: np.random.Generator | int | None) -> Any:
    """A random ring (a :class:`~hapticsim.geometry.supertoroid.Supertoroid`) of hand-held size,
    its hole's centre at the origin: the tube's half-widths uniform in :data:`HOLED_A_RANGE`
    (a1 = a2, a round ring, or a1 != a2 with equal chance), exponents in
    :data:`HOLED_EPS_RANGE`, the hole ratio in :data:`HOLED_HOLE_RANGE`, a uniformly random
    orientation (outer diameters 40-100 mm).

    Args:
        rng: seed or generator.
    """
    from hapticsim.geometry.supertoroid import Supertoroid

    gen = as_generator(rng)
    a = gen.uniform(*HOLED_A_RANGE, size=3)
    if gen.random() < 0.5:
        a[1] = a[0]
    eps = gen.uniform(*HOLED_EPS_RANGE, size=2)
    hole = float(gen.uniform(*HOLED_HOLE_RANGE))
    return Supertoroid(a, eps, hole, random_rotation(gen), np.zeros(3))


def random_handled(rng: np.random.Generator | int | None) -> Any:
    """A random body with a ring handle: a superquadric of hand-held size (semi-axes 22-35 mm,
    exponents in [0.2, 1], upright) and a ring (:func:`random_holed`'s shape, its tube
    4-7 mm) standing on its side with its axis tangent to the body, its centre set so that a
    third of the ring's outer half-width lies inside the body, at a random height and side;
    the union's volume centre at the origin.

    Args:
        rng: seed or generator.
    """
    from hapticsim.geometry.supertoroid import Supertoroid
    from hapticsim.geometry.union import SuperquadricUnion

    gen = as_generator(rng)
    body = Superquadric(a=gen.uniform(0.022, 0.035, 3), eps=gen.uniform(0.2, 1.0, 2))
    tube = gen.uniform(0.004, 0.007)
    ring_shape = (np.array([tube, tube, gen.uniform(0.004, 0.008)]), gen.uniform(0.4, 1.0, 2),
                  float(gen.uniform(2.0, 3.0)))  # fmt: skip
    side = gen.uniform(-np.pi, np.pi)
    out = np.array([np.cos(side), np.sin(side), 0.0])  # where the handle sticks out
    height = gen.uniform(-0.4, 0.4) * body.a[2]
    # the body's surface along `out` at that height (a ray from outside), then the ring there
    reach = 4.0 * body.bounding_radius
    start = np.array([0.0, 0.0, height]) + reach * out
    depth = float(body.first_hits(start[None], -out[None], reach, (256, 32, 32))[0])
    surface = start - depth * out
    a, eps, hole = ring_shape
    radius = a[0] * (hole + 1.0)  # the ring's outer half-width
    center = surface + out * (radius * (2.0 / 3.0))
    # body z of the ring = the tangent (its hole faces along the tangent); body x = out
    tangent = np.cross([0.0, 0.0, 1.0], out)
    rotation = np.column_stack([out, np.cross(tangent, out), tangent])
    union = SuperquadricUnion((body, Supertoroid(a, eps, hole, rotation, center)))
    return union.transformed(np.eye(3), -union.center)


def random_composite(rng: np.random.Generator | int | None, parts: int | None = None) -> Any:
    """A random union of overlapping superquadrics of hand-held size, volume centre at the origin.

    Draws the number of parts (uniform in :data:`COMPOSITE_PARTS` unless given), then part by
    part: semi-axes uniform in :data:`COMPOSITE_A_RANGE`, exponents uniform in [0.1, 1], a
    uniformly random orientation, and, from the second part on, where it attaches: a point on
    the surface of a part drawn before (uniform angles), its centre set back inside along that
    point's normal so that 30-70 % of its extent in that direction lies inside. A draw whose union
    is larger than :data:`COMPOSITE_RADIUS` or hides more than 1 - :data:`COMPOSITE_SHOWS` of a
    part is drawn again, from the same generator (at most 200 times).

    Args:
        rng: seed or generator.
        parts: the number of parts (2 to 4), or None to draw it.

    Raises:
        InvalidInputError: `parts` out of range, or no acceptable draw in 200.
    """

    gen = as_generator(rng)
    lo, hi = COMPOSITE_PARTS
    if parts is not None and (not isinstance(parts, (int, np.integer)) or not lo <= parts <= hi):
        raise InvalidInputError(f"`parts` must be an int in [{lo}, {hi}], got {parts!r}")
    count = int(gen.integers(lo, hi + 1)) if parts is None else int(parts)
    for _ in range(200):
        shapes: list[Superquadric] = []
        for k in range(count):
            a = gen.uniform(*COMPOSITE_A_RANGE, size=3)
            eps = gen.uniform(0.1, 1.0, size=2)
            rotation = random_rotation(gen)
            center = np.zeros(3)
            if k:
                host = shapes[int(gen.integers(k))]
                eta, omega = gen.uniform(-np.pi / 2, np.pi / 2), gen.uniform(-np.pi, np.pi)
                point, normal = (v[0] for v in host.surface(np.array([eta]), np.array([omega])))
                part = Superquadric(a=a, eps=eps, rotation=rotation)
                reach = 4.0 * part.bounding_radius  # its extent along the normal, by a ray
                extent = reach - float(part.first_hits(reach * normal[None], -normal[None],
                                                       reach, (64, 32))[0])  # fmt: skip
                center = point - normal * extent * (1.0 - 2.0 * gen.uniform(0.3, 0.7))
            shapes.append(Superquadric(a=a, eps=eps, rotation=rotation, center=center))
        union = SuperquadricUnion(tuple(shapes))
        shows = union._unique_volumes / np.array([p.volume for p in shapes])
        if k and np.min(shows[1:]) < COMPOSITE_SHOWS:
            continue
        union = union.transformed(np.eye(3), -union.center)
        if union.bounding_radius <= COMPOSITE_RADIUS:
            return union
    raise InvalidInputError("no acceptable random composite in 200 draws")


@dataclass(frozen=True)
class Pose:
    """A rigid placement ``x -> rotation @ x + position``.

    Attributes:
        position: (3,) float [m, world].
        rotation: (3, 3) float, a proper rotation (identity by default).
    """

    position: Array
    rotation: Array = field(default_factory=lambda: np.eye(3))

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", finite_array(self.position, "position", (3,)))
        rot = finite_array(self.rotation, "rotation", (3, 3))
        if not np.allclose(rot.T @ rot, np.eye(3), atol=1e-6) or np.linalg.det(rot) < 0:
            raise InvalidInputError("`rotation` must be a proper rotation matrix")
        object.__setattr__(self, "rotation", rot)

    @classmethod
    def parse(cls, text: str) -> Pose:
        """A pose from ``"x,y,z"`` [m] or ``"x,y,z,qw,qx,qy,qz"`` (unit quaternion, w first).

        Raises:
            InvalidInputError: not 3 or 7 comma-separated numbers, or a zero quaternion.
        """
        try:
            values = [float(v) for v in str(text).replace(" ", "").split(",")]
        except ValueError:
            values = []
        if len(values) not in (3, 7) or not all(np.isfinite(values)):
            raise InvalidInputError(
                f"`pose` must be 'x,y,z' [m] or 'x,y,z,qw,qx,qy,qz', got {text!r}"
            )
        if len(values) == 3:
            return cls(np.array(values))
        q = np.array(values[3:])
        if np.linalg.norm(q) < 1e-9:
            raise InvalidInputError(f"`pose` quaternion must be non-zero, got {values[3:]}")
        return cls(np.array(values[:3]), quaternion_to_matrix(q / np.linalg.norm(q)))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready ``{"position": [...], "rotation": [[...], ...]}``."""
        return {"position": self.position.tolist(), "rotation": self.rotation.tolist()}


def _kind_of(source: str) -> str:
    if source in BODY_NAMES:
        return "body"
    if source in RANDOM_KINDS:
        return source

    if source.startswith(PREFIX):
        return "pybullet"
    suffix = Path(source).suffix.lower()
    if suffix == ".json":
        return "superquadric"
    if suffix in MESH_SUFFIXES:
        return "mesh"
    if suffix:
        raise InvalidInputError(
            f"unknown object file format {suffix!r} ({source}): give a superquadric .json or a "
            f"mesh file ({', '.join(s.lstrip('.').upper() for s in MESH_SUFFIXES)})"
        )

    hint = did_you_mean(source, (*BODY_NAMES, *RANDOM_KINDS))
    raise InvalidInputError(f"unknown object {source!r}{hint}: give {OBJECT_HELP}")


@dataclass(frozen=True)
class ObjectSpec:
    """Where an object comes from, and how it is scaled and placed.

    Attributes:
        source: a body name, ``"random"``, ``"random_tapered"``, ``"random_composite"``, the
            path of a superquadric or union ``.json`` or of a mesh file (``.stl``, ``.obj``,
            ``.ply``, ``.off``), or ``pybullet:NAME`` (a library object, centred on its
            centroid before `pose` places it).
        scale: factor from the file's units to metres (> 0): 0.001 for a mesh in millimetres.
        pose: placement of the object's own frame in the world (module docstring); None keeps
            a superquadric's own pose and puts a mesh's centroid at the origin.
        kind: one of :data:`OBJECT_KINDS`, derived from `source`.

    Raises:
        InvalidInputError: an unknown name or file format (the message lists the kinds), a
            missing file, or a bad scale.
    """

    source: str
    scale: float = 1.0
    pose: Pose | None = None
    kind: str = field(init=False)

    def __post_init__(self) -> None:
        if isinstance(self.source, Path):
            object.__setattr__(self, "source", str(self.source))
        if not isinstance(self.source, str) or not self.source:
            raise InvalidInputError(f"`source` must be a non-empty string, got {self.source!r}")
        object.__setattr__(self, "scale", finite_float(self.scale, "scale"))
        if self.scale <= 0:
            raise InvalidInputError(f"`scale` must be > 0, got {self.scale!r}")
        if self.pose is not None and not isinstance(self.pose, Pose):
            raise InvalidInputError(f"`pose` must be a Pose or None, got {self.pose!r}")
        kind = _kind_of(self.source)
        if kind in ("superquadric", "mesh") and not Path(self.source).is_file():
            raise InvalidInputError(f"object file not found: {self.source}")
        object.__setattr__(self, "kind", kind)

    @property
    def name(self) -> str:
        """A short label: the body or kind name, the file's stem, or a library object's name
        (``/`` as ``-``)."""
        if self.kind in ("superquadric", "mesh"):
            return Path(self.source).stem
        if self.kind == "pybullet":
            return self.source.split(":", 1)[1].replace("/", "-")
        return self.source

    @property
    def is_random(self) -> bool:
        """True for the kinds drawn from a seed."""
        return self.kind in RANDOM_KINDS

    def resolve(self, rng: np.random.Generator | int | None = None) -> Truth:
        """The object posed in the world.

        Args:
            rng: seed or generator of the random kinds (unused by the others).

        Returns:
            the solid: a Superquadric, a SuperquadricUnion, or a MeshSolid for a mesh.

        Raises:
            InvalidInputError: an unreadable, empty, open (not watertight) or multi-body mesh,
                a malformed superquadric or union file, or a library object that cannot be read.
        """
        if self.kind in ("mesh", "pybullet"):
            if self.kind == "mesh":
                solid = load_mesh(self.source, self.scale)
            else:

                solid = load_library_object(self.source.split(":", 1)[1], self.scale)
            if self.pose is None:
                return solid.transformed(np.eye(3), -solid.centroid)
            return solid.transformed(self.pose.rotation, self.pose.position)
        shape: Solid
        if self.kind == "body":

            shape = get_body(self.source)
        elif self.kind == "superquadric":

            shape = solid_from_json(self.source)
        elif self.kind == "random_composite":
            shape = random_composite(rng)
        elif self.kind == "random_holed":
            shape = random_holed(rng)
        elif self.kind == "random_handled":
            shape = random_handled(rng)
        else:
            shape = random_superquadric(rng, tapered=self.kind == "random_tapered")
        if self.scale != 1.0:
            shape = shape.scaled(self.scale)
        if self.pose is not None:
            shape = shape.transformed(self.pose.rotation, self.pose.position)
        return shape

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description (kind, source, scale, pose)."""
        return {
            "kind": self.kind,
            "source": self.source,
            "scale": self.scale,
            "pose": None if self.pose is None else self.pose.to_dict(),
        }


def load_mesh(path: str | Path, scale: float = 1.0) -> MeshSolid:
    """Read a mesh file through trimesh, in the file's coordinates times `scale` [m], repaired
    into one closed solid (:func:`hapticsim.data.mesh_repair.repair_mesh`: vertices merged,
    collapsed and repeated faces dropped, winding fixed, small holes filled, slivers collapsed,
    bodies oriented outward and touching ones fused). What changed is said in one line on
    stderr and kept in the solid's ``repair`` (``metrics.json``'s ``mesh_repair``).

    Args:
        path: an ``.stl``, ``.obj``, ``.ply`` or ``.off`` file.
        scale: factor to metres (> 0).

    Raises:
        InvalidInputError: a missing file, an unknown format, a file trimesh cannot read, an
            empty mesh, a hole too large to fill (its size named), or bodies apart (how many,
            how far).
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise InvalidInputError(
            f"unknown mesh format {suffix or '(no suffix)'!r} ({path}): mesh files must be "
            f"{', '.join(s.lstrip('.').upper() for s in MESH_SUFFIXES)}"
        )
    if not path.is_file():
        raise InvalidInputError(f"mesh file not found: {path}")
    factor = finite_float(scale, "scale")
    if factor <= 0:
        raise InvalidInputError(f"`scale` must be > 0, got {scale!r}")
    import trimesh

    try:
        mesh = trimesh.load(str(path), force="mesh", process=False)
    except Exception as exc:  # trimesh raises many types for malformed files
        raise InvalidInputError(f"cannot read mesh file {path}: {exc}") from exc
    faces = getattr(mesh, "faces", None)
    if not isinstance(mesh, trimesh.Trimesh) or faces is None or len(faces) == 0:
        raise InvalidInputError(f"mesh file {path} is empty: it holds no triangles")
    vertices, faces, report = repair_mesh(mesh.vertices, mesh.faces, path.name, unit=factor)
    if report.changed:
        print(f"hapticsim: repaired mesh {path.name}: {report.summary()}", file=sys.stderr)
    return MeshSolid(vertices * factor, faces, repair=report.to_dict())


def stl_bytes(solid: MeshSolid) -> bytes:
    """Binary STL of a mesh solid (its coordinates as they are: world frame, metres)."""
    buf = _io.BytesIO()
    solid.to_trimesh().export(buf, file_type="stl")
    return buf.getvalue()


def write_stl(path: str | Path, solid: MeshSolid) -> Path:
    """Write a mesh solid as binary STL through a temporary file and a rename.

    Raises:
        InvalidInputError: the path cannot be written (the message names it).
    """

    data = stl_bytes(solid)
    return atomic_write(path, lambda fh: fh.write(data), "wb")


def truth_file(solid: Solid) -> tuple[str, bytes]:
    """The file a run writes of its truth: a mesh as binary STL (``truth.stl``, its JSON would
    be large), any other solid as its JSON (``truth.json``: SPEC §6, a union SPEC §10)."""

    if isinstance(solid, MeshSolid):
        return "truth.stl", stl_bytes(solid)
    return "truth.json", (json.dumps(solid.to_dict(), indent=2) + "\n").encode()


def as_spec(value: ObjectSpec | str | Path) -> ObjectSpec:
    """An :class:`ObjectSpec` from itself, a name or a path."""
    if isinstance(value, ObjectSpec):
        return value
    if isinstance(value, (str, Path)):
        return ObjectSpec(str(value))
    raise InvalidInputError(
        f"an object must be an ObjectSpec, a name or a file path, got {type(value).__name__}"
    )


def resolve_object(
    value: ObjectSpec | str | Path | Solid,
    rng: np.random.Generator | int | None = None,
) -> Truth:
    """The ground truth of any object description: a solid as it is, or a spec, name or path
    resolved by :meth:`ObjectSpec.resolve`."""
    if isinstance(value, Solid):
        return value
    return as_spec(value).resolve(rng)


__all__ = [
    "MESH_SUFFIXES",
    "OBJECT_HELP",
    "OBJECT_KINDS",
    "RANDOM_KINDS",
    "ObjectSpec",
    "Pose",
    "Truth",
    "as_spec",
    "load_mesh",
    "random_composite",
    "random_holed",
    "random_handled",
    "random_superquadric",
    "resolve_object",
    "stl_bytes",
    "truth_file",
    "write_stl",
]
