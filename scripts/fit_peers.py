"""nH against a peer fitter from the registry, same contacts, same process (issue 37 item 3):
the median fit time and the mean epsilon of each.

    pip install sage-superquadric        # the peer (Apache-2.0), not a hapticsim dependency
    python scripts/fit_peers.py --out docs/fast-loop/peers/peers.json

The peer: ``sage_superquadrics.superquadric.fit_superquadric`` (PyPI ``sage-superquadric``
1.0): SciPy's trust-region least squares (``soft_l1`` loss) of the radial residual from an
axis-aligned bounding-box start, points only (it takes no normals). Each case is fitted by both
methods in turn (the order alternates), timed in CPU seconds of this process, and scored by
``hapticsim.score`` (the peer's fit as a hapticsim ``Superquadric``: its Euler angles ``zyx``
(yaw, pitch, roll) make the rotation whose columns are the body axes, as ours).

Cases (``--families``; each at a random pose, 150 contacts, sigma_N in 0, 0.02, 0.05, 0.1; the
data seed is the case seed + 7919, the fit seed the case seed):

- ``paper``: the paper's four bodies, the paper's pattern (``paper_dataset``), 3 poses each;
- ``random``: 12 random tapered superquadrics, the paper's pattern;
- ``ring``: 8 random tapered superquadrics, contacts area-uniform over the whole surface
  (``sample_surface``), a pattern neither fitter was tuned on.

``--methods`` takes ``sage``, any hapticsim method and ``METHOD@BUDGET`` (that method at another
evaluation budget: what nH's accuracy costs at the peer's speed).

Prints JSON (and writes it with --out, a manifest.json beside it): per method the median CPU
and wall seconds and the mean epsilon per family and noise level, and the ratio of the medians.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_sys.path.insert(0, str(_Path(__file__).resolve().parents[1]))

import argparse
import json
import os
import sys
import time
from typing import Any

# One BLAS thread, set before numpy loads BLAS: the peer's package asks for it, and a second
# thread spinning beside a fit would double both methods' CPU seconds (its setdefault in main()
# came after numpy's import and did nothing, unless the shell had set it).
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402 - after the thread setting

NOISES = (0.0, 0.02, 0.05, 0.1)
FAMILIES = ("paper", "random", "ring")


def cases(families: tuple[str, ...]) -> list[tuple[str, int, float]]:
    """(family, seed, noise) of every case."""
    out = []
    for noise in NOISES:
        if "paper" in families:
            out += [("paper", s, noise) for s in range(800, 812)]
        if "random" in families:
            out += [("random", s, noise) for s in range(8100, 8112)]
        if "ring" in families:
            out += [("ring", s, noise) for s in range(8200, 8208)]
    return out


def contacts(family: str, seed: int, noise: float) -> tuple[Any, np.ndarray, np.ndarray]:
    """The truth and its noisy contacts (150, 3) points [m] and normals."""
    from hapticsim.data.bodies import BODY_NAMES, get_body
    from hapticsim.data.noise import add_noise
    from hapticsim.data.objects import random_superquadric
    from hapticsim.data.synthetic import paper_dataset
    from hapticsim.geometry import random_rotation

    rng = np.random.default_rng(seed)
    if family == "paper":
        body = get_body(BODY_NAMES[seed % 4])
    else:
        body = random_superquadric(rng, tapered=True)
    truth = body.transformed(random_rotation(rng), rng.normal(0.0, 0.1, size=3))
    if family == "ring":
        gen = np.random.default_rng(seed + 7919)
        points, normals = truth.sample_surface(150, gen)
        points, normals = add_noise(points, normals, noise, float(np.mean(truth.a)), gen)
        return truth, points, normals
    data = paper_dataset(truth, noise=noise, rng=seed + 7919, count=150)
    return truth, data.points, data.normals


def sage_fit(points: np.ndarray) -> Any:
    """The peer's fit of `points` as a hapticsim Superquadric."""
    from scipy.spatial.transform import Rotation
    from sage_superquadrics.superquadric import fit_superquadric

    from hapticsim.geometry import Superquadric

    p, _ = fit_superquadric(points)
    rot = Rotation.from_euler("zyx", [p["yaw"], p["pitch"], p["roll"]]).as_matrix()
    eps = np.clip([p["eps1"], p["eps2"]], 0.1, 2.0)
    return Superquadric(a=[p["a1"], p["a2"], p["a3"]], eps=eps, rotation=rot,
                        center=[p["cx"], p["cy"], p["cz"]])  # fmt: skip


