"""Reference contact mechanics for the skin (issue 38, item 3; SPEC §11): what an elastic layer
really does under a press, to hold the skin's law against.

Three references for a sphere of radius R pressed by an indentation delta:

- :func:`hertz_sphere`: Hertz's half-space solution (the layer far thicker than the contact):
  ``a = sqrt(R delta)``, ``F = 4/3 E* sqrt(R) delta^(3/2)``, ``p(r) = p0 sqrt(1 - r^2/a^2)``
  with ``p0 = 2 E* a / (pi R)`` and ``E* = E / (1 - nu^2)`` (one elastic body, the other rigid);
- :func:`winkler_sphere`: the skin's own law (:class:`~hapticsim.perception.tactile.skin.
  SkinModel`, a Winkler foundation ``p = E d / h``): ``a = sqrt(2 R delta)``,
  ``F = pi E R delta^2 / h``, ``p0 = E delta / h``; exact for a thin layer (contact radius
  several thicknesses) of a material without lateral coupling (Poisson's ratio 0);
For a long cylinder (a line contact, per metre of length): :func:`hertz_cylinder` (half-width
``b = sqrt(4 R F' / (pi E*))``, ``p0 = 2 F' / (pi b)``), :func:`winkler_cylinder`
(``F' = 4/3 (E / h) delta a``) and :func:`fem_layer_line_press` (the flat layer's FE in plane
strain).

- :func:`fem_layer_press` and :func:`fem_pad_press`: a finite-element solution of linear
  elasticity (axisymmetric, quadratic triangles, scikit-fem) with frictionless contact found by
  an active set, for any thickness and Poisson's ratio: a flat layer bonded to a rigid base
  under a rigid sphere, and a fingertip pad (a layer bonded on a rigid spherical core) pressed
  onto a rigid flat; and :func:`fem_punch_press`, a flat-ended punch into the flat layer, with
  Boussinesq's half-space solution :func:`punch_half_space` (``F = 2 E* a delta``) as its
  limit. Both limits hold (tests/perception/test_mechanics.py): a thick layer gives
  Hertz's force, contact radius and peak pressure within 2-3 %, a thin layer of Poisson's ratio
  0 the Winkler force and peak pressure within 1 %.

A law with the layer's lateral coupling (:func:`layer_pressure`): the surface displacement is
the convolution of the pressure with the layer's influence function (:func:`layer_kernel`, the
FE surface displacement of a bonded layer under a small uniform disc load, computed once per
layer and grid spacing), and the pressure is the contact solution of a depth image on a regular
grid (Polonsky and Keer's constrained conjugate gradient, FFT convolutions; displacement
given; a cell's own response is the sinking at its centre, the collocation point). A sphere
pressed 0.1-1 mm into a 2 mm layer on a 0.1 mm grid: force, contact radius and peak pressure
within 1.7 % of :func:`fem_layer_press` for Poisson's ratios 0-0.49; held out (spheres of 4 and
15 mm in 1 and 3 mm layers, flat punches), within 2.8 %; on a pad's 0.5 mm grid, force within
2.5 % (docs/tactile/mechanics/README.md). A skin with a Poisson's ratio reads this law
(:class:`~hapticsim.perception.tactile.skin.SkinModel`).

The FE solutions need the ``fem`` extra (``pip install -e ".[fem]"``: scikit-fem). What they
say of the skin's law is in docs/tactile/mechanics/README.md (``scripts/skin_mechanics.py``).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_float
from hapticsim.errors import InvalidInputError

Array = NDArray[np.float64]

#: Active-set passes of the contact solution (it settles in 3-8).
MAX_PASSES: int = 40

#: A published sensor's force-indentation curve, indentation [m] -> normal force [N]: a rigid
#: sphere of :data:`GELSIGHT_MINI_SPHERE_RADIUS` pressed into the gel of a GelSight Mini (the
#: ground truth of the gel's material identification in Helmut, Dziarski, Funk, Belousov and
#: Peters, arXiv 2411.03315, github.com/feats-ai/feats; their gel is 4 mm thick). The
#: ``gelsight_mini`` skin preset is calibrated against it (scripts/skin_calibration.py).
GELSIGHT_MINI_PRESSES: dict[float, float] = {
    0.5e-3: 1.6503, 1.0e-3: 5.9641, 1.5e-3: 13.5257, 2.0e-3: 23.2532,
}  # fmt: skip
#: The radius [m] of that sphere (15 mm across).
GELSIGHT_MINI_SPHERE_RADIUS: float = 7.5e-3


@dataclass(frozen=True)
class ContactSolution:
    """A sphere's press: force [N], contact radius [m], peak (centre) pressure [Pa] and, for
    the FE solutions, the surface pressure ``pressure`` [Pa] at radii ``radii`` [m]."""

    force: float
    contact_radius: float
    peak_pressure: float
    radii: Array | None = None
    pressure: Array | None = None


def _check(modulus: float, poisson: float, radius: float, indentation: float) -> None:
    finite_float(modulus, "modulus", low=1.0, high=1e12)
    finite_float(poisson, "poisson", low=0.0, high=0.4999)
    finite_float(radius, "radius", low=1e-5, high=1.0)
    finite_float(indentation, "indentation", low=1e-9, high=0.5 * radius)


def hertz_sphere(modulus: float, poisson: float, radius: float,
                 indentation: float) -> ContactSolution:  # fmt: skip
    """Hertz's solution (module docstring): a rigid sphere into an elastic half-space, or an
    elastic sphere onto a rigid flat."""
    _check(modulus, poisson, radius, indentation)
    e_star = modulus / (1.0 - poisson**2)
    a = math.sqrt(radius * indentation)
    return ContactSolution(
        force=4.0 / 3.0 * e_star * math.sqrt(radius) * indentation**1.5,
        contact_radius=a, peak_pressure=2.0 * e_star * a / (math.pi * radius),
    )  # fmt: skip


def winkler_sphere(skin: Any, radius: float, indentation: float) -> ContactSolution:
    """The skin's law for a sphere of `radius` pressed `indentation` into it (`skin`: a
    :class:`~hapticsim.perception.tactile.skin.SkinModel`)."""
    _check(skin.modulus, 0.0, radius, indentation)
    return ContactSolution(
        force=skin.sphere_force(radius, indentation),
        contact_radius=math.sqrt(2.0 * radius * indentation),
        peak_pressure=float(skin.pressure(indentation)),
    )  # fmt: skip


def _graded(stop: float, fine_to: float, step: float, growth: float = 1.2) -> Array:
    """Nodes from 0 to `stop`: `step` apart up to `fine_to`, then each `growth` times the last."""
    nodes = list(np.arange(0.0, min(fine_to, stop), step)) + [min(fine_to, stop)]
    while nodes[-1] < stop:
        step *= growth
        nodes.append(min(stop, nodes[-1] + step))
    return np.array(nodes)


def _fem() -> Any:
    try:
        import skfem
    except ImportError as exc:
        raise InvalidInputError(
            'the FE contact solutions need scikit-fem: pip install -e ".[fem]"'
        ) from exc
    return skfem


def _lame(modulus: float, poisson: float) -> tuple[float, float]:
    return (modulus * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)),
            modulus / (2.0 * (1.0 + poisson)))  # fmt: skip


def _stiffness(skfem: Any, basis: Any, modulus: float, poisson: float,
               plane: bool = False) -> Any:  # fmt: skip
    """The stiffness matrix of axisymmetric linear elasticity on `basis` (x = r, y = z), or of
    plane strain (x across, y = z; per metre of length) when `plane`."""
    from skfem.helpers import grad

    lam, mu = _lame(modulus, poisson)

    def strains(u: Any, r: Array) -> tuple[Any, ...]:
        g = grad(u)  # g[i][j] = d u_i / d x_j
        hoop = 0.0 * g[0][0] if plane else u[0] / r
        return g[0][0], g[1][1], hoop, 0.5 * (g[0][1] + g[1][0])

    @skfem.BilinearForm
    def stiffness(u: Any, v: Any, w: Any) -> Any:
        r = w.x[0]
        eu, ev = strains(u, r), strains(v, r)
        tu, tv = eu[0] + eu[1] + eu[2], ev[0] + ev[1] + ev[2]
        shear = eu[0] * ev[0] + eu[1] * ev[1] + eu[2] * ev[2] + 2.0 * eu[3] * ev[3]
        weight = 1.0 if plane else r  # per metre of length, or per radian of the revolution
        return (lam * tu * tv + 2.0 * mu * shear) * weight

    return skfem.asm(stiffness, basis)


def _solve(
    mesh: Any, modulus: float, poisson: float, fixed: Callable[[Array], Array],
    surface: Callable[[Array], Array], gap: Callable[[Array, Array], Array], sign: float,
    probe: Callable[[Array], Array], probe_radii: Array, plane: bool = False,
) -> ContactSolution:  # fmt: skip
    """Axisymmetric linear elasticity on `mesh` (x = r, y = z) with frictionless contact, or
    plane strain when `plane` (x across, the symmetry plane at x = 0; the force per metre of
    length, both halves).

    `fixed` (facet midpoints -> bool) is bonded (no displacement); the axis has no radial
    displacement; on the `surface` facets the vertical displacement of a node at (r, z) must not
    pass ``gap(r, z)`` (``sign`` +1: at least it, the obstacle below pushing up; -1: at most it,
    the obstacle above pushing down); the surface pressure is probed at ``probe(radii)``.
    """
    skfem = _fem()
    from skfem.helpers import grad

    lam, mu = _lame(modulus, poisson)
    basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTriP2()))
    k = _stiffness(skfem, basis, modulus, poisson, plane)
    bonded = basis.get_dofs(fixed).all()
    axis = basis.get_dofs(lambda x: x[0] < 1e-12).all("u^1")
    top = basis.get_dofs(surface).all("u^2")
    r_s, z_s = basis.doflocs[:, top]
    target = gap(r_s, z_s)
    active = sign * target > 0.0
    zero = np.zeros(k.shape[0])
    for _ in range(MAX_PASSES):
        prescribed = np.zeros(k.shape[0])
        prescribed[top[active]] = target[active]
        dofs = np.unique(np.concatenate([bonded, axis, top[active]]))
        u = skfem.solve(*skfem.condense(k, zero, x=prescribed, D=dofs))
        reaction = sign * (k @ u)[top]  # > 0: the obstacle pushes; < 0 it would pull
        release = active & (reaction < 0.0)
        enter = ~active & (sign * (target - u[top]) > 1e-15)
        if not release.any() and not enter.any():
            break
        active = (active & ~release) | enter
    else:
        raise InvalidInputError("the FE contact's active set did not settle")
    inside = float(r_s[active].max()) if active.any() else 0.0
    beyond = r_s[~active & (r_s > inside)]
    edge = 0.5 * (inside + float(beyond.min())) if len(beyond) else inside
    # surface pressure: sigma_zz projected onto quadratic triangles and probed under the surface
    scalar = basis.with_element(skfem.ElementTriP2())
    field = basis.interpolate(u)
    g = grad(field)
    r_q = np.asarray(basis.global_coordinates())[0]
    hoop = 0.0 if plane else np.asarray(field[0]) / r_q
    szz = lam * (g[0][0] + g[1][1] + hoop) + 2.0 * mu * g[1][1]
    stress = scalar.project(szz)
    pressure = -(scalar.probes(probe(probe_radii)) @ stress)  # compression is negative
    return ContactSolution(
        force=float((2.0 if plane else 2.0 * np.pi) * np.sum(reaction[active])),
        contact_radius=edge,
        peak_pressure=float(pressure[0]), radii=probe_radii, pressure=pressure,
    )  # fmt: skip


def fem_layer_press(modulus: float, poisson: float, thickness: float, radius: float,
                    indentation: float, resolution: int = 24) -> ContactSolution:  # fmt: skip
    """A flat layer (`thickness` [m], bonded to a rigid base) under a rigid sphere of `radius`
    pressed `indentation` into it; FE (module docstring), `resolution` elements across the
    expected contact radius. The layer reaches 20 thicknesses or 20 contact radii out."""
    _check(modulus, poisson, radius, indentation)
    a = math.sqrt(2.0 * radius * indentation)  # the larger of Hertz's and Winkler's

    def gap(rr: Array, zz: Array) -> Array:
        return radius - np.sqrt(np.maximum(radius**2 - rr**2, 0.0)) - indentation

    return _layer(modulus, poisson, thickness, a, gap, resolution)


def fem_punch_press(modulus: float, poisson: float, thickness: float, punch_radius: float,
                    indentation: float, resolution: int = 24) -> ContactSolution:  # fmt: skip
    """A flat layer (`thickness` [m], bonded to a rigid base) under a rigid flat-ended cylinder
    of `punch_radius` [m] pressed `indentation` into it; FE (module docstring). The pressure is
    singular at the punch's edge: ``peak_pressure`` is the centre's."""
    _check(modulus, poisson, punch_radius, indentation)

    def gap(rr: Array, zz: Array) -> Array:
        return np.where(rr <= punch_radius * (1.0 + 1e-9), -indentation, np.inf)

    return _layer(modulus, poisson, thickness, punch_radius, gap, resolution)


def fem_layer_line_press(modulus: float, poisson: float, thickness: float, radius: float,
                         indentation: float, resolution: int = 24) -> ContactSolution:  # fmt: skip
    """A flat layer (`thickness` [m], bonded to a rigid base) under a long rigid cylinder of
    `radius` pressed `indentation` into it, in plane strain: ``force`` per metre of length
    [N/m], ``contact_radius`` the contact's half-width [m]; FE (module docstring)."""
    _check(modulus, poisson, radius, indentation)
    a = math.sqrt(2.0 * radius * indentation)

    def gap(xx: Array, zz: Array) -> Array:
        return radius - np.sqrt(np.maximum(radius**2 - xx**2, 0.0)) - indentation

    return _layer(modulus, poisson, thickness, a, gap, resolution, plane=True)


