"""The skin's law against an elastic layer (issue 38, item 3): docs/tactile/mechanics/README.md.

    python scripts/skin_mechanics.py --out docs/tactile/mechanics/mechanics.json \
        --figure docs/tactile/mechanics/mechanics.png

For the built-in hand's fingertip pad (a 2 mm layer on a sphere of 8 mm, both skin presets'
thickness; the presets differ in Young's modulus only, which every ratio here is free of), pressed
0.1-1 mm onto a rigid flat: the skin's Winkler law (force, contact radius, centre pressure)
against the finite-element solution of the same pad (hapticsim.perception.tactile.mechanics) for
Poisson's ratios 0 (the Winkler law's own assumption), 0.3, 0.45 and 0.49 (silicone elastomers:
0.45-0.5); and the FE's own check against Hertz's solution (a 6 mm layer) at two resolutions.
Then the law with the layer's lateral coupling (``layer_pressure``, a 0.1 mm grid) and the
Winkler law against the FE for a sphere of 8 mm pressed into a flat 2 mm pad, and, held out
(none of it was looked at while the law was written), spheres of 4 and 15 mm in 1 and 3 mm
layers and flat-ended punches; the FE punch against Boussinesq's half-space solution. And a long
cylinder of 8 mm (a line contact) in 1-3 mm layers: the plane-strain FE against Hertz's line
contact and the Winkler law, the layer law and the Winkler law against that FE. And the skin
itself with a Poisson's ratio (the layer law on its pads' 0.5 and 1 mm grids) against the FE.
Prints JSON (and writes it with --out); --figure draws the pressure profiles at 0.5 mm.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from typing import Any

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from hapticsim.constants import FINGERTIP_RADIUS
from hapticsim.perception.tactile.mechanics import (
    ContactSolution,
    cylinder_depth,
    fem_layer_line_press,
    fem_layer_press,
    fem_pad_press,
    fem_punch_press,
    grid_radii,
    hertz_cylinder,
    hertz_sphere,
    layer_pressure,
    punch_half_space,
    sphere_depth,
    winkler_cylinder,
    winkler_sphere,
)
from hapticsim.perception.tactile.presets import load_skin
from hapticsim.perception.tactile.skin import SkinModel

POISSON = (0.0, 0.3, 0.45, 0.49)
INDENTATIONS = (1e-4, 2.5e-4, 5e-4, 1e-3)  # [m]


def table(resolution: int = 48) -> dict[str, Any]:
    """The rows of the module docstring."""
    vision = load_skin("vision").skin
    capacitive = load_skin("capacitive").skin
    assert vision.thickness == capacitive.thickness  # the ratios below hold for both
    skin = vision
    radius = FINGERTIP_RADIUS
    rows = []
    for nu in POISSON:
        for delta in INDENTATIONS:
            fe = fem_pad_press(skin.modulus, nu, radius, skin.thickness, delta, resolution)
            w = winkler_sphere(skin, radius, delta)
            sys.stderr.write(f"nu {nu} delta {delta * 1e3:.2f} mm: skin/FE force "
                             f"{w.force / fe.force:.3f}\n")  # fmt: skip
            rows.append({
                "poisson": nu, "indentation_mm": delta * 1e3,
                "fe": {"force_n": fe.force, "contact_radius_mm": fe.contact_radius * 1e3,
                       "peak_pressure_kpa": fe.peak_pressure / 1e3},
                "skin": {"force_n": w.force, "contact_radius_mm": w.contact_radius * 1e3,
                         "peak_pressure_kpa": w.peak_pressure / 1e3},
                "skin_over_fe": {"force": w.force / fe.force,
                                 "contact_radius": w.contact_radius / fe.contact_radius,
                                 "peak_pressure": w.peak_pressure / fe.peak_pressure},
            })  # fmt: skip
    checks = []
    for res in (24, resolution):
        for delta in (1e-5, 2e-5):
            ref = hertz_sphere(skin.modulus, 0.3, radius, delta)
            fe = fem_pad_press(skin.modulus, 0.3, radius, 0.006, delta, res)
            checks.append({
                "resolution": res, "indentation_mm": delta * 1e3, "thickness_mm": 6.0,
                "fe_over_hertz": {"force": fe.force / ref.force,
                                  "contact_radius": fe.contact_radius / ref.contact_radius,
                                  "peak_pressure": fe.peak_pressure / ref.peak_pressure},
            })  # fmt: skip
    layer = []
    spacing = 1e-4
    for nu in POISSON:
        for delta in INDENTATIONS:
            clock = time.perf_counter()
            p = layer_pressure(sphere_depth(radius, delta, spacing), spacing, skin.modulus, nu,
                               skin.thickness)  # fmt: skip
            seconds = time.perf_counter() - clock
            fe = fem_layer_press(skin.modulus, nu, skin.thickness, radius, delta, resolution)
            w = winkler_sphere(skin, radius, delta)
            layer.append({
                "poisson": nu, "indentation_mm": delta * 1e3, "grid_mm": spacing * 1e3,
                "fe_force_n": fe.force, "seconds": seconds,
                "layer_over_fe": _over(_measures(p, spacing), fe),
                "winkler_over_fe": _over(w, fe),
            })  # fmt: skip
    return {"pad_radius_mm": radius * 1e3, "thickness_mm": skin.thickness * 1e3,
            "modulus_pa": {"vision": vision.modulus, "capacitive": capacitive.modulus},
            "resolution": resolution, "rows": rows, "hertz_check": checks, "flat_pad": layer,
            "held_out": held_out(skin.modulus), "boussinesq_check": boussinesq(skin.modulus),
            "cylinders": cylinders(skin.modulus), "skin_grids": skin_grids(skin, resolution)}


def skin_grids(skin: SkinModel, resolution: int) -> list[dict[str, Any]]:
    """The skin itself on its pads' grids (SkinModel with a Poisson's ratio: the layer law at
    the taxel pitch) and the Winkler skin, against the FE layer: the 8 mm sphere pressed
    0.1-1 mm into a flat 2 mm pad, its centre on a taxel and half a pitch off along both axes;
    and the CPU time of one image's contact solution."""
    out = []
    radius = FINGERTIP_RADIUS
    for nu in (0.45, 0.49):
        layer = SkinModel(skin.modulus, skin.thickness, nu)
        for pitch in (5e-4, 1e-3):
            for delta in INDENTATIONS:
                fe = fem_layer_press(skin.modulus, nu, skin.thickness, radius, delta, resolution)
                for offset in (0.0, 0.5):
                    r = grid_radii(1.3 * np.sqrt(2.0 * radius * delta) + pitch, pitch)
                    n = len(r)
                    k = (np.arange(n) - n // 2 - offset) * pitch
                    r = np.hypot(k[:, None], k[None, :])
                    depth = delta - (radius - np.sqrt(np.maximum(radius**2 - r**2, 0.0)))
                    layer.pressure(depth, pitch)  # the kernel, once
                    clock = time.process_time()
                    p = layer.pressure(depth, pitch)
                    seconds = time.process_time() - clock
                    w = skin.pressure(depth)
                    out.append({
                        "poisson": nu, "pitch_mm": pitch * 1e3, "indentation_mm": delta * 1e3,
                        "offset_pitch": offset, "pressed_taxels": int((p > 0).sum()),
                        "cpu_seconds": seconds,
                        "skin_over_fe": _over(_grid_measures(p, pitch), fe),
                        "winkler_skin_over_fe": _over(_grid_measures(w, pitch), fe),
                    })  # fmt: skip
                sys.stderr.write(f"skin grid nu {nu} pitch {pitch * 1e3:g} mm delta "
                                 f"{delta * 1e3:g} mm\n")  # fmt: skip
    return out


def _grid_measures(pressure: np.ndarray, spacing: float) -> ContactSolution:
    """:func:`_measures` with the largest pressure for the centre's (a sphere off a taxel)."""
    m = _measures(pressure, spacing)
    return ContactSolution(m.force, m.contact_radius, float(pressure.max()))


def _measures(pressure: np.ndarray, spacing: float) -> ContactSolution:
    """A pressure image's force, contact radius (of the area it covers) and centre pressure."""
    n = len(pressure)
    return ContactSolution(
        force=float(pressure.sum() * spacing**2),
        contact_radius=float(np.sqrt((pressure > 0).sum() * spacing**2 / np.pi)),
        peak_pressure=float(pressure[n // 2, n // 2]),
    )  # fmt: skip


def _over(law: ContactSolution, ref: ContactSolution) -> dict[str, float]:
    return {"force": law.force / ref.force,
            "contact_radius": law.contact_radius / ref.contact_radius,
            "peak_pressure": law.peak_pressure / ref.peak_pressure}  # fmt: skip


def held_out(modulus: float, spacing: float = 1e-4) -> list[dict[str, Any]]:
    """The layer law and the Winkler law against the FE on geometries not looked at before."""
    out = []
    for radius, h in ((0.004, 0.001), (0.004, 0.003), (0.015, 0.001), (0.015, 0.003)):
        for nu in (0.45, 0.49):
            for delta in (0.1 * h, 0.4 * h):
                p = layer_pressure(sphere_depth(radius, delta, spacing), spacing, modulus, nu, h)
                fe = fem_layer_press(modulus, nu, h, radius, delta, 48)
                w = winkler_sphere(SkinModel(modulus, h), radius, delta)
                out.append({
                    "indenter": f"sphere, R = {radius * 1e3:g} mm", "thickness_mm": h * 1e3,
                    "poisson": nu, "indentation_mm": delta * 1e3,
                    "layer_over_fe": _over(_measures(p, spacing), fe),
                    "winkler_over_fe": {"force": w.force / fe.force},
                })  # fmt: skip
    for punch, h in ((0.0015, 0.002), (0.003, 0.001)):
        for nu in (0.45, 0.49):
            delta = 0.1 * h
            r = grid_radii(1.5 * punch, spacing)
            p = layer_pressure(np.where(r <= punch, delta, -1.0), spacing, modulus, nu, h)
            fe = fem_punch_press(modulus, nu, h, punch, delta, 48)
            law = _measures(p, spacing)
            out.append({
                "indenter": f"flat punch, a = {punch * 1e3:g} mm", "thickness_mm": h * 1e3,
                "poisson": nu, "indentation_mm": delta * 1e3,
                "layer_over_fe": {"force": law.force / fe.force,
                                  "centre_pressure": law.peak_pressure / fe.peak_pressure},
                "winkler_over_fe": {"force": modulus / h * delta * np.pi * punch**2 / fe.force},
            })  # fmt: skip
    return out


def cylinders(modulus: float, spacing: float = 1e-4) -> dict[str, Any]:
    """A long cylinder (line contact): the plane-strain FE against Hertz's line contact (thick
    layers) and the Winkler law (thin, Poisson's ratio 0); the layer law (the centre row of a
    cylinder 12 thicknesses long each way) and the Winkler law against the FE."""
    radius = FINGERTIP_RADIUS
    checks = []
    for h, nu, delta in ((0.05, 0.3, 2e-4), (0.2, 0.3, 2e-4), (0.2, 0.45, 2e-4)):
        fe = fem_layer_line_press(modulus, nu, h, radius, delta, 48)
        ref = hertz_cylinder(modulus, nu, radius, fe.force)
        checks.append({"reference": "hertz", "thickness_mm": h * 1e3, "poisson": nu,
                       "half_width": fe.contact_radius / ref.contact_radius,
                       "peak_pressure": fe.peak_pressure / ref.peak_pressure})  # fmt: skip
    for h in (0.001, 0.002):
        fe = fem_layer_line_press(modulus, 0.0, h, radius, 5e-4, 48)
        ref = winkler_cylinder(SkinModel(modulus, h), radius, 5e-4)
        checks.append({"reference": "winkler", "thickness_mm": h * 1e3, "poisson": 0.0,
                       "force": fe.force / ref.force,
                       "peak_pressure": fe.peak_pressure / ref.peak_pressure})  # fmt: skip
    rows = []
    for h in (0.001, 0.002, 0.003):
        for nu in (0.0, 0.45, 0.49):
            for share in (0.1, 0.25, 0.5):
                delta = share * h
                fe = fem_layer_line_press(modulus, nu, h, radius, delta, 48)
                p = layer_pressure(cylinder_depth(radius, delta, spacing, 12.0 * h), spacing,
                                   modulus, nu, h)  # fmt: skip
                centre = p[len(p) // 2]
                law = ContactSolution(force=float(centre.sum() * spacing),
                                      contact_radius=float((centre > 0).sum() * spacing / 2.0),
                                      peak_pressure=float(centre.max()))  # fmt: skip
                w = winkler_cylinder(SkinModel(modulus, h), radius, delta)
                rows.append({"thickness_mm": h * 1e3, "poisson": nu,
                             "indentation_mm": delta * 1e3, "fe_force_n_per_m": fe.force,
                             "layer_over_fe": {"force": law.force / fe.force,
                                               "half_width": law.contact_radius
                                               / fe.contact_radius,
                                               "peak_pressure": law.peak_pressure
                                               / fe.peak_pressure},
                             "winkler_over_fe": {"force": w.force / fe.force,
                                                 "half_width": w.contact_radius
                                                 / fe.contact_radius,
                                                 "peak_pressure": w.peak_pressure
                                                 / fe.peak_pressure}})  # fmt: skip
    return {"radius_mm": radius * 1e3, "grid_mm": spacing * 1e3, "checks": checks, "rows": rows}


def boussinesq(modulus: float) -> list[dict[str, Any]]:
    """The FE flat punch on a layer 60 punch radii thick against Boussinesq's half-space."""
    out = []
    for res in (24, 48):
        ref = punch_half_space(modulus, 0.3, 1e-3, 1e-5)
        fe = fem_punch_press(modulus, 0.3, 0.06, 1e-3, 1e-5, res)
        out.append({"resolution": res, "force": fe.force / ref.force,
                    "centre_pressure": fe.peak_pressure / ref.peak_pressure})  # fmt: skip
    return out


def figure(path: str, resolution: int = 48) -> None:
    """Pressure profiles at 0.5 mm: the skin's law against the FE pad for each Poisson ratio."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    skin = load_skin("vision").skin
    delta, radius = 5e-4, FINGERTIP_RADIUS
    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=110)
    r = np.linspace(0.0, 1.3 * np.sqrt(2 * radius * delta), 200)
    winkler = skin.modulus / skin.thickness * np.maximum(delta - r**2 / (2 * radius), 0.0)
    ax.plot(r * 1e3, winkler / 1e3, "k--", label="skin (Winkler, p = E d / h)")
    for nu in POISSON:
        fe = fem_pad_press(skin.modulus, nu, radius, skin.thickness, delta, resolution)
        ax.plot(fe.radii * 1e3, fe.pressure / 1e3, label=f"elastic pad, FE, nu = {nu}")
    ax.set_xlabel("distance from the centre of the contact [mm]")
    ax.set_ylabel("pressure [kPa]")
    ax.set_title("Fingertip pad (8 mm, 2 mm layer, E = 0.2 MPa) pressed 0.5 mm onto a flat",
                 fontsize=9)  # fmt: skip
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=None)
    parser.add_argument("--figure", default=None)
    parser.add_argument("--resolution", type=int, default=48)
    args = parser.parse_args()
    start = time.perf_counter()
    result = table(args.resolution)
    result["seconds"] = time.perf_counter() - start
    text = json.dumps(result, indent=1)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    if args.figure:
        figure(args.figure, args.resolution)
    print(text)


if __name__ == "__main__":
    main()
