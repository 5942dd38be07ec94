"""The skin's traction field against the thin layer's closed form and MuJoCo's friction, in
explorations, and what it costs (docs/tactile/traction).

    python scripts/skin_traction.py --out docs/tactile/traction/traction.json \\
        --figure docs/tactile/traction/traction.png

Parts (about 90 s on 2 cores):

- ``thin_layer``: a sphere of the built-in fingertip's radius pressed 0.5 mm into the ideal
  skin (a 0.05 mm grid, Winkler pressure) and loaded tangentially by Q = share x mu N: the stick
  region's radius against ``(1 - share)^(1/4)``, and the load the field carries; the same on the
  built-in 31 x 31 pad;
- ``strokes``: a fingertip pressed by N onto a face and pushed by a slowly rising tangential
  force (``tests/sim/test_traction.py``'s stroke): the load at which it slides (1 mm/s) and at
  which every taxel of its pad slips, over mu and N, with and without MuJoCo's no-slip passes;
- ``explorations``: the paper's bodies, paper strategy, 150 contacts, ideal skin: how the
  recorded touches stick and slip, and Coulomb's bound over every taxel;
- ``speed``: environment steps per CPU second, exact sensing (``HapticExplore-v0``) against the
  traction field (``HapticExploreTactile-v1``), both backends, interleaved;
  ``explore_seconds``: a tactile exploration's CPU time with and without the no-slip passes
  (separate processes).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from hapticsim.constants import FINGERTIP_RADIUS  # noqa: E402
from hapticsim.perception.tactile import (  # noqa: E402
    PadLayout,
    load_skin,
    taxel_depths,
    traction_field,
    winkler_stick_radius,
)
from hapticsim.perception.tactile.mechanics import grid_radii, sphere_depth  # noqa: E402
from hapticsim.perception.tactile.traction import (  # noqa: E402
    TAXEL_SLIP,
    TAXEL_STICK,
    contact_share,
)

SHARES = (0.0, 0.2, 0.4, 0.6, 0.8, 0.9, 0.95, 0.99)
MU = 0.3
INDENT = 5e-4
SPACING = 5e-5
BODIES = ("tapered_box", "cube", "cylinder", "ellipsoid")


def thin_layer() -> dict[str, Any]:
    """Stick radius and carried load of a sphere in the ideal skin (module docstring)."""
    skin = load_skin("ideal").skin
    depth = sphere_depth(FINGERTIP_RADIUS, INDENT, SPACING)
    r = grid_radii(1.3 * np.sqrt(2.0 * FINGERTIP_RADIUS * INDENT), SPACING)
    pressure = skin.pressure(depth)
    a = float(np.sqrt(np.sum(pressure > 0) / np.pi) * SPACING)
    fine = []
    for share in SHARES:
        field, state = traction_field(pressure, np.array([share, 0.0]), MU)
        stick = state == TAXEL_STICK
        radius = float(r[stick].max()) if stick.any() else 0.0
        area_radius = float(np.sqrt(stick.sum() / np.pi) * SPACING)
        carried, slipping = contact_share(field, state, MU)
        fine.append({"share": share, "stick_radius_over_a": area_radius / a,
                     "stick_outer_over_a": radius / a,
                     "closed_form": winkler_stick_radius(share), "carried": carried,
                     "slipping": slipping})  # fmt: skip
    layout = PadLayout(31, 31, 0.001, FINGERTIP_RADIUS, [0, 0, -1], [0, 1, 0], [0, 0, 0])
    pos, nrm, area = layout.taxels
    from hapticsim.geometry import Superquadric

    face = Superquadric([0.3] * 3, [0.1, 0.1], center=[0, 0, -0.3])
    centre = np.array([0.0, 0.0, FINGERTIP_RADIUS - INDENT])
    pad_pressure = skin.pressure(taxel_depths(face, pos + centre, nrm, FINGERTIP_RADIUS))
    coarse = []
    for share in SHARES:
        field, state = traction_field(pad_pressure, np.array([share, 0.0]), MU, area)
        carried, slipping = contact_share(field, state, MU, area)
        coarse.append({"share": share, "carried": carried, "slipping": slipping,
                       "stick_taxels": int(np.sum(state == TAXEL_STICK)),
                       "contact_taxels": int(np.sum(state > 0))})  # fmt: skip
    return {"indentation_m": INDENT, "friction": MU, "contact_radius_m": a,
            "fine_grid_m": SPACING, "fine": fine, "built_in_pad": coarse}  # fmt: skip


def strokes() -> list[dict[str, Any]]:
    """Slide and slip onsets of pushed fingertips (module docstring)."""
    from hapticsim.sim.scene import NOSLIP_ITERATIONS
    from tests.sim.test_traction import stroke

    out = []
    for noslip in (NOSLIP_ITERATIONS, 0):
        for mu in (0.2, 0.3, 0.5):
            for normal in (0.3, 0.5, 1.0):
                rows = stroke(mu, normal, noslip)
                ratio = np.array([x[0] for x in rows])
                speed = np.array([x[1] for x in rows])
                slipping = np.array([np.mean(x[3][x[3] > 0] == TAXEL_SLIP) if (x[3] > 0).any()
                                     else 1.0 for x in rows])  # fmt: skip
                worst = max(float(np.max(np.hypot(x[2][..., 1], x[2][..., 2])[x[2][..., 0] > 0]
                                         / (mu * x[2][..., 0][x[2][..., 0] > 0])))
                            for x in rows if (x[2][..., 0] > 0).any())  # fmt: skip
                out.append({"noslip_iterations": noslip, "friction": mu, "normal_N": normal,
                            "slides_at": float(ratio[np.argmax(speed > 1e-3)]),
                            "all_slip_at": float(ratio[np.argmax(slipping == 1.0)]),
                            "half_load_slipping": float(slipping[np.argmax(ratio >= 0.5)]),
                            "traction_over_bound_max": worst})  # fmt: skip
                print(f"stroke noslip {noslip} mu {mu} N {normal}: {out[-1]}", file=sys.stderr)
    return out


def explorations() -> list[dict[str, Any]]:
    """How recorded touches stick and slip on the paper's bodies (module docstring)."""
    from hapticsim.data import get_body
    from hapticsim.sim.scene import SceneConfig
    from hapticsim.sim.session import run_exploration

    out = []
    for body in BODIES:
        run = run_exploration(get_body(body), "paper", 150, 0,
                              scene_config=SceneConfig(sensing="tactile"))  # fmt: skip
        t, finger = run.tactile, run.arrays["finger"]
        n = len(finger)
        state = t["taxel_state"][np.arange(n), finger].reshape(n, -1)
        field = t["traction"].reshape(-1, 3).astype(np.float64)
        touching = (state > 0).sum(axis=1)
        share = (state == TAXEL_SLIP).sum(axis=1) / np.maximum(touching, 1)
        lit = field[:, 0] > 0
        bound = np.hypot(field[lit, 1], field[lit, 2]) / (0.2 * field[lit, 0])
        kinds = run.explorer.recorder.pattern_kinds
        stroke = np.array([kinds[p] == "stripe" for p in run.arrays["pattern"]])
        out.append({"body": body, "touches": n,
                    "all_stick": int(np.sum(share == 0)), "partial": int(np.sum((share > 0)
                                                                                & (share < 1))),
                    "all_slip": int(np.sum(share == 1)),
                    "slipping_median_probe": float(np.median(share[~stroke])) if (~stroke).any()
                    else None,
                    "slipping_median_stroke": float(np.median(share[stroke])) if stroke.any()
                    else None,
                    "traction_over_bound_max": float(bound.max())})  # fmt: skip
        print(f"explore {body}: {out[-1]}", file=sys.stderr)
    return out


