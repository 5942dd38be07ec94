"""What a controller may know about the object before touching it: an honest vision estimate.

:func:`vision_estimate` does what a robot with a depth camera can do (SPEC §7): it takes one
noisy, partial point cloud of the object's visible side (:func:`depth_cloud`, a simulated depth
camera) and fits a primitive to it, knowing nothing else of the object:

1. **the cloud**: area-uniform samples of the true surface (superquadric or mesh) that face the
   camera are projected into the camera's pixels; per pixel the nearest one is kept (a z-buffer,
   so parts of a non-convex object hide each other), surfaces seen at more than 80 degrees from
   the viewing ray return nothing, and Gaussian noise of ``depth_noise`` [m] is added along each
   viewing ray (seeded);
2. **"has edges"**, from the cloud alone: local normals (principal axes of the 12 nearest
   neighbours) and RANSAC planes whose inliers lie within ``3 depth_noise + 0.5 mm`` of the plane
   with normals within 12 degrees of it. The object has edges (flat faces meeting at edges: a
   box, a cylinder's ends, a prism) when the largest plane holds at least
   :data:`EDGE_PLANE_FRACTION` of the cloud;
3. **the primitive**: with edges, an oriented bounding box (a superquadric box, exponents
   :data:`BOX_EPS`): for each of up to three detected planes, the box with one axis along the
   plane's normal and the other two from the minimum-area rectangle of the cloud projected on the
   plane (extents between the 0.5 and 99.5 percentiles), the one of least volume kept; without
   edges, an ellipsoid fitted to the cloud by least squares on the radial distance and on the
   outline in the image (which the camera sees whole and which pins the unseen far side),
   upright (turned about the vertical only: objects rest on a support) unless a tilted one
   fits much better (:data:`TILT_RMS_RATIO`). An ellipsoid centred outside the cloud's box
   (a head across a handle, which no ellipsoid fits: its fits sat 5-8 cm off and twice too
   large, and approaches aimed through their centre met nothing) gives way to the box of the
   cloud along its principal axes. Never the true exponents or taper.

Controllers plan approach points and palm poses on this estimate; every recorded contact still
comes from MuJoCo's contact data on the true object. The body axes of the estimate are ordered so
that its z axis is the one nearest the world's vertical (pointing up) and its x axis the one
nearest the world's x (pointing to +x).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import as_generator, finite_array, finite_float, positive_int
from hapticsim.errors import InvalidInputError, SimulationError
from hapticsim.geometry import Superquadric, rotvec_to_matrix
from hapticsim.geometry.mesh_solid import sample_triangles
from hapticsim.geometry.solid import Solid, solid_arg
from hapticsim.geometry.superquadric import superquadric_arg

Array = NDArray[np.float64]

#: Shape exponent below which a superquadric counts as having edges (box- or cylinder-like);
#: used to describe true shapes in tests and reports, never by the vision estimate.
EDGE_EPS: float = 0.5
#: Fraction of the cloud the largest plane must hold for the object to count as having edges.
#: Measured on the default camera (docs/objects.md): the paper's ellipsoid 0.07-0.08 and round
#: random superquadrics 0.08-0.11; box-like bodies, the cylinder and box-like random shapes
#: 0.15-0.47.
EDGE_PLANE_FRACTION: float = 0.15
#: A round object's ellipsoid may tilt away from upright only when that brings the RMS of its
#: radial distances below this fraction of the upright one's. Measured (default camera): a
#: tilted ellipsoid 0.41; tapered round superquadrics, which no ellipsoid fits, 0.78-0.95
#: (their free fits tilt 20-45 degrees and mislead the planner).
TILT_RMS_RATIO: float = 0.6
#: Exponents (eps1, eps2) of the box the estimate gives for an object with edges.
BOX_EPS: tuple[float, float] = (0.1, 0.1)
#: Neighbours of a point's local normal.
_NORMAL_NEIGHBOURS: int = 12
#: Largest angle [rad] between a point's local normal and a plane for it to be an inlier.
_PLANE_ANGLE: float = np.radians(12.0)
#: RANSAC seeds per plane.
_RANSAC_SEEDS: int = 150
#: Surface samples per pixel the visible surface covers (z-buffer fill).
_SAMPLES_PER_PIXEL: float = 6.0
#: Mesh resolution (longitudes) on which a superquadric's surface is sampled for the camera.
_CAMERA_MESH_RESOLUTION: int = 96
#: Points of the cloud on which local normals and planes are computed (a seeded subsample).
_PLANE_POINTS: int = 1000
#: Points of the plane subsample used by the ellipsoid fit.
_ELLIPSOID_POINTS: int = 600


@dataclass(frozen=True)
class DepthCamera:
    """A simulated depth camera aimed at the object (as a pan-tilt head would aim it).

    Attributes:
        azimuth: direction from the object to the camera about the world's vertical [rad]
            (0: from +x; the default -60 degrees looks from the front right).
        elevation: angle of that direction above the horizontal [rad].
        distance: camera distance from the object's centre [m].
        fovy: vertical field of view [rad].
        width, height: image size [px].
        depth_noise: standard deviation of the depth along each viewing ray [m].
        max_incidence: surfaces seen at a larger angle [rad] from the viewing ray return no depth.
    """

    azimuth: float = np.radians(-60.0)
    elevation: float = np.radians(40.0)
    distance: float = 0.4
    fovy: float = np.radians(45.0)
    width: int = 320
    height: int = 240
    depth_noise: float = 0.001
    max_incidence: float = np.radians(80.0)

    def __post_init__(self) -> None:
        finite_float(self.azimuth, "azimuth")
        finite_float(self.elevation, "elevation", -np.pi / 2, np.pi / 2)
        if finite_float(self.distance, "distance") <= 0:
            raise InvalidInputError(f"`distance` must be > 0 [m], got {self.distance!r}")
        finite_float(self.fovy, "fovy", 1e-3, np.pi - 1e-3)
        positive_int(self.width, "width", minimum=8)
        positive_int(self.height, "height", minimum=8)
        finite_float(self.depth_noise, "depth_noise", 0.0, 0.05)
        finite_float(self.max_incidence, "max_incidence", 0.0, np.pi / 2)

    def eye(self, target_world: Array) -> Array:
        """(3,) float, camera position [m, world] when aimed at `target_world`."""
        ce, se = np.cos(self.elevation), np.sin(self.elevation)
        direction = np.array([ce * np.cos(self.azimuth), ce * np.sin(self.azimuth), se])
        return np.asarray(target_world, float) + self.distance * direction

    @property
    def pixel_angle(self) -> float:
        """Angle subtended by one pixel [rad]."""
        return self.fovy / self.height

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready settings (angles in degrees, lengths in metres)."""
        return {
            "azimuth_deg": float(np.degrees(self.azimuth)),
            "elevation_deg": float(np.degrees(self.elevation)),
            "distance": self.distance,
            "fovy_deg": float(np.degrees(self.fovy)),
            "width": self.width,
            "height": self.height,
            "depth_noise": self.depth_noise,
            "max_incidence_deg": float(np.degrees(self.max_incidence)),
        }


