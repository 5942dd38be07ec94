"""Accuracy and cost of the environment's per-step scorer (``TruthScorer``) against references.

    python scripts/scorer_accuracy.py --out docs/fast-loop/scorer_accuracy.json

30 estimate/truth pairs (random tapered and paper bodies, each truth perturbed into an estimate:
semi-axes +-15 %, exponents +-0.4, taper +-0.2, centre 4 mm), each scored by scorers of 4 seeds.
References: alpha and beta from 3 x 10^6 Monte Carlo samples (``volume_overlap``, standard error
< 0.0003), the Chamfer distance from ``chamfer`` with 20 000 points. Prints JSON: for each
(samples, Chamfer points), the RMS and largest errors of alpha, beta and epsilon, the RMS
relative error of the Chamfer distance, and the median time of one score; and, for comparison,
the error of plain Monte Carlo at 10 000 samples (``volume_overlap``, fresh seeds). Then the
same for a mesh truth (``TruthScorer``, default 4096 samples) on the L-block: 6 nearby
superquadrics x 3 scorer seeds against ``score`` with 400 000 Monte Carlo samples.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from hapticsim.data.distributions import ObjectDistribution
from hapticsim.metrics.chamfer import chamfer
from hapticsim.metrics.episode import TruthScorer
from hapticsim.metrics.volume import volume_overlap


def pairs(count: int, seed: int) -> list:
    rng = np.random.default_rng(seed)
    kinds = [ObjectDistribution(kind="random_tapered"), ObjectDistribution(kind="paper")]
    out = []
    for i in range(count):
        t = kinds[i % 2].sample(rng)
        e = t.replace(
            a=t.a * (1 + rng.uniform(-0.15, 0.15, 3)),
            eps=np.clip(t.eps + rng.uniform(-0.4, 0.4, 2), 0.1, 1.9),
            taper=np.clip(t.taper + rng.uniform(-0.2, 0.2, 2), -0.9, 0.9),
            center=t.center + rng.normal(0, 0.004, 3),
        )
        out.append((t, e))
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=30)
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--samples", type=int, nargs="+", default=[2048, 4096, 10_000])
    parser.add_argument("--chamfer", type=int, nargs="+", default=[96, 128, 200])
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args(argv)
    load = os.getloadavg()[0]
    cases = pairs(args.pairs, 123)
    ref = []
    for t, e in cases:
        v = [volume_overlap(e, t, 1_000_000, rng=s) for s in range(3)]
        ref.append((np.mean([x.alpha for x in v]), np.mean([x.beta for x in v]),
                    chamfer(e, t, samples=20_000, rng=0)))  # fmt: skip
    ref = np.array(ref)

    def summary(errors: list, seconds: list) -> dict:
        err = np.array(errors)
        rms = np.sqrt(np.mean(err**2, axis=0))
        out = {"rms_alpha": rms[0], "rms_beta": rms[1], "rms_epsilon": rms[2],
               "max_abs_epsilon": float(np.abs(err[:, 2]).max())}  # fmt: skip
        if err.shape[1] > 3:
            out["rms_relative_chamfer"] = rms[3]
        if seconds:
            out["median_ms"] = float(np.median(seconds) * 1e3)
        return {k: float(v) for k, v in out.items()}

    rows = []
    for n in args.samples:
        for c in args.chamfer:
            errors, seconds = [], []
            for seed in range(args.seeds):
                for (t, e), r in zip(cases, ref, strict=True):
                    scorer = TruthScorer(t, n, c, rng=seed)
                    scorer.score(e)  # the first call compiles / loads the kernels
                    start = time.perf_counter()
                    s = scorer.score(e)
                    seconds.append(time.perf_counter() - start)
                    errors.append((s.alpha - r[0], s.beta - r[1], s.epsilon - r[0] - r[1],
                                   s.chamfer / r[2] - 1.0))  # fmt: skip
            rows.append({"samples": n, "chamfer_points": c, **summary(errors, seconds)})
            print(f"scorer accuracy: {n} samples, {c} points done", file=sys.stderr)
    mc = []
    for seed in range(args.seeds):
        for (t, e), r in zip(cases, ref, strict=True):
            v = volume_overlap(e, t, 10_000, rng=1000 + seed)
            mc.append((v.alpha - r[0], v.beta - r[1], v.alpha + v.beta - r[0] - r[1]))
    from hapticsim.data.example_meshes import l_block
    from hapticsim.geometry import Superquadric
    from hapticsim.geometry.rotations import rotvec_to_matrix
    from hapticsim.metrics import score

    solid, gen = l_block(), np.random.default_rng(4)
    mesh_errors, mesh_seconds = [], []
    for _ in range(6):
        est = Superquadric(
            a=solid.half_extents * gen.uniform(0.8, 1.2, 3), eps=gen.uniform(0.1, 1.0, 2),
            taper=gen.uniform(-0.2, 0.2, 2),
            rotation=solid.principal_axes @ rotvec_to_matrix(gen.normal(0.0, 0.15, 3)),
            center=solid.centroid + gen.normal(0.0, 0.003, 3),
        )  # fmt: skip
        r = score(est, solid, rng=9, volume_samples=400_000, chamfer_samples=500)
        for seed in range(3):
            scorer = TruthScorer(solid, rng=seed)
            start = time.perf_counter()
            f = scorer.score(est).to_dict()
            mesh_seconds.append(time.perf_counter() - start)
            mesh_errors.append(
                (f["alpha"] - r.alpha, f["beta"] - r.beta, f["epsilon"] - r.alpha - r.beta)
            )
    print("scorer accuracy: mesh done", file=sys.stderr)
    result = {
        "command": "python scripts/scorer_accuracy.py "
        + " ".join(sys.argv[1:] if argv is None else argv),
        "pairs": args.pairs, "scorer_seeds": args.seeds,
        "load_average_1min": {"start": load, "end": os.getloadavg()[0]},
        "truth_scorer": rows,
        "monte_carlo_10000": summary(mc, []),
        "mesh_truth_l_block_4096": summary(mesh_errors, mesh_seconds),
    }  # fmt: skip
    text = json.dumps(result, indent=2) + "\n"
    if args.out is not None:
        from hapticsim._files import write_text_atomic

        write_text_atomic(args.out, text)
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