def _steps(env_id: str, backend: str, seed: int, touches: int = 15) -> float:
    from tactile_servo import env_rate

    steps, cpu = env_rate(env_id, seed, touches, backend=backend)
    return steps / cpu


def speed(repeats: int = 3) -> dict[str, Any]:
    """Steps per CPU second, exact against traction field (module docstring)."""
    out: dict[str, Any] = {}
    for backend in ("analytic", "mujoco"):
        rates: dict[str, list[float]] = {"exact": [], "traction": []}
        for k in range(repeats):
            rates["exact"].append(_steps("hapticsim/HapticExplore-v0", backend, k))
            rates["traction"].append(_steps("hapticsim/HapticExploreTactile-v1", backend, k))
        med = {key: float(np.median(v)) for key, v in rates.items()}
        out[backend] = {"steps_per_cpu_second": med, "runs": rates,
                        "traction_over_exact": med["traction"] / med["exact"]}  # fmt: skip
        print(f"speed {backend}: {out[backend]}", file=sys.stderr)
    return out


def explore_seconds(noslip: int) -> float:
    """CPU seconds of the four bodies' tactile explorations with `noslip` passes (run in its
    own process: the constant is read when a scene is built)."""
    import hapticsim.sim.scene as scene_module

    scene_module.NOSLIP_ITERATIONS = noslip
    from hapticsim.data import get_body
    from hapticsim.sim.scene import SceneConfig
    from hapticsim.sim.session import run_exploration

    start = time.process_time()
    for body in BODIES:
        run_exploration(get_body(body), "paper", 150, 0,
                        scene_config=SceneConfig(sensing="tactile"))  # fmt: skip
    return time.process_time() - start


