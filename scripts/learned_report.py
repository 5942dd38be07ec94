"""Table, plot and paired tests of ``hapticsim policies evaluate`` results (docs/policies/learned).

Reads the JSON that ``hapticsim policies evaluate`` printed for several policies on the same
backend, objects, seed, episodes and touches (so the episodes pair), writes with
:func:`lab.benchmarks.comparison.write_comparison` a folder with ``README.md`` (mean ± std
(median) after N touches; paired Wilcoxon tests of every policy against random, learned ones
against uncertainty and the shipped ``learned`` too), ``epsilon.csv``, ``epsilon.png`` and
``raw.json``, and prints as JSON the figures after the last touch and the bar of issue 10
(eps_L <= eps_R - 0.5 (eps_R - eps_U) and a two-sided paired Wilcoxon p below ``--alpha``)::

    python scripts/learned_report.py docs/policies/learned/json/analytic-*.json \\
        --out docs/policies/learned/analytic
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the checkout on the path: the lab (lab/) sits beside the library and is not installed
_sys.path.insert(0, str(_Path(__file__).resolve().parents[1]))

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

#: Keys that must agree for results to pair episode by episode.
PAIRING_KEYS: tuple[str, ...] = ("backend", "objects", "episodes", "touches", "seed")


def read_results(paths: list[Path]) -> list[dict[str, Any]]:
    results = []
    for path in paths:
        try:
            data = json.loads(path.read_text())
        except (OSError, ValueError) as exc:
            raise SystemExit(f"{path}: not a readable JSON file: {exc}") from None
        missing = [k for k in (*PAIRING_KEYS, "policy", "episodes_epsilon") if k not in data]
        if missing:
            raise SystemExit(f"{path}: not `hapticsim policies evaluate` output (lacks {missing})")
        results.append(data)
    first = results[0]
    for path, data in zip(paths, results, strict=True):
        differ = [k for k in PAIRING_KEYS if data[k] != first[k]]
        if differ:
            raise SystemExit(
                f"{path} does not pair with {paths[0]}: "
                + ", ".join(f"{k} {data[k]!r} != {first[k]!r}" for k in differ)
            )
    names = [r["policy"] for r in results]
    if len(set(names)) != len(names):
        raise SystemExit(f"one result per policy, got {names}")
    return results


def one_sided_p(a: np.ndarray, b: np.ndarray) -> float:
    """Wilcoxon signed-rank p-value of the alternative 'a is lower than b'."""
    from scipy.stats import wilcoxon

    return float(wilcoxon(a, b, alternative="less").pvalue) if np.any(a != b) else 1.0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="+", type=Path, help="JSON of policies evaluate")
    parser.add_argument("--out", type=Path, required=True, help="folder to write")
    parser.add_argument("--alpha", type=float, default=0.01, help="level of the paired test")
    parser.add_argument("--learned", default="learned", help="name of the learned policy")
    args = parser.parse_args(argv)

    from hapticsim.envs.evaluation import Comparison
    from hapticsim.envs.haptic_explore_v0 import HapticExploreConfig
    from lab.benchmarks.comparison import write_comparison

    results = read_results(args.results)
    first = results[0]
    order = {"learned": 0, "random": 1, "paper": 2, "uncertainty": 3}
    results.sort(
        key=lambda r: order.get(r["policy"], 0 if r["policy"].startswith("learned") else 9)
    )
    objects, touches = first["objects"], int(first["touches"])
    episodes = tuple(
        {"policy": r["policy"], "objects": objects, "episode": i, "epsilon": row}
        for r in results
        for i, row in enumerate(r["episodes_epsilon"])
    )
    config = HapticExploreConfig(backend=first["backend"], touch_budget=touches)
    from dataclasses import asdict

    settings = {k: v for k, v in asdict(config).items() if k not in ("objects", "fit")}
    settings.update(fit=asdict(config.fit), seed=first["seed"], episodes=first["episodes"])
    cmp = Comparison(tuple(r["policy"] for r in results), (objects,), touches, episodes, settings)
    command = "hapticsim policies evaluate --policy NAME " + (
        f"--backend {first['backend']} --objects {objects} --episodes {first['episodes']} "
        f"--touches {touches} --seed {first['seed']}, then python scripts/learned_report.py "
        + " ".join(str(p) for p in args.results)
        + f" --out {args.out}"
    )
    write_comparison(cmp, args.out, command)

    final = {
        r["policy"]: {
            "mean": float(r["epsilon"]["mean"][-1]),
            "std": float(r["epsilon"]["std"][-1]),
            "median": float(r["epsilon"]["median"][-1]),
        }
        for r in results
    }
    out: dict[str, Any] = {k: first[k] for k in PAIRING_KEYS}
    out["epsilon_after_last_touch"] = final
    tests = {}
    for policy in cmp.policies:
        for baseline in ("random", "uncertainty", "learned"):
            if policy in ("random", baseline) or baseline not in cmp.policies:
                continue
            if baseline == "learned" and not policy.startswith("learned"):
                continue  # learned policies against the shipped compact one
            t = cmp.paired_test(policy, baseline, objects, touches)
            a = cmp.epsilon(policy, objects)[:, touches - 1]
            b = cmp.epsilon(baseline, objects)[:, touches - 1]
            t["p_value_one_sided_lower"] = one_sided_p(a, b)
            tests[f"{policy} vs {baseline}"] = t
    out["paired_wilcoxon"] = tests
    learned = args.learned
    if learned in final and "random" in final:
        eps_l, eps_r = final[learned]["mean"], final["random"]["mean"]
        test = tests[f"{learned} vs random"]
        bar: dict[str, Any] = {"beats_random": eps_l < eps_r and test["p_value"] < args.alpha}
        if "uncertainty" in final:
            eps_u = final["uncertainty"]["mean"]
            bar["threshold"] = eps_r - 0.5 * (eps_r - eps_u)
            bar["meets_half_gap"] = eps_l <= bar["threshold"]
            bar["meets_stretch"] = eps_l <= eps_u
        out["bar"] = bar
    (args.out / "summary.json").write_text(json.dumps(out, indent=2) + "\n")
    print(json.dumps(out, indent=2))
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
