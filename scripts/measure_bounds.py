"""Measure what the quality thresholds of the tests stand on, and print it as JSON.

    python scripts/measure_bounds.py [--section fit|regression|explore|env|all] [--seeds 10]

The binding tests (issue 14 item 5) write these figures beside their limits; rerun this after
a change of the fitter, the simulation or the environment and update both. For each case it
prints the quantity the test bounds for the method the test runs, over several fit seeds
(min, median, max), and what weaker variants score on the same data (nLS from the paper's
initial estimate, nH at a budget of 300, the initial estimate itself, the oracle: nLS started
from the truth), so that the margin on both sides is visible.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
os.environ.setdefault("MUJOCO_GL", "egl")

from hapticsim.data.bodies import get_body  # noqa: E402
from hapticsim.data.synthetic import paper_dataset  # noqa: E402
from hapticsim.fitting import fit  # noqa: E402
from hapticsim.fitting.initial import paper_initial  # noqa: E402
from hapticsim.geometry import rotvec_to_matrix  # noqa: E402
from hapticsim.metrics import volume_overlap  # noqa: E402
from tests.fitting.conftest import posed  # noqa: E402


def epsilon(estimate, truth) -> float:
    """alpha + beta with the tests' scorer (20 000 Monte Carlo samples, seed 0)."""
    overlap = volume_overlap(estimate, truth, samples=20_000, rng=0)
    return round(float(overlap.alpha + overlap.beta), 4)


def spread(values: list[float]) -> dict[str, float]:
    return {"min": min(values), "median": float(np.median(values)), "max": max(values)}


def variants(points, normals, truth, seeds: int, method: str = "nH") -> dict[str, object]:
    """`method` over fit seeds, and the weaker variants, on one data set."""
    with_normals = method.startswith("n")
    nrm = normals if with_normals else None
    main = [epsilon(fit(points, nrm, method=method, rng=s).superquadric, truth)
            for s in range(seeds)]  # fmt: skip
    low = [epsilon(fit(points, nrm, method=method, budget=300, rng=s).superquadric, truth)
           for s in range(seeds)]  # fmt: skip
    local = "nLS" if with_normals else "LS"
    return {
        method: spread(main),
        f"{method}_seed0": main[0],
        f"{method}_budget300": spread(low),
        local: epsilon(fit(points, nrm, method=local).superquadric, truth),
        "initial_estimate": epsilon(paper_initial(points), truth),
        "oracle": epsilon(fit(points, nrm, method=local, initial=truth).superquadric, truth),
    }


def section_fit(seeds: int) -> dict[str, object]:
    """tests/fitting/test_fit.py."""
    out: dict[str, object] = {}
    truth = posed(get_body("cube"), 0)
    data = paper_dataset(truth, noise=0.1, rng=0)
    out["noisy_cube"] = variants(data.points, data.normals, truth, seeds)
    truth = posed(get_body("cube"), 3)
    data = paper_dataset(truth, noise=0.02, rng=3)
    turn = rotvec_to_matrix(np.radians(8.0) * np.array([0.0, 0.6, 0.8]))
    warm = truth.replace(a=truth.a * 1.25, rotation=turn @ truth.rotation,
                         center=truth.center + 0.004)  # fmt: skip
    refined = fit(data.points, data.normals, method="nLS", initial=warm, budget=2000)
    out["warm_start"] = {
        "warm_start": epsilon(warm, truth),
        "nLS_from_warm": epsilon(refined.superquadric, truth),
        "evaluations": refined.evaluations,
        "status": refined.status,
        "nLS_from_paper_initial": epsilon(
            fit(data.points, data.normals, method="nLS", budget=2000).superquadric, truth
        ),
    }
    return out


def section_regression(seeds: int) -> dict[str, object]:
    """tests/fitting/test_regression.py."""
    from tests.fitting.test_regression import NOISY, ONE_SIDED

    out: dict[str, object] = {"paper_noise": {}, "one_sided": {}}
    for name in NOISY:
        truth = posed(get_body(name), 0)
        data = paper_dataset(truth, noise=0.1, rng=0)
        out["paper_noise"][name] = variants(data.points, data.normals, truth, seeds)
    for (name, seed, patterns), limit in ONE_SIDED.items():
        truth = posed(get_body(name), seed)
        data = paper_dataset(truth, noise=0.0, rng=seed)
        keep = np.isin(data.extra["pattern"], patterns)
        row = variants(data.points[keep], data.normals[keep], truth, seeds)
        row["contacts"], row["limit"] = int(keep.sum()), limit
        out["one_sided"][f"{name}/seed{seed}/patterns{list(patterns)}"] = row
    return out


def section_explore(seeds: int) -> dict[str, object]:
    """tests/sim/test_explore.py (default-run cases)."""
    import tempfile

    from hapticsim.exploration import explore
    from tests.sim.test_explore import DEFAULT_RUNS

    out: dict[str, object] = {}
    for (body, strategy, count), _limits in DEFAULT_RUNS.items():
        rows = []
        for seed in range(min(seeds, 3)):
            with tempfile.TemporaryDirectory() as tmp:
                s = explore(body, strategy, noise=0.0, method="nH", seed=seed, out_dir=tmp,
                            progress=False, count=count)  # fmt: skip
            rows.append({"seed": seed, "epsilon": round(s["metrics"]["epsilon"], 4),
                         "distance_median": s["contact_accuracy"]["distance_median"],
                         "angle_p95_deg": s["contact_accuracy"]["angle_p95_deg"],
                         "contacts": s["contacts"]})  # fmt: skip
        out[f"{body}/{strategy}/{count}"] = rows
    return out


def section_env(seeds: int) -> dict[str, object]:
    """tests/envs/test_haptic_explore.py: independent scoring and a sensible policy."""
    from tests.envs.test_haptic_explore import env_epsilon_curve, independent_epsilon_run

    return {
        "info_vs_independent_epsilon": independent_epsilon_run(),
        "policy_epsilon": {str(s): env_epsilon_curve(s) for s in range(max(seeds, 12))},
    }


SECTIONS = {
    "fit": section_fit,
    "regression": section_regression,
    "explore": section_explore,
    "env": section_env,
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--section", choices=(*SECTIONS, "all"), default="all")
    parser.add_argument("--seeds", type=int, default=10, help="fit seeds per case")
    args = parser.parse_args()
    start = time.perf_counter()
    names = list(SECTIONS) if args.section == "all" else [args.section]
    report: dict[str, object] = {"command": " ".join(["python", *sys.argv])}
    for name in names:
        report[name] = SECTIONS[name](args.seeds)
    report["seconds"] = round(time.perf_counter() - start, 1)
    report["load_average"] = [round(x, 2) for x in os.getloadavg()]
    report["machine"] = (
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"
    )
    print(json.dumps(report, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
