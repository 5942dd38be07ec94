"""Example mesh objects built with trimesh: three convex solids and a non-convex L-block.

Hand-held sizes (a few centimetres), centroid at the origin, as :class:`MeshSolid` values; write
them with :func:`hapticsim.data.objects.write_stl` to explore them as files
(``hapticsim explore --object part.stl``). ``docs/objects.md`` measures the exploration of each.

=====================  ======================================================  ========
name                   shape                                                   convex
=====================  ======================================================  ========
``hexagonal_prism``    regular hexagon, circumradius 3 cm, 6 cm tall           yes
``rounded_box``        6 x 4.5 x 4 cm box, edges rounded with radius 8 mm      yes
``truncated_pyramid``  7 x 6 cm base, 3.5 x 3 cm top, 5 cm tall                yes
``l_block``            L of two 6 x 2 cm bars (2 cm overlap), 5 cm tall        no
=====================  ======================================================  ========
"""

from __future__ import annotations

from collections.abc import Callable
from types import MappingProxyType

import numpy as np

from hapticsim.errors import InvalidInputError
from hapticsim.geometry.mesh_solid import MeshSolid


def _solid(mesh: object) -> MeshSolid:
    import trimesh

    assert isinstance(mesh, trimesh.Trimesh)
    solid = MeshSolid(np.asarray(mesh.vertices, float), np.asarray(mesh.faces))
    return solid.transformed(np.eye(3), -solid.centroid)


def hexagonal_prism(circumradius: float = 0.03, height: float = 0.06) -> MeshSolid:
    """A regular hexagonal prism, axis along z [m]."""
    import trimesh

    return _solid(trimesh.creation.cylinder(radius=circumradius, height=height, sections=6))


def rounded_box(
    extents: tuple[float, float, float] = (0.06, 0.045, 0.04), radius: float = 0.008
) -> MeshSolid:
    """A box with rounded edges and corners: the convex hull of eight spheres of `radius` [m]
    set in from the corners of a box of `extents` [m]."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=3, radius=radius)
    inner = 0.5 * np.asarray(extents, float) - radius
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    points = np.concatenate([sphere.vertices + c * inner for c in corners])
    return _solid(trimesh.convex.convex_hull(points))


def truncated_pyramid(
    base: tuple[float, float] = (0.07, 0.06),
    top: tuple[float, float] = (0.035, 0.03),
    height: float = 0.05,
) -> MeshSolid:
    """A frustum of a rectangular pyramid: `base` and `top` rectangles [m], `height` [m]."""
    import trimesh

    bx, by = 0.5 * np.asarray(base, float)
    tx, ty = 0.5 * np.asarray(top, float)
    h = 0.5 * height
    points = [[sx * bx, sy * by, -h] for sx in (-1, 1) for sy in (-1, 1)]
    points += [[sx * tx, sy * ty, h] for sx in (-1, 1) for sy in (-1, 1)]
    return _solid(trimesh.convex.convex_hull(np.array(points)))


def l_block(length: float = 0.06, width: float = 0.02, height: float = 0.05) -> MeshSolid:
    """An L-shaped block: two bars of ``length x width`` [m] meeting at a square corner,
    `height` [m] tall (non-convex; exact union by manifold3d)."""
    import trimesh

    bar_x = trimesh.creation.box((length, width, height))
    bar_y = trimesh.creation.box(
        (width, length, height),
        transform=trimesh.transformations.translation_matrix(
            (-(length - width) / 2.0, (length - width) / 2.0, 0.0)
        ),
    )
    return _solid(trimesh.boolean.union([bar_x, bar_y], engine="manifold"))


#: Builders by name (default sizes).
EXAMPLE_MESHES: MappingProxyType[str, Callable[[], MeshSolid]] = MappingProxyType(
    {
        "hexagonal_prism": hexagonal_prism,
        "rounded_box": rounded_box,
        "truncated_pyramid": truncated_pyramid,
        "l_block": l_block,
    }
)


def example_mesh(name: str) -> MeshSolid:
    """An example mesh by name (one of :data:`EXAMPLE_MESHES`)."""
    if name not in EXAMPLE_MESHES:
        raise InvalidInputError(
            f"unknown example mesh {name!r}: the examples are {', '.join(EXAMPLE_MESHES)}"
        )
    return EXAMPLE_MESHES[name]()


__all__ = [
    "EXAMPLE_MESHES",
    "example_mesh",
    "hexagonal_prism",
    "l_block",
    "rounded_box",
    "truncated_pyramid",
]