@dataclass(frozen=True)
class RoughObject:
    """A rough superquadric of the object: what the planner is given.

    Attributes:
        shape: the rough superquadric, world frame.
        has_edges: True when the object looks prismatic (flat faces meeting at edges); such
            bodies get corner patches and edge-crossing stripes.
        vision: how the estimate was made (camera, cloud size, plane fraction, method), or None
            for an estimate given by hand; JSON-ready.
        cloud: (n, 3) float, the point cloud it was fitted to [m, world], or None.
    """

    shape: Superquadric
    has_edges: bool
    vision: dict[str, Any] | None = None
    cloud: Array | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        superquadric_arg(self.shape, "shape")
        object.__setattr__(self, "has_edges", bool(self.has_edges))

    @property
    def center(self) -> Array:
        """(3,) float, rough centre [m, world]."""
        return self.shape.center

    @property
    def radius(self) -> float:
        """Bounding radius of the rough shape [m]."""
        return self.shape.bounding_radius

    def surface(self, eta: Array, omega: Array) -> tuple[Array, Array]:
        """Rough surface points (n, 3) [m, world] and outward unit normals (n, 3) at (eta, omega)
        of the uniform parametrisation (paper eq. 6)."""
        return self.shape.surface(np.atleast_1d(eta), np.atleast_1d(omega))

    def moved(self, center_world: Array) -> RoughObject:
        """The same estimate with its centre at `center_world` (3,) [m]."""
        c = finite_array(center_world, "center_world", (3,))
        cloud = None if self.cloud is None else self.cloud + (c - self.center)
        return RoughObject(self.shape.replace(center=c), self.has_edges, self.vision, cloud)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the rough ``shape`` (superquadric), ``has_edges`` and ``vision``."""
        return {"shape": self.shape.to_dict(), "has_edges": self.has_edges, "vision": self.vision}


# ----------------------------------------------------------------------------- the camera
@lru_cache(maxsize=16)
def _surface_triangles(truth: Solid) -> tuple[Array, Array, Array]:
    """Triangles (m, 3, 3) [m], their areas (m,) [m^2] and outward unit normals (m, 3) of the
    solid's surface mesh (:meth:`~hapticsim.geometry.solid.Solid.surface_mesh`: a mesh's own, a
    superquadric's at :data:`_CAMERA_MESH_RESOLUTION` longitudes, whose chords, a few 1e-5 m,
    are far below a camera's depth noise), kept for the solids seen last (episodes come back to
    the same bodies)."""
    vertices, faces = truth.surface_mesh(_CAMERA_MESH_RESOLUTION)
    tri = np.asarray(vertices)[np.asarray(faces)]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    doubled = np.linalg.norm(cross, axis=1)
    ok = doubled > 0
    out = (tri[ok], 0.5 * doubled[ok], cross[ok] / doubled[ok, None])
    for arr in out:
        arr.setflags(write=False)
    return out


def depth_cloud(
    truth: Solid,
    rng: np.random.Generator | int | None = None,
    camera: DepthCamera | None = None,
) -> tuple[Array, Array]:
    """The point cloud a depth camera gives of the object's visible side (module docstring).

    Args:
        truth: the object (any solid), world frame.
        rng: seed or generator (surface samples, then the depth noise).
        camera: the camera (default :class:`DepthCamera`), aimed at ``truth.center``.

    Returns:
        points (n, 3) [m, world] with depth noise, and the camera position (3,) [m, world].

    Raises:
        SimulationError: the camera sees fewer than 50 points of the object.
    """
    truth = solid_arg(truth, "truth")
    cam = DepthCamera() if camera is None else camera
    gen = as_generator(rng)
    target = np.asarray(truth.center, float)
    eye = cam.eye(target)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    if np.linalg.norm(right) < 1e-9:  # looking straight down or up
        right = np.array([1.0, 0.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    focal = 0.5 * cam.height / np.tan(0.5 * cam.fovy)  # [px]
    tri, area, normal = _surface_triangles(truth)
    # the faces the camera sees (front-facing, not too oblique) and the pixels they cover
    view = eye - tri.mean(axis=1)
    dist = np.linalg.norm(view, axis=1)
    cos_incidence = np.einsum("ij,ij->i", normal, view) / dist
    seen = cos_incidence > np.cos(cam.max_incidence)
    if not np.any(seen):
        raise SimulationError("the depth camera sees no surface of the object")
    tri, area, normal = tri[seen], area[seen], normal[seen]
    pixels = float(np.sum(area * cos_incidence[seen] * (focal / dist[seen]) ** 2))
    count = int(np.clip(_SAMPLES_PER_PIXEL * pixels, 5_000, 400_000))
    points, face = sample_triangles(tri, area, count, gen)
    view = eye - points
    dist = np.linalg.norm(view, axis=1)
    keep = np.einsum("ij,ij->i", normal[face], view) > np.cos(cam.max_incidence) * dist
    points, dist = points[keep], dist[keep]
    rel = points - eye
    depth = rel @ forward
    u = np.floor(0.5 * cam.width + focal * (rel @ right) / depth).astype(np.int64)
    v = np.floor(0.5 * cam.height - focal * (rel @ up) / depth).astype(np.int64)
    inside = (depth > 0) & (u >= 0) & (u < cam.width) & (v >= 0) & (v < cam.height)
    points, dist, u, v = points[inside], dist[inside], u[inside], v[inside]
    pix = v * cam.width + u
    order = np.lexsort((dist, pix))  # by pixel, nearest first
    first = np.ones(len(order), dtype=bool)
    first[1:] = pix[order][1:] != pix[order][:-1]
    nearest = order[first]
    cloud = points[nearest]
    if len(cloud) < 50:
        raise SimulationError(
            f"the depth camera sees only {len(cloud)} points of the object (at least 50 needed): "
            "it is too small or out of view"
        )
    rays = (cloud - eye) / np.linalg.norm(cloud - eye, axis=1, keepdims=True)
    if cam.depth_noise > 0:
        cloud = cloud + rays * gen.normal(0.0, cam.depth_noise, size=(len(cloud), 1))
    return cloud, eye


# ----------------------------------------------------------------------------- the fit
def _local_normals(cloud: Array, points: Array, eye: Array) -> Array:
    """(k, 3) unit normals (towards the camera) at `points` (k, 3) of a `cloud` (n, 3) [m]: the
    least principal axis of each point's nearest neighbours in the cloud."""
    from scipy.spatial import cKDTree

    k = min(_NORMAL_NEIGHBOURS, len(cloud))
    _, idx = cKDTree(cloud).query(points, k=k)
    nb = cloud[idx] - cloud[idx].mean(axis=1, keepdims=True)
    _, vecs = np.linalg.eigh(np.einsum("nki,nkj->nij", nb, nb))
    normals = vecs[:, :, 0]
    flip = np.einsum("ij,ij->i", normals, eye - points) < 0
    normals[flip] *= -1.0
    return normals