def hertz_cylinder(modulus: float, poisson: float, radius: float,
                   line_force: float) -> ContactSolution:  # fmt: skip
    """Hertz's line contact: a long rigid cylinder on an elastic half-space carrying
    `line_force` [N/m]: half-width ``b = sqrt(4 R F' / (pi E*))``, ``p(x) = p0 sqrt(1 -
    x^2/b^2)`` with ``p0 = 2 F' / (pi b)``. (The half-space has no finite indentation in plane
    strain: the load is given.)"""
    _check(modulus, poisson, radius, 1e-9)
    finite_float(line_force, "line_force", low=0.0)
    e_star = modulus / (1.0 - poisson**2)
    b = math.sqrt(4.0 * radius * line_force / (math.pi * e_star))
    return ContactSolution(force=float(line_force), contact_radius=b,
                           peak_pressure=2.0 * line_force / (math.pi * b) if b > 0 else 0.0)


def winkler_cylinder(skin: Any, radius: float, indentation: float) -> ContactSolution:
    """The skin's law for a long cylinder of `radius` pressed `indentation` into it, per metre
    of length: half-width ``a = sqrt(2 R delta)``, ``F' = 4/3 (E / h) delta a``, ``p0 = E delta /
    h``."""
    _check(skin.modulus, 0.0, radius, indentation)
    a = math.sqrt(2.0 * radius * indentation)
    return ContactSolution(force=4.0 / 3.0 * skin.stiffness * indentation * a,
                           contact_radius=a, peak_pressure=float(skin.pressure(indentation)))


