"""Solids and their geometry: the :class:`Solid` interface every object is (SPEC §10), and its
kinds: the :class:`Superquadric` (the model, its functions, parametrisations, volumes, meshes
and sampling), the :class:`SuperquadricUnion`, the :class:`Supertoroid` (a superquadric with a
hole) and the :class:`MeshSolid` (a closed triangle mesh); ray casting, the EOF and its
compiled kernels.

The bottom layer of hapticsim: depends on numpy (scipy, trimesh, manifold3d and coacd are
imported lazily where a method needs them).
"""

from hapticsim.geometry.functions import (
    inside_outside,
    log_inside_outside,
    normals_body,
    radial_distance,
    signed_power,
    volume,
)
from hapticsim.geometry.mesh_solid import MeshSolid
from hapticsim.geometry.parametrization import natural, uniform
from hapticsim.geometry.rotations import (
    matrix_to_quaternion,
    matrix_to_rotvec,
    quaternion_to_matrix,
    random_rotation,
    rotvec_to_matrix,
)
from hapticsim.geometry.solid import Solid, solid_arg
from hapticsim.geometry.solid_io import solid_from_dict, solid_from_json
from hapticsim.geometry.superquadric import N_PARAMS, PARAM_NAMES, Superquadric
from hapticsim.geometry.supertoroid import Supertoroid
from hapticsim.geometry.union import SuperquadricUnion

__all__ = [
    "MeshSolid",
    "N_PARAMS",
    "PARAM_NAMES",
    "Solid",
    "Superquadric",
    "SuperquadricUnion",
    "Supertoroid",
    "inside_outside",
    "log_inside_outside",
    "matrix_to_quaternion",
    "matrix_to_rotvec",
    "natural",
    "normals_body",
    "quaternion_to_matrix",
    "radial_distance",
    "random_rotation",
    "rotvec_to_matrix",
    "signed_power",
    "solid_arg",
    "solid_from_dict",
    "solid_from_json",
    "uniform",
    "volume",
]