def _planes(
    cloud: Array, normals: Array, tolerance: float, gen: np.random.Generator, count: int = 3
) -> list[tuple[Array, NDArray[np.bool_]]]:
    """Up to `count` planes found by RANSAC on points and local normals, largest first.

    Returns:
        (unit normal (3,), inlier mask (n,)) per plane.
    """
    cos_max = np.cos(_PLANE_ANGLE)
    free = np.ones(len(cloud), dtype=bool)
    found: list[tuple[Array, NDArray[np.bool_]]] = []
    for _ in range(count):
        candidates = np.flatnonzero(free)
        if len(candidates) < 10:
            break
        seeds = gen.choice(candidates, size=min(_RANSAC_SEEDS, len(candidates)), replace=False)
        n_seed = normals[seeds]  # (s, 3): one plane through each seed, along its normal
        offset = np.einsum("ij,ij->i", n_seed, cloud[seeds])
        masks = (np.abs(cloud @ n_seed.T - offset) < tolerance) & (normals @ n_seed.T > cos_max)
        masks &= free[:, None]
        k = int(np.argmax(masks.sum(axis=0)))
        best, best_normal = masks[:, k], n_seed[k]
        if best.sum() < 10:
            break
        # refine: the inliers' best-fit plane, and its inliers
        pts = cloud[best]
        centre = pts.mean(axis=0)
        _, vecs = np.linalg.eigh((pts - centre).T @ (pts - centre))
        n = vecs[:, 0] * np.sign(vecs[:, 0] @ best_normal)
        mask = free & (np.abs((cloud - centre) @ n) < tolerance) & (normals @ n > cos_max)
        found.append((n, mask))
        free &= ~mask
    return found


