"""The skin's elastic model and the sensor model of its taxels.

**Skin** (:class:`SkinModel`): a linear elastic layer of Young's modulus E [Pa] and thickness h
[m] on a rigid core, modelled as a Winkler (mattress) foundation: every taxel's patch of skin is
an independent spring compressed along its own normal, so the pressure under a taxel is

    p = E * d / h,

d the depth [m] by which the undeformed skin surface at the taxel lies inside the object, along
the taxel's inward normal (:mod:`hapticsim.perception.tactile.depth`). A sphere of radius R pressed
by delta
into a flat face then carries ``F = pi E R delta^2 / h`` (:meth:`SkinModel.sphere_force`).

With a Poisson's ratio (``poisson``, SPEC §11) the skin is instead the elastic layer itself, its
lateral coupling included (:func:`~hapticsim.perception.tactile.mechanics.layer_pressure`): the
surface sinks by the taxels' forces convolved with the layer's influence function on the pad's
grid, and the pressure image is the contact solution of the depth image (the sinking equals the
depth where a taxel is pressed, no taxel pulls). An elastomer (0.45-0.49) then pushes back 2-3
times harder than the Winkler law says, as the finite-element references do
(docs/tactile/mechanics/README.md). The influence function needs the ``fem`` extra
(scikit-fem), once per layer and pitch (about 0.5 s).

**Sensor** (:class:`SensorModel`): what the taxel electronics make of the pressure image, in
this order: crosstalk (a Gaussian blur of std ``blur`` taxels, zero beyond the pad's edge),
per-taxel gains (a fixed pattern, std ``gain_spread``), white noise of std ``noise`` [Pa] per
reading, saturation at ``full_scale``, quantisation to ``bits`` bits of the full scale, the
detection ``threshold`` (readings below it are 0) and dead taxels (a fixed pattern of the share
``dead_fraction``, reading 0). The fixed patterns are drawn once per sensor
(:meth:`SensorModel.pattern`), the noise per reading; both from seeded generators.

numpy only (the layer law: :mod:`~hapticsim.perception.tactile.mechanics`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_float, positive_int
from hapticsim.errors import InvalidInputError

Array = NDArray[np.float64]

#: Normal force [N] a fingertip presses with to record a probe (the probe's threshold,
#: :class:`~hapticsim.sim.controllers.ProbeConfig`): the tactile hand's contact softness matches
#: the skin's law there, and the analytic backend's rigid pad sinks in by the skin's penetration
#: at it.
PROBE_FORCE: float = 0.5


#: Penetrations [m] of a sphere's force table under the layer law (:meth:`SkinModel.sphere_force`),
#: as fractions of the layer's thickness: geometric from 1e-4 to 1.
SPHERE_TABLE: Array = np.geomspace(1e-4, 1.0, 41)
#: Grid spacing of the sphere's force table, as a fraction of the layer's thickness (the law on
#: a 0.1 mm grid for a 2 mm layer holds the finite-element pad within 1.7 %).
SPHERE_TABLE_SPACING: float = 0.05
#: Laws of the skin (:attr:`SkinModel.law`).
SKIN_LAWS: tuple[str, ...] = ("winkler", "layer")


@dataclass(frozen=True)
class SkinModel:
    """A linear elastic skin layer (module docstring).

    Attributes:
        modulus: Young's modulus E [Pa], > 0.
        thickness: layer thickness h [m], > 0.
        poisson: Poisson's ratio in [0, 0.4999] for the layer law, or None for the Winkler law
            (module docstring).
    """

    modulus: float = 2.0e5
    thickness: float = 0.002
    poisson: float | None = None

    def __post_init__(self) -> None:
        finite_float(self.modulus, "modulus", low=1.0, high=1e12)
        finite_float(self.thickness, "thickness", low=1e-6, high=0.1)
        if self.poisson is not None:
            finite_float(self.poisson, "poisson", low=0.0, high=0.4999)

    @property
    def law(self) -> str:
        """``"winkler"`` (no Poisson's ratio) or ``"layer"`` (:data:`SKIN_LAWS`)."""
        return "winkler" if self.poisson is None else "layer"

    @property
    def stiffness(self) -> float:
        """E / h [Pa/m]: the Winkler law's pressure per metre of depth."""
        return self.modulus / self.thickness

    def kernel(self, spacing: float):  # noqa: ANN201 - mechanics.LayerKernel
        """The layer's influence function on a grid of `spacing` [m] (the layer law; cached)."""
        from hapticsim.perception.tactile.mechanics import layer_kernel

        if self.poisson is None:
            raise InvalidInputError("the Winkler skin has no influence function")
        spacing = finite_float(spacing, "spacing", low=1e-7, high=self.thickness)
        try:
            return layer_kernel(float(self.modulus), float(self.poisson), float(self.thickness),
                                float(spacing))  # fmt: skip
        except InvalidInputError as exc:
            if not isinstance(exc.__cause__, ImportError):
                raise
            raise InvalidInputError(
                "a skin with a Poisson's ratio (the layer law) needs scikit-fem: "
                'pip install -e ".[fem]"'
            ) from exc

    def pressure(self, depth: Array, spacing: float | None = None) -> Array:
        """Pressure [Pa] of depths [m] (negative depths give 0). The Winkler law takes any
        shape; the layer law images (..., rows, cols) on a grid of `spacing` [m] (the pad's
        pitch), each the contact solution over the box of its pressed taxels."""
        d = np.asarray(depth, dtype=np.float64)
        if self.poisson is None:
            return self.stiffness * np.maximum(d, 0.0)
        from hapticsim.perception.tactile.mechanics import layer_forces

        kernel = self.kernel(self._spacing(spacing, d))

        def solve(image: Array) -> Array:
            # a taxel not inside the object has it at an unknown distance (depths are >= 0):
            # far, so the layer may bulge there (a thin, near-incompressible layer rises around
            # a press; held at 0 such taxels carried force, outside the object)
            gap = np.where(image > 0.0, image, -1.0)
            return layer_forces(gap, kernel) / kernel.spacing**2

        return _by_pressed_box(d, solve)

    def depth(self, pressure: Array, spacing: float | None = None) -> Array:
        """The depth [m] a pressure [Pa] reading stands for where it is positive (0 elsewhere):
        the inverse of :meth:`pressure`. Under the layer law, the layer's sinking under the
        reading (its forces convolved with the influence function), which is the depth where
        a taxel is pressed."""
        p = np.maximum(np.asarray(pressure, dtype=np.float64), 0.0)
        if self.poisson is None:
            return p / self.stiffness
        kernel = self.kernel(self._spacing(spacing, p))

        def sink(image: Array) -> Array:
            down = kernel.sink(image * kernel.spacing**2)
            return np.where(image > 0.0, np.maximum(down, 0.0), 0.0)

        return _by_pressed_box(p, sink)

    def cell_stiffness(self, spacing: float | None = None) -> float:
        """Pressure [Pa] per metre of depth of one taxel's cell pressed alone: ``E / h`` under
        the Winkler law; under the layer law the inverse of the cell's own sinking per unit
        pressure (what a taxel's pressure noise is in depth)."""
        if self.poisson is None:
            return self.stiffness
        kernel = self.kernel(self._spacing(spacing, None))
        return 1.0 / (kernel.own * kernel.spacing**2)

    def sphere_force(self, radius: float, penetration: float) -> float:
        """Normal force [N] of a sphere of `radius` [m] pressed `penetration` [m] into a flat
        face: ``pi E R delta^2 / h`` under the Winkler law (the foundation integrated over the
        contact disc, to first order in delta / R); under the layer law interpolated (log-log)
        in a table of contact solutions (:data:`SPHERE_TABLE`, on a grid of
        :data:`SPHERE_TABLE_SPACING` thicknesses)."""
        d = max(float(penetration), 0.0)
        if self.poisson is None:
            return float(np.pi * self.stiffness * radius * (d * d))
        if d == 0.0:
            return 0.0
        depths, forces = _sphere_table(self, float(radius))
        return float(np.exp(np.interp(np.log(d), np.log(depths), np.log(forces))))

    def sphere_penetration(self, radius: float, force: float) -> float:
        """The penetration [m] at which a sphere of `radius` [m] carries `force` [N] on a flat
        face (inverse of :meth:`sphere_force`)."""
        f = max(float(force), 0.0)
        if self.poisson is None:
            return float(np.sqrt(f / (np.pi * self.stiffness * radius)))
        if f == 0.0:
            return 0.0
        depths, forces = _sphere_table(self, float(radius))
        return float(np.exp(np.interp(np.log(f), np.log(forces), np.log(depths))))

    def secant_stiffness(self, radius: float, force: float) -> float:
        """Force over penetration [N/m] of a sphere of `radius` [m] carrying `force` [N] on a
        flat face (:meth:`sphere_penetration`)."""
        if self.poisson is None:
            return float(np.sqrt(np.pi * self.stiffness * radius * force))
        return float(force) / self.sphere_penetration(radius, force)

    def _spacing(self, spacing: float | None, image: Array | None) -> float:
        if spacing is None:
            raise InvalidInputError("the layer law needs the taxels' `spacing` [m]")
        if image is not None and image.ndim < 2:
            raise InvalidInputError(
                f"the layer law reads (rows, cols) images, got the shape {image.shape}"
            )
        return float(spacing)


def _by_pressed_box(images: Array, solve: Callable[[Array], Array]) -> Array:
    """`solve` of each (rows, cols) image of `images` (..., rows, cols) over the box of its
    positive cells (:func:`_pressed_box`); 0 elsewhere."""
    out = np.zeros(images.shape)
    flat = out.reshape(-1, *images.shape[-2:])
    for k, image in enumerate(images.reshape(-1, *images.shape[-2:])):
        box = _pressed_box(image > 0.0)
        if box is not None:
            flat[k][box] = solve(image[box])
    return out


def _pressed_box(pressed: NDArray[np.bool_]) -> tuple[slice, slice] | None:
    """The rows and columns spanning an image's pressed taxels, or None: cells beyond them
    carry no force in a contact solution, so it is solved on that box alone."""
    rows, cols = np.flatnonzero(pressed.any(axis=1)), np.flatnonzero(pressed.any(axis=0))
    if not len(rows):
        return None
    return slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1)