def run(families: tuple[str, ...], methods: tuple[str, ...]) -> dict[str, Any]:
    from hapticsim import score
    from hapticsim.fitting import fit

    rows = []
    all_cases = cases(families)
    for k, (family, seed, noise) in enumerate(all_cases):
        truth, points, normals = contacts(family, seed, noise)
        row: dict[str, Any] = {"family": family, "seed": seed, "noise": noise}
        order = methods if k % 2 == 0 else methods[::-1]
        for method in order:
            t, c = time.perf_counter(), time.process_time()
            if method == "sage":
                estimate = sage_fit(points)
            else:  # "nH" or "nH@BUDGET"
                name, _, budget = method.partition("@")
                estimate = fit(points, normals, method=name, rng=seed,
                               budget=int(budget) if budget else None).solid  # fmt: skip
            row[method] = {"cpu": time.process_time() - c, "wall": time.perf_counter() - t,
                           "epsilon": score(estimate, truth, rng=0).epsilon}  # fmt: skip
        rows.append(row)
        if (k + 1) % 20 == 0:
            print(f"fit_peers: {k + 1}/{len(all_cases)}", file=sys.stderr)
    summary: dict[str, Any] = {}
    for method in methods:
        cpu = [r[method]["cpu"] for r in rows]
        summary[method] = {
            "median_cpu_s": float(np.median(cpu)),
            "median_wall_s": float(np.median([r[method]["wall"] for r in rows])),
            "mean_epsilon": float(np.mean([r[method]["epsilon"] for r in rows])),
            "epsilon": {f"{fam}/{n:g}": float(np.mean([r[method]["epsilon"] for r in rows
                                                       if r["family"] == fam and r["noise"] == n]))
                        for fam in families for n in NOISES},
        }  # fmt: skip
    if "sage" in methods:
        for method in methods:
            if method != "sage":
                summary[method]["median_cpu_over_sage"] = (
                    summary[method]["median_cpu_s"] / summary["sage"]["median_cpu_s"]
                )
    return {"cases": len(rows), "load_average": os.getloadavg()[0], "summary": summary,
            "rows": rows}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--families", nargs="+", default=list(FAMILIES), choices=FAMILIES)
    parser.add_argument("--methods", nargs="+", default=["nH", "sage"])
    parser.add_argument("--out", default=None, help="results JSON (a manifest.json beside it)")
    args = parser.parse_args()
    start = time.perf_counter()
    from hapticsim.data.bodies import get_body
    from hapticsim.data.synthetic import paper_dataset
    from hapticsim.fitting import fit

    warm = paper_dataset(get_body("cube"), noise=0.02, rng=0, count=150)
    for method in args.methods:  # compiled kernels and imports first, untimed
        if method != "sage":
            fit(warm.points, warm.normals, method=method.partition("@")[0], rng=0)
    if "sage" in args.methods:
        sage_fit(warm.points)
    result = run(tuple(args.families), tuple(args.methods))
    result["seconds"] = time.perf_counter() - start
    text = json.dumps(result, indent=1)
    if args.out:
        from hapticsim._files import write_text_atomic
        from hapticsim.suites.provenance import manifest

        write_text_atomic(args.out, text + "\n")
        command = ["python", "scripts/fit_peers.py", *sys.argv[1:]]
        m = manifest(command)
        try:
            from importlib.metadata import version

            m["packages"]["sage-superquadric"] = version("sage-superquadric")
        except Exception:  # noqa: BLE001 - the peer's version where it is installed
            pass
        write_text_atomic(str(_Path(args.out).parent / "manifest.json"),
                          json.dumps(m, indent=2) + "\n")  # fmt: skip
    print(json.dumps({k: v for k, v in result.items() if k != "rows"}, indent=1))


if __name__ == "__main__":
    main()