def punch_half_space(modulus: float, poisson: float, punch_radius: float,
                     indentation: float) -> ContactSolution:  # fmt: skip
    """Boussinesq's flat punch on a half-space: ``F = 2 E* a delta``, the pressure
    ``F / (2 pi a sqrt(a^2 - r^2))`` (its centre's as ``peak_pressure``)."""
    _check(modulus, poisson, punch_radius, indentation)
    force = 2.0 * modulus / (1.0 - poisson**2) * punch_radius * indentation
    return ContactSolution(force=force, contact_radius=punch_radius,
                           peak_pressure=force / (2.0 * math.pi * punch_radius**2))  # fmt: skip


def _layer(modulus: float, poisson: float, thickness: float, a: float,
           gap: Callable[[Array, Array], Array], resolution: int,
           plane: bool = False) -> ContactSolution:  # fmt: skip
    """The FE press of a flat bonded layer by an indenter of contact radius (half-width) about
    `a`, axisymmetric or in plane strain."""
    finite_float(thickness, "thickness", low=1e-7, high=1.0)
    skfem = _fem()
    step = 1.5 * a / int(resolution)
    r = _graded(max(20.0 * thickness, 20.0 * a), 1.5 * a, step)
    z = np.sort(thickness - _graded(thickness, 1.5 * a, step))
    mesh = skfem.MeshTri.init_tensor(r, z)
    tol = 1e-3 * min(thickness, step)
    return _solve(
        mesh, modulus, poisson,
        fixed=lambda x: x[1] < tol,
        surface=lambda x: x[1] > thickness - tol,
        gap=gap,
        sign=-1.0,
        probe=lambda q: np.vstack([q, np.full_like(q, thickness - 0.005 * min(thickness, a))]),
        probe_radii=np.linspace(0.0, 1.3 * a, 53),
        plane=plane,
    )  # fmt: skip