@lru_cache(maxsize=32)
def _sphere_table(skin: SkinModel, radius: float) -> tuple[Array, Array]:
    """Penetrations [m] and forces [N] of a sphere pressed into a flat face under the layer
    law (:meth:`SkinModel.sphere_force`)."""
    from hapticsim.perception.tactile.mechanics import layer_forces, sphere_depth

    kernel = skin.kernel(SPHERE_TABLE_SPACING * skin.thickness)
    depths = SPHERE_TABLE * min(skin.thickness, 0.5 * radius)
    forces = np.array([float(layer_forces(sphere_depth(radius, d, kernel.spacing), kernel).sum())
                       for d in depths])  # fmt: skip
    keep = forces > 0.0
    return depths[keep], forces[keep]


@dataclass(frozen=True)
class FixedPattern:
    """A sensor's fixed pattern: per-taxel gains and dead taxels.

    Attributes:
        gain: (pads, rows, cols) float, multiplicative gains (>= 0).
        dead: (pads, rows, cols) bool, True for taxels that read 0.
    """

    gain: Array
    dead: NDArray[np.bool_]


@dataclass(frozen=True)
class SensorModel:
    """The taxels' electronics (module docstring); the defaults are an ideal sensor.

    Attributes:
        noise: std of the white noise per taxel and reading [Pa], >= 0.
        full_scale: saturation [Pa], > 0 (inf: none).
        bits: quantisation of [0, full_scale] into ``2**bits - 1`` steps, 1..24, or None
            (needs a finite `full_scale`).
        gain_spread: std of the per-taxel gains about 1, >= 0.
        dead_fraction: share of dead taxels, in [0, 1).
        blur: std of the Gaussian crosstalk kernel [taxels], >= 0.
        threshold: readings below it are 0 [Pa], >= 0.
    """

    noise: float = 0.0
    full_scale: float = float("inf")
    bits: int | None = None
    gain_spread: float = 0.0
    dead_fraction: float = 0.0
    blur: float = 0.0
    threshold: float = 0.0

    def __post_init__(self) -> None:
        finite_float(self.noise, "noise", low=0.0)
        if not (isinstance(self.full_scale, (int, float)) and self.full_scale > 0):
            raise InvalidInputError(f"`full_scale` must be > 0 [Pa], got {self.full_scale!r}")
        if self.bits is not None:
            positive_int(self.bits, "bits", maximum=24)
            if not np.isfinite(self.full_scale):
                raise InvalidInputError("`bits` needs a finite `full_scale` [Pa]")
        finite_float(self.gain_spread, "gain_spread", low=0.0, high=1.0)
        if not 0.0 <= finite_float(self.dead_fraction, "dead_fraction") < 1.0:
            raise InvalidInputError(
                f"`dead_fraction` must be in [0, 1), got {self.dead_fraction!r}"
            )
        finite_float(self.blur, "blur", low=0.0, high=10.0)
        finite_float(self.threshold, "threshold", low=0.0)

    @property
    def ideal(self) -> bool:
        """True when the sensor changes nothing."""
        return self == SensorModel()

    @property
    def step(self) -> float:
        """Quantisation step [Pa] (0 without quantisation)."""
        return 0.0 if self.bits is None else self.full_scale / (2**self.bits - 1)

    def pattern(self, shape: tuple[int, int, int], rng: np.random.Generator) -> FixedPattern:
        """Draw the fixed pattern of a sensor of `shape` (pads, rows, cols)."""
        gain = np.ones(shape)
        if self.gain_spread > 0:
            gain = np.maximum(1.0 + self.gain_spread * rng.standard_normal(shape), 0.0)
        dead = np.zeros(shape, dtype=bool)
        if self.dead_fraction > 0:
            dead = rng.random(shape) < self.dead_fraction
        return FixedPattern(gain=gain, dead=dead)

    def apply(
        self, pressure: Array, pattern: FixedPattern | None, rng: np.random.Generator | None
    ) -> Array:
        """The readings [Pa] of ideal pressure images.

        Args:
            pressure: (pads, rows, cols) float, the skin's pressure [Pa].
            pattern: the sensor's fixed pattern (None: ideal gains, no dead taxels).
            rng: the generator of the noise (needed when `noise` > 0).

        Returns:
            (pads, rows, cols) float readings [Pa], >= 0.
        """
        out = np.asarray(pressure, dtype=np.float64)
        if self.blur > 0:
            out = gaussian_blur(out, self.blur)
        if pattern is not None:
            out = np.where(pattern.dead, 0.0, out * pattern.gain)
        if self.noise > 0:
            if rng is None:
                raise InvalidInputError("a sensor with noise needs a generator `rng`")
            out = out + self.noise * rng.standard_normal(out.shape)
        out = np.clip(out, 0.0, self.full_scale)
        if self.bits is not None:
            out = np.round(out / self.step) * self.step
        if self.threshold > 0:
            out = np.where(out < self.threshold, 0.0, out)
        if pattern is not None:
            out = np.where(pattern.dead, 0.0, out)
        return out