def _min_area_rectangle(xy: Array) -> Array:
    """(2, 2) float, columns the axes of the minimum-area rectangle around 2-d points."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = xy[ConvexHull(xy).vertices]
    except QhullError:
        return np.eye(2)
    edges = np.roll(hull, -1, axis=0) - hull
    angles = np.unique(np.mod(np.arctan2(edges[:, 1], edges[:, 0]), np.pi / 2))
    c, s = np.cos(angles), np.sin(angles)
    u = np.stack([c, s], axis=1)
    w = np.stack([-s, c], axis=1)
    pu, pw = hull @ u.T, hull @ w.T
    area = np.ptp(pu, axis=0) * np.ptp(pw, axis=0)
    k = int(np.argmin(area))
    return np.stack([u[k], w[k]], axis=1)


def _canonical(rotation: Array, half: Array) -> tuple[Array, Array]:
    """Reorder and flip box axes: z nearest the world's up, x nearest the world's +x."""
    r = np.array(rotation, float)
    z = int(np.argmax(np.abs(r[2])))
    rest = [k for k in range(3) if k != z]
    x = rest[int(np.argmax(np.abs(r[0, rest])))]
    y = 3 - x - z
    ez = r[:, z] * np.sign(r[2, z] or 1.0)
    ex = r[:, x] * np.sign(r[0, x] or 1.0)
    ey = np.cross(ez, ex)
    return np.stack([ex, ey, ez], axis=1), np.asarray(half)[[x, y, z]]


def _box_along(cloud: Array, normal: Array) -> tuple[Array, Array, Array]:
    """The box around a cloud with one axis along `normal`: rotation, centre, half extents."""
    n = normal / np.linalg.norm(normal)
    helper = np.eye(3)[int(np.argmin(np.abs(n)))]
    e1 = np.cross(n, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    flat = np.stack([cloud @ e1, cloud @ e2], axis=1)
    axes2 = _min_area_rectangle(flat)
    u = axes2[0, 0] * e1 + axes2[1, 0] * e2
    w = np.cross(n, u)
    return _box_in(cloud, np.stack([u, w, n], axis=1))


def _box_in(cloud: Array, rot: Array) -> tuple[Array, Array, Array]:
    """The box around a cloud with the axes `rot` (columns): rotation, centre, half extents
    (between the 0.5 and 99.5 percentiles)."""
    local = cloud @ rot
    lo, hi = np.percentile(local, 0.5, axis=0), np.percentile(local, 99.5, axis=0)
    return rot, rot @ (0.5 * (lo + hi)), np.maximum(0.5 * (hi - lo), 1e-3)


def _principal_box(cloud: Array) -> tuple[Array, Array, Array]:
    """The box around a cloud along its principal axes (:func:`_box_in`)."""
    d = cloud - cloud.mean(axis=0)
    _, vecs = np.linalg.eigh(d.T @ d)
    if np.linalg.det(vecs) < 0:
        vecs[:, 0] *= -1.0
    return _box_in(cloud, vecs)


def _camera_axes(cloud: Array, eye: Array) -> Array:
    """(3, 3) float, columns right, up, forward of a camera at `eye` looking at the cloud."""
    forward = cloud.mean(axis=0) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    if np.linalg.norm(right) < 1e-9:
        right = np.array([1.0, 0.0, 0.0])
    right /= np.linalg.norm(right)
    return np.stack([right, np.cross(right, forward), forward], axis=1)


def _ellipsoid(
    cloud: Array, eye: Array, noise: float, pixel: float, upright: bool = False
) -> tuple[Array, Array, Array, float]:
    """Ellipsoid of a round object's visible side: rotation, centre, semi-axes and the RMS of
    the radial distances [m].

    Least squares on the radial distance of the points (scaled by the depth noise) and on the
    outline: the ellipsoid's extent across the image (along the camera's right and up axes,
    ``c.d +- sqrt(d^T R diag(a^2) R^T d)``) must match the cloud's (scaled by the pixel size).
    The visible side alone leaves the far side free (a larger ellipsoid further back fits a
    cap as well); the outline, which the camera sees whole, pins it. ``upright`` turns the
    ellipsoid about the vertical only.
    """
    from scipy.optimize import least_squares

    axes = _camera_axes(cloud, eye)
    image = (cloud @ axes)[:, :2]
    lo, hi = np.percentile(image, 0.5, axis=0), np.percentile(image, 99.5, axis=0)
    d = cloud - cloud.mean(axis=0)
    if upright:  # principal axes of the horizontal spread, z up
        _, v2 = np.linalg.eigh(d[:, :2].T @ d[:, :2])
        vecs = np.eye(3)
        vecs[:2, :2] = v2 if np.linalg.det(v2) > 0 else v2[:, ::-1]
    else:
        _, vecs = np.linalg.eigh(d.T @ d)
        if np.linalg.det(vecs) < 0:
            vecs[:, 0] *= -1.0
    extent = np.maximum(0.5 * np.ptp(d @ vecs, axis=0), 2e-3)
    sigma = max(noise, 5e-4)
    limit = 2.0 * float(np.max(hi - lo)) + 2e-3
    base = vecs
    view = axes[:, :2]  # (3, 2): right and up
    free = slice(2, 3) if upright else slice(0, 3)  # rotation-vector components fitted
    n_rot = free.stop - free.start

    def unpack(x: Array) -> tuple[Array, Array, Array]:
        """Semi-axes (P, 3), rotations (P, 3, 3) and centres (P, 3) of parameter rows (P, k)."""
        rotvec = np.zeros((len(x), 3))
        rotvec[:, free] = x[:, 3 : 3 + n_rot]
        return x[:, :3], base @ rotvec_to_matrix(rotvec), x[:, -3:]

    def radial(x: Array) -> Array:
        a, rot, c = unpack(x)
        p = np.einsum("pni,pij->pnj", cloud[None, :, :] - c[:, None, :], rot)  # (P, n, 3)
        f = np.sqrt(np.sum((p / a[:, None, :]) ** 2, axis=2))
        return np.linalg.norm(p, axis=2) * (1.0 - 1.0 / np.maximum(f, 1e-12))

    def residuals_many(x: Array) -> Array:
        a, rot, c = unpack(x)
        # reach of the ellipsoid along the camera's right and up axes: sqrt(d^T R A^2 R^T d)
        local = np.einsum("pji,jk->pik", rot, view)  # R^T view, (P, 3, 2)
        reach = np.sqrt(np.sum(local**2 * (a**2)[:, :, None], axis=1))  # (P, 2)
        mid = c @ view
        outline = np.concatenate([mid + reach - hi, mid - reach - lo], axis=1) / pixel
        return np.concatenate([radial(x) / sigma, outline], axis=1)

    def residuals(x: Array) -> Array:
        return residuals_many(x[None, :])[0]

    def jacobian(x: Array) -> Array:
        # Forward differences, all perturbed rows in one batched call.
        step = 1e-7 * np.maximum(np.abs(x), 1e-2)
        step = np.where(x + step > bounds_hi, -step, step)
        rows = np.vstack([x, x + np.diag(step)])
        r = residuals_many(rows)
        return ((r[1:] - r[0]) / step[:, None]).T

    centre0 = cloud.mean(axis=0) + axes[:, 2] * float(np.mean(extent))  # one extent deeper
    x0 = np.concatenate([np.minimum(extent, limit - 1e-3), np.zeros(n_rot), centre0])
    bounds_lo = np.concatenate([np.full(3, 1e-3), np.full(n_rot, -np.pi), np.full(3, -np.inf)])
    bounds_hi = np.concatenate([np.full(3, limit), np.full(n_rot, np.pi), np.full(3, np.inf)])
    sol = least_squares(residuals, np.clip(x0, bounds_lo + 1e-9, bounds_hi - 1e-9), jac=jacobian,
                        bounds=(bounds_lo, bounds_hi), x_scale="jac", max_nfev=200)  # fmt: skip
    a, rot, c = (v[0] for v in unpack(sol.x[None, :]))
    return rot, c, a, float(np.sqrt(np.mean(radial(sol.x[None, :])[0] ** 2)))


def vision_estimate(
    truth: Solid,
    rng: np.random.Generator | int | None = None,
    camera: DepthCamera | None = None,
) -> RoughObject:
    """A rough estimate of the object from one noisy depth image (module docstring).

    Args:
        truth: the object, world frame (only its visible surface is used).
        rng: seed or generator (the cloud's samples and noise, then RANSAC).
        camera: the depth camera (default :class:`DepthCamera`).

    Returns:
        The rough object: an oriented box (exponents :data:`BOX_EPS`) when the cloud shows flat
        faces, else an ellipsoid; never the true exponents or taper. ``vision`` records the
        camera, the cloud size, the largest plane's fraction and the method.

    Raises:
        SimulationError: the camera sees too little of the object.
    """
    cam = DepthCamera() if camera is None else camera
    if not isinstance(cam, DepthCamera):
        raise InvalidInputError(f"`camera` must be a DepthCamera, got {type(cam).__name__}")
    gen = as_generator(rng)
    cloud, eye = depth_cloud(truth, gen, cam)
    sample = cloud
    if len(cloud) > _PLANE_POINTS:
        sample = cloud[gen.choice(len(cloud), _PLANE_POINTS, replace=False)]
    normals = _local_normals(cloud, sample, eye)
    tolerance = 3.0 * cam.depth_noise + 5e-4
    planes = _planes(sample, normals, tolerance, gen)
    fraction = float(planes[0][1].mean()) if planes else 0.0
    has_edges = fraction >= EDGE_PLANE_FRACTION
    if has_edges:
        boxes = [_box_along(cloud, n) for n, mask in planes if mask.mean() >= 0.05]
        rot, centre, half = min(boxes, key=lambda b: float(np.prod(b[2])))
        eps, method = BOX_EPS, "oriented bounding box on the largest planes (least volume)"
    else:
        pixel = cam.distance * cam.pixel_angle
        sub = sample[:_ELLIPSOID_POINTS]
        upright = _ellipsoid(sub, eye, cam.depth_noise, pixel, upright=True)
        tilted = _ellipsoid(sub, eye, cam.depth_noise, pixel)
        keep_tilt = tilted[3] < TILT_RMS_RATIO * upright[3]
        rot, centre, half, rms = tilted if keep_tilt else upright
        eps = (1.0, 1.0)
        method = (
            f"least-squares ellipsoid (radial distance and outline), "
            f"{'tilted' if keep_tilt else 'upright'}; RMS {rms * 1e3:.2f} mm (upright "
            f"{upright[3] * 1e3:.2f} mm, tilted {tilted[3] * 1e3:.2f} mm)"
        )
        lo, hi = np.percentile(cloud, 0.5, axis=0), np.percentile(cloud, 99.5, axis=0)
        if np.any((centre < lo) | (centre > hi)):
            # no ellipsoid fits (a hammer, a mallet: a head across a handle); one centred
            # outside what the camera saw misleads every approach aimed through its centre
            rot, centre, half = _principal_box(cloud)
            eps = BOX_EPS
            method = (
                "box on the cloud's principal axes (the least-squares ellipsoid was centred "
                f"outside the cloud's box; its RMS {rms * 1e3:.2f} mm)"
            )
    rot, half = _canonical(rot, half)
    shape = Superquadric(a=half, eps=eps, rotation=rot, center=centre)
    vision = {
        "method": method,
        "camera": cam.to_dict() | {"position": eye.tolist()},
        "points": int(len(cloud)),
        "largest_plane_fraction": fraction,
        "edge_rule": f"largest plane holds >= {EDGE_PLANE_FRACTION} of the cloud",
        "plane_tolerance": tolerance,
    }
    return RoughObject(shape=shape, has_edges=has_edges, vision=vision, cloud=cloud)


__all__ = [
    "BOX_EPS",
    "TILT_RMS_RATIO",
    "DepthCamera",
    "EDGE_EPS",
    "EDGE_PLANE_FRACTION",
    "RoughObject",
    "depth_cloud",
    "vision_estimate",
]