def noslip_cost(repeats: int = 3) -> dict[str, Any]:
    """Four tactile explorations' CPU seconds with and without no-slip passes, interleaved."""
    runs: dict[str, list[float]] = {"noslip_5": [], "noslip_0": []}
    for _ in range(repeats):
        for n in (5, 0):
            res = subprocess.run([sys.executable, __file__, "--explore-seconds", str(n)],
                                 capture_output=True, text=True, check=True)  # fmt: skip
            runs[f"noslip_{n}"].append(float(res.stdout.strip()))
    med = {k: float(np.median(v)) for k, v in runs.items()}
    return {"cpu_seconds_median": med, "runs": runs, "ratio": med["noslip_5"] / med["noslip_0"]}


def figure(path: str) -> None:
    """Stick and slip on the fine grid at four loads, and the stick radius against the closed
    form."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    skin = load_skin("ideal").skin
    pressure = skin.pressure(sphere_depth(FINGERTIP_RADIUS, INDENT, SPACING))
    half = pressure.shape[0] * SPACING / 2 * 1e3
    cmap = ListedColormap(["#28282f", "#3c82dc", "#f08c28"])
    fig, axes = plt.subplots(1, 5, figsize=(15, 3.2))
    for ax, share in zip(axes[:4], (0.0, 0.5, 0.9, 1.0), strict=True):
        field, state = traction_field(pressure, np.array([share, 0.0]), MU)
        ax.imshow(state, cmap=cmap, vmin=0, vmax=2, extent=[-half, half, -half, half])
        ax.set_title(f"Q = {share:g} mu N")
        ax.set_xlabel("mm")
    axes[0].set_ylabel("blue stick, orange slip")
    s = np.linspace(0, 1, 101)
    ax = axes[4]
    ax.plot(s, [winkler_stick_radius(x) for x in s], "k-", label="thin layer (1 - s)^(1/4)")
    ax.plot(s, (1 - s) ** (1 / 3), "k:", label="half-space (1 - s)^(1/3)")
    fine = thin_layer()["fine"]
    ax.plot([f["share"] for f in fine], [f["stick_radius_over_a"] for f in fine], "o",
            color="#3c82dc", label="skin field (0.05 mm grid)")  # fmt: skip
    ax.set_xlabel("Q / (mu N)")
    ax.set_ylabel("stick radius / contact radius")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=None)
    parser.add_argument("--figure", default=None)
    parser.add_argument("--explore-seconds", type=int, default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.explore_seconds is not None:
        print(explore_seconds(args.explore_seconds))
        return
    start = time.perf_counter()
    result = {"thin_layer": thin_layer(), "strokes": strokes(),
              "explorations": explorations(), "speed": speed(),
              "explore_seconds": noslip_cost()}  # fmt: skip
    result["seconds"] = time.perf_counter() - start
    text = json.dumps(result, indent=1)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(text + "\n")
    if args.figure:
        figure(args.figure)
    print(text)


if __name__ == "__main__":
    main()
