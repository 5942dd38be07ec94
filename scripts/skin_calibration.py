"""A skin preset calibrated against a published sensor's force-indentation curve (issue 38,
item 3): docs/tactile/calibration/README.md.

    python scripts/skin_calibration.py --out docs/tactile/calibration/calibration.json

The sensor: the GelSight Mini (GelSight Inc.), as characterised by Helmut, Dziarski, Funk,
Belousov and Peters, "Learning Force Distribution Estimation for the GelSight Mini Optical
Tactile Sensor Based on Finite Element Analysis" (arXiv 2411.03315; code at
github.com/feats-ai/feats). Their identification of the gel's material
(``src/calculix/src/hyperelasticity_identification``) fits a finite-element model of the gel to
the normal force measured at four indentations of a rigid sphere 15 mm across
(``mechanics.GELSIGHT_MINI_PRESSES``);
their FE model's gel is a layer 4 mm thick at the centre, bonded to the rigid base (its mesh:
z from -4 mm to 0), and the material they identified is an incompressible neo-Hookean solid of
C10 = 0.0725 MPa, i.e. a shear modulus of 0.145 MPa and E = 0.435 MPa. Only those numbers are
used here; none of their code.

What this script does with them: for each Poisson's ratio of :data:`POISSON`, the finite-element
press of a flat 4 mm layer (``fem_layer_press``, linear elasticity) by the same sphere gives the
force per unit modulus at the four indentations, and the modulus that minimises the largest
relative error over them (the geometric mean of the smallest and largest ratio of measured to
computed force); the ratio with the smallest largest error is the preset's. A check held out
from the choice: (E, nu) fitted on two of the four indentations predict the other two. Then the
preset's skin itself (``SkinModel`` with that layer: the layer law on a grid of 0.05 thicknesses,
the force law MuJoCo's contact follows) pressed by the sphere, and the Winkler law and Hertz's
half-space of the same modulus beside it; and the shipped preset (its modulus rounded) the same
way. Prints JSON (and writes it with --out, a manifest.json
beside it).
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import os
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from hapticsim.perception.tactile.mechanics import (
    GELSIGHT_MINI_PRESSES as MEASURED,
    GELSIGHT_MINI_SPHERE_RADIUS as RADIUS,
    fem_layer_press,
    hertz_sphere,
)
from hapticsim.perception.tactile.presets import load_skin
from hapticsim.perception.tactile.skin import SkinModel

#: The gel's thickness [m] in the cited identification's FE model.
THICKNESS: float = 4e-3
#: The incompressible neo-Hookean solid the cited work identified: E = 6 C10 [Pa].
CITED_MODULUS: float = 6.0 * 0.0725e6
#: Poisson's ratios searched.
POISSON: tuple[float, ...] = (0.3, 0.35, 0.4, 0.42, 0.43, 0.44, 0.45, 0.46, 0.47, 0.48, 0.49)


def unit_forces(poisson: float) -> dict[float, float]:
    """The FE force [N] per pascal of modulus at each measured indentation."""
    scale = 1e6
    return {d: fem_layer_press(scale, poisson, THICKNESS, RADIUS, d).force / scale
            for d in MEASURED}  # fmt: skip


def minimax_modulus(unit: dict[float, float], points: tuple[float, ...]) -> float:
    """The modulus [Pa] that minimises the largest relative error at `points`."""
    ratios = [MEASURED[d] / unit[d] for d in points]
    return math.sqrt(min(ratios) * max(ratios))


def errors(forces: dict[float, float]) -> dict[str, float]:
    """Relative error of forces [N] (per indentation, keyed in mm) against the measured."""
    return {f"{d * 1e3:g}": forces[d] / MEASURED[d] - 1.0 for d in MEASURED}


def table() -> dict[str, Any]:
    rows = []
    units = {}
    for nu in POISSON:
        units[nu] = unit = unit_forces(nu)
        modulus = minimax_modulus(unit, tuple(MEASURED))
        err = errors({d: modulus * unit[d] for d in MEASURED})
        rows.append({"poisson": nu, "modulus": modulus, "errors": err,
                     "max_error": max(abs(v) for v in err.values())})  # fmt: skip
        sys.stderr.write(
            f"nu {nu}: E {modulus:.0f} Pa, largest error {rows[-1]['max_error']:.3f}\n"
        )
    chosen = min(rows, key=lambda r: r["max_error"])
    nu, modulus = chosen["poisson"], chosen["modulus"]

    held_out = []  # fit (E, nu) on two indentations, predict the other two
    for pair in itertools.combinations(MEASURED, 2):
        fits = [(max(abs(modulus_ * units[p][d] / MEASURED[d] - 1) for d in pair), p, modulus_)
                for p in POISSON for modulus_ in [minimax_modulus(units[p], pair)]]  # fmt: skip
        _, p, e = min(fits)
        rest = [d for d in MEASURED if d not in pair]
        held_out.append({
            "fitted_on_mm": [d * 1e3 for d in pair], "poisson": p, "modulus": e,
            "predicted": {f"{d * 1e3:g}": e * units[p][d] / MEASURED[d] - 1.0 for d in rest},
        })  # fmt: skip

    skin = SkinModel(modulus=modulus, thickness=THICKNESS, poisson=nu)
    winkler = SkinModel(modulus=modulus, thickness=THICKNESS)
    law = {d: skin.sphere_force(RADIUS, d) for d in MEASURED}
    presses = {
        f"{d * 1e3:g}": {
            "measured": MEASURED[d],
            "fe": modulus * units[nu][d],
            "skin": law[d],
            "winkler": winkler.sphere_force(RADIUS, d),
            "hertz": hertz_sphere(modulus, nu, RADIUS, d).force,
        }
        for d in MEASURED
    }
    shipped = load_skin("gelsight_mini").skin  # the preset file, its modulus rounded
    shipped_law = {d: shipped.sphere_force(RADIUS, d) for d in MEASURED}
    cited = units[0.49]  # the cited modulus (incompressible), nearest ratio the FE takes
    return {
        "sensor": "GelSight Mini",
        "source": "Helmut et al., arXiv 2411.03315; github.com/feats-ai/feats, "
                  "src/calculix/src/hyperelasticity_identification",
        "sphere_radius_m": RADIUS, "thickness_m": THICKNESS,
        "measured_N": {f"{d * 1e3:g}": f for d, f in MEASURED.items()},
        "search": rows,
        "preset": {"modulus": modulus, "poisson": nu, "thickness": THICKNESS,
                   "fe_errors": chosen["errors"], "skin_errors": errors(law)},
        "shipped_preset": {"modulus": shipped.modulus, "poisson": shipped.poisson,
                           "thickness": shipped.thickness,
                           "skin_errors": errors(shipped_law)},
        "held_out": held_out,
        "presses": presses,
        "cited_modulus": {"modulus": CITED_MODULUS,
                          "fe_errors_at_0.49": errors({d: CITED_MODULUS * cited[d]
                                                              for d in MEASURED})},
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=None, help="results JSON (a manifest.json beside it)")
    args = parser.parse_args()
    start = time.perf_counter()
    result = table()
    result["seconds"] = time.perf_counter() - start
    text = json.dumps(result, indent=1)
    if args.out:
        from hapticsim._files import write_text_atomic
        from hapticsim.suites.provenance import manifest

        write_text_atomic(args.out, text + "\n")
        command = ["python", "scripts/skin_calibration.py", "--out", args.out]
        write_text_atomic(str(Path(args.out).parent / "manifest.json"),
                          json.dumps(manifest(command), indent=2) + "\n")  # fmt: skip
    print(text)


if __name__ == "__main__":
    main()