def fem_pad_press(modulus: float, poisson: float, radius: float, thickness: float,
                  indentation: float, resolution: int = 24) -> ContactSolution:  # fmt: skip
    """A fingertip pad: a layer of `thickness` [m] bonded on a rigid spherical core, its outer
    surface a sphere of `radius` [m], pressed `indentation` onto a rigid flat; FE (module
    docstring), `resolution` elements across the expected contact radius."""
    _check(modulus, poisson, radius, indentation)
    finite_float(thickness, "thickness", low=1e-7, high=radius)
    skfem = _fem()
    a = math.sqrt(2.0 * radius * indentation)
    fine = min(math.pi / 2.0, 1.6 * a / radius)
    theta = _graded(math.pi / 2.0, fine, fine / int(resolution))
    depth = _graded(thickness, thickness, min(thickness, fine * radius) / max(6, resolution // 2))
    grid = skfem.MeshTri.init_tensor(theta, np.sort(radius - depth))
    t, rho = grid.p
    # polar angle from the -z axis; the orientation of the triangles kept
    mesh = skfem.MeshTri(np.vstack([rho * np.sin(t), -rho * np.cos(t)]), grid.t[[1, 0, 2]])
    tol = 0.01 * thickness  # facet midpoints of the curved boundaries lie on chords

    def distance(x: Array) -> Array:
        return np.hypot(x[0], x[1])

    under = radius - 0.005 * min(thickness, a)
    return _solve(
        mesh, modulus, poisson,
        fixed=lambda x: distance(x) < radius - thickness + tol,
        surface=lambda x: distance(x) > radius - tol,
        gap=lambda rr, zz: -(radius - indentation) - zz,
        sign=1.0,
        probe=lambda q: np.vstack([q, -np.sqrt(np.maximum(under**2 - q**2, 0.0))]),
        probe_radii=np.linspace(0.0, 1.3 * a, 53),
    )  # fmt: skip


@dataclass(frozen=True)
class LayerKernel:
    """A bonded layer's surface response on a square grid: ``radii`` (m,) [m] and
    ``displacement`` (m,) [m/N], the surface's sinking at a distance from a 1 N load spread
    uniformly over a disc of the grid cell's area; ``own`` [m/N], the sinking at that disc's
    centre (a cell's response to its own load where its depth is matched: the cells' centres
    are the collocation points; the disc's mean sinking, 0.80-0.84 of it, made the law 5-20 %
    too stiff on 0.5-1 mm grids); ``spacing`` [m], the grid's."""

    radii: Array
    displacement: Array
    own: float
    spacing: float
    _spectra: dict[tuple[int, int], Array] = field(default_factory=dict, compare=False,
                                                   repr=False)  # fmt: skip

    def spectrum(self, rows: int, cols: int) -> Array:
        """The FFT of the response on a (2 rows, 2 cols) grid of offsets (zero-padded, for
        non-periodic convolutions of a (rows, cols) image); cached per shape."""
        cached = self._spectra.get((rows, cols))
        if cached is None:
            cached = self._spectra[(rows, cols)] = self._spectrum(rows, cols)
        return cached

    def sink(self, forces: Array) -> Array:
        """The surface's sinking [m] under a (rows, cols) image of forces [N] on the grid."""
        rows, cols = forces.shape
        shape = (2 * rows, 2 * cols)
        return np.fft.irfft2(np.fft.rfft2(forces, shape) * self.spectrum(rows, cols),
                             shape)[:rows, :cols]  # fmt: skip

    def _spectrum(self, rows: int, cols: int) -> Array:
        dy = np.arange(2 * rows)
        dx = np.arange(2 * cols)
        dy = np.where(dy < rows, dy, dy - 2 * rows) * self.spacing
        dx = np.where(dx < cols, dx, dx - 2 * cols) * self.spacing
        dist = np.hypot(dy[:, None], dx[None, :])
        response = np.interp(dist, self.radii, self.displacement, right=0.0)
        response[0, 0] = self.own
        return np.fft.rfft2(response)


@functools.lru_cache(maxsize=16)
def layer_kernel(modulus: float, poisson: float, thickness: float,
                 spacing: float) -> LayerKernel:  # fmt: skip
    """The surface response of a layer (`modulus` [Pa], `poisson`, `thickness` [m], bonded to a
    rigid base) on a grid of `spacing` [m]: axisymmetric FE (module docstring) of a 1 N load on a
    disc of area ``spacing^2``, out to 30 thicknesses. Cached per arguments (0.4-0.8 s)."""
    _check(modulus, poisson, 1.0, 1e-3)
    finite_float(thickness, "thickness", low=1e-7, high=1.0)
    finite_float(spacing, "spacing", low=1e-7, high=thickness)
    skfem = _fem()
    disc = spacing / math.sqrt(math.pi)
    step = disc / 8.0
    r = _graded(max(30.0 * thickness, 30.0 * disc), 3.0 * disc, step, growth=1.15)
    z = np.sort(thickness - _graded(thickness, min(thickness, 3.0 * disc), step, growth=1.15))
    mesh = skfem.MeshTri.init_tensor(r, z)
    basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTriP2()))
    k = _stiffness(skfem, basis, modulus, poisson)
    tol = 1e-3 * step
    loaded = mesh.facets_satisfying(lambda x: (x[1] > thickness - tol) & (x[0] < disc + tol))
    pressure = 1.0 / (math.pi * disc * disc)

    @skfem.LinearForm
    def load(v: Any, w: Any) -> Any:
        return -pressure * v[1] * w.x[0]

    f = skfem.asm(load, skfem.FacetBasis(mesh, basis.elem, facets=loaded))
    bonded = basis.get_dofs(lambda x: x[1] < tol).all()
    axis = basis.get_dofs(lambda x: x[0] < 1e-12).all("u^1")
    u = skfem.solve(*skfem.condense(k, f, D=np.unique(np.concatenate([bonded, axis]))))
    top = basis.get_dofs(lambda x: x[1] > thickness - tol).all("u^2")
    radii = basis.doflocs[0, top]
    order = np.argsort(radii)
    radii, sink = radii[order], -u[top][order]
    return LayerKernel(radii=radii, displacement=sink, own=float(sink[0]), spacing=float(spacing))