def gaussian_blur(images: Array, sigma: float) -> Array:
    """Separable Gaussian blur of the last two axes of `images` (std `sigma` taxels; the
    kernel is cut at 3 sigma and the image is zero beyond its edge)."""
    radius = max(1, int(np.ceil(3.0 * sigma)))
    x = np.arange(-radius, radius + 1)
    kernel = np.exp(-0.5 * (x / sigma) ** 2)
    kernel /= kernel.sum()
    out = np.asarray(images, dtype=np.float64)
    for axis in (-1, -2):
        moved = np.moveaxis(out, axis, -1)
        padded = np.pad(moved, [(0, 0)] * (moved.ndim - 1) + [(radius, radius)])
        windows = np.lib.stride_tricks.sliding_window_view(padded, len(kernel), axis=-1)
        out = np.moveaxis(windows @ kernel, -1, axis)
    return out


@dataclass(frozen=True)
class SkinPreset:
    """A named skin: its elastic model, its sensor model and, optionally, its own taxel pitch.

    Attributes:
        name: the preset's name.
        skin: the elastic model.
        sensor: the sensor model.
        pitch: the taxel pitch [m] the sensor has (the hand's pads are laid out again at it,
            over the same extent), or None (the hand's own pitch).
        description: one line on what it models.
        source: where its numbers come from (and which are assumed).
    """

    name: str
    skin: SkinModel = field(default_factory=SkinModel)
    sensor: SensorModel = field(default_factory=SensorModel)
    pitch: float | None = None
    description: str = ""
    source: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise InvalidInputError(
                f"a skin's `name` must be a non-empty string, got {self.name!r}"
            )
        if self.pitch is not None:
            finite_float(self.pitch, "pitch", low=1e-5, high=0.05)

    def to_dict(self) -> dict[str, object]:
        """JSON-ready description (for metrics and provenance)."""
        s = self.sensor
        return {
            "name": self.name,
            "modulus": self.skin.modulus,
            "thickness": self.skin.thickness,
            "poisson": self.skin.poisson,
            "law": self.skin.law,
            "pitch": self.pitch,
            "sensor": {
                "noise": s.noise, "full_scale": None if not np.isfinite(s.full_scale)
                else s.full_scale, "bits": s.bits, "gain_spread": s.gain_spread,
                "dead_fraction": s.dead_fraction, "blur": s.blur, "threshold": s.threshold,
            },
            "description": self.description,
            "source": self.source,
        }  # fmt: skip


__all__ = [
    "FixedPattern",
    "PROBE_FORCE",
    "SKIN_LAWS",
    "SPHERE_TABLE",
    "SPHERE_TABLE_SPACING",
    "SensorModel",
    "SkinModel",
    "SkinPreset",
    "gaussian_blur",
]
