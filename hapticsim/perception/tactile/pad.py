"""The geometry of a taxel pad: a rows x columns grid laid on a fingertip's surface.

A pad lives in the frame of the element that carries it (a fingertip geom or site; the *carrier
frame*). Its taxels sit on

- a **sphere** of radius R about ``origin`` (a curved pad following a spherical fingertip): the
  grid's tangent coordinates ``(u, v)`` [m] are mapped by the exponential map at the pad's centre
  direction ``m0``, so distances along the grid's rows and columns through the centre are arc
  lengths on the sphere (geodesic polar coordinates). A taxel at ``(u, v)``, ``r = |(u, v)|``,
  ``theta = r / R`` lies at ``origin + R * n`` with the outward unit normal
  ``n = cos(theta) m0 + sin(theta) (u e_u + v e_v) / r``; its area is ``pitch^2 sin(theta) /
  theta`` (the sphere's area element in geodesic polar coordinates);
- or a **plane** through ``origin`` with normal ``m0`` (a flat plate): ``origin + u e_u + v e_v``,
  normal ``m0``, area ``pitch^2``.

``e_v`` (increasing row index) is ``up`` made orthogonal to ``m0``; ``e_u = e_v x m0`` (increasing
column index), so that (e_u, e_v, m0) is right-handed. Taxel ``(i, j)`` has
``u = (j - (cols - 1) / 2) * pitch`` and ``v = (i - (rows - 1) / 2) * pitch``.

numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_array, finite_float, positive_int
from hapticsim.errors import InvalidInputError

Array = NDArray[np.float64]

#: Largest angle [rad] from the pad's centre that a curved pad's taxels may reach (its corners):
#: beyond pi the exponential map folds the grid over itself.
MAX_PAD_ANGLE: float = 0.95 * np.pi
#: Largest number of taxels in one pad (rows * cols).
MAX_TAXELS: int = 65_536
#: Default grid of a fingertip pad: (rows, cols, pitch [m]). On an 8 mm fingertip sphere it
#: reaches 107 deg from the pad's centre along its rows and columns: 99 % of the contacts of the
#: paper strategy lie within about 100 deg of a finger's mean contact direction. 1 mm resolves a
#: box's rounded edge (at 1.5 mm an edge lights one row of taxels and the paper cube's nH
#: epsilon from the estimated contacts was 0.011, at 1 mm 0.0007; docs/tactile/README.md).
DEFAULT_PAD_GRID: tuple[int, int, float] = (31, 31, 0.001)


class PadError(InvalidInputError):
    """A pad that cannot be laid out; the message names the field."""


def _unit(value: object, name: str) -> Array:
    v = finite_array(value, name, (3,))
    n = float(np.linalg.norm(v))
    if n < 1e-9:
        raise PadError(f"`{name}` must be a non-zero vector, got {v.tolist()}")
    return v / n


@dataclass(frozen=True)
class PadLayout:
    """A taxel grid on a sphere or a plane, in its carrier's frame (module docstring).

    Attributes:
        rows: number of rows, >= 1.
        cols: number of columns, >= 1.
        pitch: taxel spacing along the surface at the pad's centre [m], > 0.
        radius: radius R of the sphere the pad follows [m], or None for a flat plate.
        normal: (3,) the outward normal at the pad's centre, m0 (normalised).
        up: (3,) the direction of increasing row index at the centre (made orthogonal to
            `normal`; must not be parallel to it).
        origin: (3,) the sphere's centre (curved pad) or the plate's centre (flat pad) [m].

    Raises:
        PadError: a field out of its domain, `up` parallel to `normal`, or a curved pad whose
            corners reach beyond :data:`MAX_PAD_ANGLE` from its centre.
    """

    rows: int
    cols: int
    pitch: float
    radius: float | None
    normal: Array
    up: Array
    origin: Array

    def __post_init__(self) -> None:
        rows = positive_int(self.rows, "rows", maximum=MAX_TAXELS)
        cols = positive_int(self.cols, "cols", maximum=MAX_TAXELS)
        if rows * cols > MAX_TAXELS:
            raise PadError(f"a pad holds at most {MAX_TAXELS} taxels, got {rows} x {cols}")
        pitch = finite_float(self.pitch, "pitch", low=1e-6, high=0.1)
        radius = None if self.radius is None else finite_float(self.radius, "radius", 1e-4, 1.0)
        m0 = _unit(self.normal, "normal")
        up = finite_array(self.up, "up", (3,))
        ev = up - (up @ m0) * m0
        if np.linalg.norm(ev) < 1e-6 * max(float(np.linalg.norm(up)), 1e-300):
            raise PadError(f"`up` {up.tolist()} must not be parallel to `normal` {m0.tolist()}")
        origin = finite_array(self.origin, "origin", (3,))
        for name, value in (
            ("rows", rows),
            ("cols", cols),
            ("pitch", pitch),
            ("radius", radius),
            ("normal", m0),
            ("up", ev / np.linalg.norm(ev)),
            ("origin", origin),
        ):
            object.__setattr__(self, name, value)  # fmt: skip
        if radius is not None:
            corner = np.hypot((cols - 1) / 2, (rows - 1) / 2) * pitch / radius
            if corner > MAX_PAD_ANGLE:
                raise PadError(
                    f"a {rows} x {cols} pad of pitch {pitch * 1e3:g} mm on a sphere of radius "
                    f"{radius * 1e3:g} mm reaches {np.degrees(corner):.0f} deg from its centre "
                    f"at its corners (at most {np.degrees(MAX_PAD_ANGLE):.0f}): fewer taxels "
                    "or a smaller pitch"
                )

    # ----------------------------------------------------------------- frame
    @cached_property
    def e_u(self) -> Array:
        """(3,) the direction of increasing column index at the centre."""
        return np.cross(self.up, self.normal)

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols)."""
        return (self.rows, self.cols)

    @property
    def count(self) -> int:
        """Number of taxels."""
        return self.rows * self.cols

    @property
    def curved(self) -> bool:
        """True for a pad on a sphere."""
        return self.radius is not None

    @property
    def extent(self) -> tuple[float, float]:
        """(height, width) [m] of the grid along the surface through its centre."""
        return ((self.rows - 1) * self.pitch, (self.cols - 1) * self.pitch)

    @cached_property
    def uv(self) -> Array:
        """(rows, cols, 2) float, tangent coordinates (u, v) [m] of every taxel."""
        u = (np.arange(self.cols) - (self.cols - 1) / 2.0) * self.pitch
        v = (np.arange(self.rows) - (self.rows - 1) / 2.0) * self.pitch
        uu, vv = np.meshgrid(u, v)
        out = np.stack([uu, vv], axis=-1)
        out.setflags(write=False)
        return out

    # ----------------------------------------------------------------- mapping
    def map(self, uv: Array) -> tuple[Array, Array]:
        """Positions and outward unit normals of tangent coordinates.

        Args:
            uv: (..., 2) float, tangent coordinates (u, v) [m].

        Returns:
            positions (..., 3) [m] and normals (..., 3), in the carrier frame.
        """
        uv = np.asarray(uv, dtype=np.float64)
        u, v = uv[..., 0:1], uv[..., 1:2]
        tangent = u * self.e_u + v * self.up
        if self.radius is None:
            normals = np.broadcast_to(self.normal, tangent.shape).copy()
            return self.origin + tangent, normals
        r = np.hypot(u, v)
        theta = r / self.radius
        with np.errstate(invalid="ignore", divide="ignore"):
            sinc = np.where(r > 0, np.sin(theta) / np.where(r > 0, r, 1.0), 1.0 / self.radius)
        normals = np.cos(theta) * self.normal + sinc * tangent
        return self.origin + self.radius * normals, normals

    @cached_property
    def taxels(self) -> tuple[Array, Array, Array]:
        """Every taxel's position (rows, cols, 3) [m], outward unit normal (rows, cols, 3) and
        area (rows, cols) [m^2], in the carrier frame."""
        pos, nrm = self.map(self.uv)
        area = np.full(self.shape, self.pitch**2)
        if self.radius is not None:
            theta = np.hypot(self.uv[..., 0], self.uv[..., 1]) / self.radius
            area *= np.sinc(theta / np.pi)  # sin(theta) / theta
        for arr in (pos, nrm, area):
            arr.setflags(write=False)
        return pos, nrm, area

    def resampled(self, pitch: float) -> PadLayout:
        """The same extent laid out at another pitch [m] (a skin preset of its own
        resolution): ``rows = round(height / pitch) + 1``, likewise the columns, at least 1."""
        p = finite_float(pitch, "pitch", low=1e-6, high=0.1)
        height, width = self.extent
        return PadLayout(
            rows=max(1, int(round(height / p)) + 1), cols=max(1, int(round(width / p)) + 1),
            pitch=p, radius=self.radius, normal=self.normal, up=self.up, origin=self.origin,
        )  # fmt: skip


def default_up(normal: Array) -> Array:
    """A direction not parallel to `normal` (3,): the carrier's z axis, or its x axis when the
    normal is within 30 degrees of z."""
    n = _unit(normal, "normal")
    return (
        np.array([1.0, 0.0, 0.0])
        if abs(n[2]) > np.cos(np.radians(30))
        else np.array([0.0, 0.0, 1.0])
    )


__all__ = [
    "DEFAULT_PAD_GRID",
    "MAX_PAD_ANGLE",
    "MAX_TAXELS",
    "PadError",
    "PadLayout",
    "default_up",
]