def layer_forces(depth: Array, kernel: LayerKernel, tol: float = 1e-9,
                 max_iter: int = 2000) -> Array:  # fmt: skip
    """The contact solution of a depth image: the force [N] on each cell of a (rows, cols)
    `depth` image [m] (how far the undeformed surface lies inside the object; <= 0 out of
    reach) on `kernel`'s grid, such that the layer's sinking (`kernel` convolved with the forces)
    is at least the depth everywhere and equal to it where a cell carries force, and no force
    pulls (Polonsky and Keer's constrained conjugate gradient, displacement given)."""
    depth = np.asarray(depth, dtype=np.float64)
    if depth.ndim != 2 or not np.all(np.isfinite(depth)):
        raise InvalidInputError(f"`depth` must be a finite (rows, cols) image, got {depth.shape}")
    sink = kernel.sink
    forces = np.where(depth > 0.0, 1e-12, 0.0)
    if not forces.any():
        return np.zeros_like(depth)
    direction = np.zeros_like(depth)
    previous, conjugate = 1.0, 0.0
    scale = float(depth.max())
    for _ in range(max_iter):
        gap = sink(forces) - depth
        loaded = forces > 0.0
        residual = np.where(loaded, gap, 0.0)
        norm = float(np.sum(residual * residual))
        if math.sqrt(norm) < tol * scale * math.sqrt(max(int(loaded.sum()), 1)):
            break
        direction = np.where(loaded, residual + conjugate * (norm / previous) * direction, 0.0)
        previous = norm
        change = sink(direction)
        curvature = float(np.sum(np.where(loaded, change * direction, 0.0)))
        step = float(np.sum(residual * direction)) / curvature if curvature > 0.0 else 0.0
        forces = np.maximum(forces - step * direction, 0.0)
        pressed = (forces == 0.0) & (gap < 0.0)  # out of contact but inside the object
        conjugate = 0.0 if pressed.any() else 1.0
        forces[pressed] -= step * gap[pressed]
    else:
        raise InvalidInputError("the layer's contact solution did not converge")
    return forces


