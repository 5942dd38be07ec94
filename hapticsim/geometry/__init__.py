"""Superquadric geometry: the model, its functions, parametrisations, volumes and meshes, and
:class:`MeshSolid`, the solid of a closed triangle mesh (a mesh ground truth).

The bottom layer of hapticsim: depends on numpy only (trimesh is imported lazily for meshes).
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
from hapticsim.geometry.superquadric import N_PARAMS, PARAM_NAMES, Superquadric

__all__ = [
    "MeshSolid",
    "N_PARAMS",
    "PARAM_NAMES",
    "Superquadric",
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
    "uniform",
    "volume",
]