def grid_radii(half_width: float, spacing: float) -> Array:
    """(n, n) distances [m] from the centre of a square grid of `spacing` [m] and an odd side
    of n cells reaching at least `half_width` [m] each way (a depth image's cells)."""
    n = int(np.ceil(2.0 * half_width / spacing)) | 1
    k = (np.arange(n) - n // 2) * spacing
    x, y = np.meshgrid(k, k)
    return np.hypot(x, y)


def sphere_depth(radius: float, indentation: float, spacing: float) -> Array:
    """The depth image [m] of a rigid sphere of `radius` pressed `indentation` into a flat pad,
    on a grid of `spacing` (:func:`grid_radii`) reaching 1.3 Winkler contact radii out."""
    r = grid_radii(1.3 * math.sqrt(2.0 * radius * indentation), spacing)
    return indentation - (radius - np.sqrt(np.maximum(radius**2 - r**2, 0.0)))


def cylinder_depth(radius: float, indentation: float, spacing: float,
                   half_length: float) -> Array:  # fmt: skip
    """The depth image [m] of a rigid cylinder of `radius` (its axis along the rows) pressed
    `indentation` into a flat pad, `half_length` [m] each way from the centre row, on a grid of
    `spacing` reaching 1.3 Winkler half-widths across; odd sides, the centre row in the middle
    (its pressure stands for the plane-strain section)."""
    a = math.sqrt(2.0 * radius * indentation)
    cols = int(np.ceil(2.0 * 1.3 * a / spacing)) | 1
    rows = int(np.ceil(2.0 * half_length / spacing)) | 1
    x = (np.arange(cols) - cols // 2) * spacing
    profile = indentation - (radius - np.sqrt(np.maximum(radius**2 - x**2, 0.0)))
    return np.broadcast_to(profile, (rows, cols)).copy()


def layer_pressure(depth: Array, spacing: float, modulus: float, poisson: float,
                   thickness: float) -> Array:  # fmt: skip
    """Pressure [Pa] (rows, cols) of a `depth` image [m] on a grid of `spacing` [m] for a layer
    of `modulus`, `poisson` and `thickness` bonded to a rigid core (module docstring): the law
    with lateral coupling, in place of the Winkler law's ``E d / h`` per cell."""
    kernel = layer_kernel(float(modulus), float(poisson), float(thickness), float(spacing))
    return layer_forces(depth, kernel) / spacing**2


__all__ = [
    "GELSIGHT_MINI_PRESSES", "GELSIGHT_MINI_SPHERE_RADIUS",
    "ContactSolution", "LayerKernel", "cylinder_depth", "fem_layer_line_press", "fem_layer_press",
    "fem_pad_press", "fem_punch_press", "grid_radii", "hertz_cylinder", "hertz_sphere",
    "layer_forces", "layer_kernel", "layer_pressure", "punch_half_space", "sphere_depth",
    "winkler_cylinder", "winkler_sphere",
]  # fmt: skip
