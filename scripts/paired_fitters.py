"""The policy tables with two fitters on the same contacts: this checkout's and another's.

The environment draws the fitter's seeds from a stream of its own, so an episode's object,
noise and rough position do not depend on the fitter, and neither do the contacts of a policy
that ignores the estimate (random, paper). Running the comparison of
``scripts/compare_policies.py`` twice, once with this checkout's ``hapticsim.fitting.fit`` and
once with the ``fit`` of another checkout (served by a child process per worker, started with
that checkout on its path), isolates what the fitter does inside the loop:

    python scripts/paired_fitters.py --other /tmp/old --out docs/fast-loop/paired_analytic.json
    python scripts/paired_fitters.py --other /tmp/old --backend mujoco --episodes 20 \\
        --out docs/fast-loop/paired_mujoco.json

(``/tmp/old``: e.g. ``git worktree add /tmp/old ca23d27``, the fitter before the fast loop.)
``--other control`` compares this fitter with itself on other seeds: how far the tables move
when nothing but the fitter's random numbers changes (the resolution of the comparison).
Prints and writes JSON: per object set, policy and N, both mean epsilons, the paired mean
difference (this - other) with its standard error, and in how many episodes the object and the
contact count of every touch were the same (the uncertainty policy's contacts follow its
estimates, so they differ).
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

SERVER = r"""
import pickle, sys
from hapticsim.fitting import fit
from hapticsim.geometry import Superquadric
inp, out = sys.stdin.buffer, sys.stdout.buffer
while True:
    try:
        points, normals, method, budget, seed, initial = pickle.load(inp)
    except EOFError:
        break
    try:
        r = fit(points, normals, method=method, budget=budget, rng=seed,
                initial=None if initial is None else Superquadric(**initial))
        s = r.superquadric
        answer = ("ok", dict(a=s.a, eps=s.eps, taper=s.taper, rotation=s.rotation,
                             center=s.center), float(r.eof), int(r.evaluations))
    except Exception as exc:
        answer = ("error", f"{type(exc).__name__}: {exc}", 0.0, 0)
    pickle.dump(answer, out)
    out.flush()
"""


class OtherFitter:
    """``hapticsim.fitting.fit``'s signature, answered by another checkout's fitter (one child
    process per process that calls it, so forked workers each get their own)."""

    def __init__(self, checkout: Path) -> None:
        self.checkout = checkout
        self._pid: int | None = None
        self._proc: subprocess.Popen[bytes] | None = None

    def _child(self) -> subprocess.Popen[bytes]:
        if self._proc is None or self._pid != os.getpid():
            env = dict(os.environ, PYTHONPATH=str(self.checkout))
            self._proc = subprocess.Popen(
                [sys.executable, "-c", SERVER], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                env=env, cwd=str(self.checkout),
            )  # fmt: skip
            self._pid = os.getpid()
        return self._proc

    def __call__(
        self, points: Any, normals: Any = None, method: str = "nH", budget: int | None = None,
        rng: Any = None, initial: Any = None,
    ) -> Any:  # fmt: skip
        from types import SimpleNamespace

        from hapticsim.errors import ExecutionError
        from hapticsim.geometry import Superquadric

        proc = self._child()
        init = None
        if initial is not None:
            init = {k: getattr(initial, k) for k in ("a", "eps", "taper", "rotation", "center")}
        pickle.dump(
            (np.asarray(points), np.asarray(normals), method, budget, rng, init), proc.stdin
        )
        proc.stdin.flush()
        status, value, eof, evaluations = pickle.load(proc.stdout)
        if status != "ok":
            raise ExecutionError(f"the other fitter failed: {value}")
        return SimpleNamespace(superquadric=Superquadric(**value), eof=eof, evaluations=evaluations)


class ShiftedSeeds:
    """This checkout's ``fit`` with every seed moved by `shift`: the control, how much the
    tables move when only the fitter's random numbers change."""

    def __init__(self, fit: Any, shift: int) -> None:
        self.fit, self.shift = fit, shift

    def __call__(self, *args: Any, rng: Any = None, **kwargs: Any) -> Any:
        return self.fit(*args, rng=int(rng) + self.shift, **kwargs)


def run(args: argparse.Namespace, other: Path | str | None) -> Any:
    import hapticsim.fitting
    from hapticsim.envs.evaluation import compare_policies

    if other == "control":
        hapticsim.fitting.fit = ShiftedSeeds(hapticsim.fitting.fit, 1_000_003)
    elif other is not None:
        hapticsim.fitting.fit = OtherFitter(other)  # forked workers inherit it
    try:
        return compare_policies(
            args.policies, args.objects, args.episodes, seed=args.seed, workers=args.workers,
            fresh_envs=True, backend=args.backend, touch_budget=args.budget, noise=args.noise,
        )  # fmt: skip
    finally:
        if other is not None:
            import importlib

            importlib.reload(hapticsim.fitting)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--other", default=None,
        help="the other checkout; 'control': this fitter with other seeds (the noise floor)",
    )  # fmt: skip
    parser.add_argument("--backend", default="analytic")
    parser.add_argument("--policies", nargs="+", default=["random", "paper", "uncertainty"])
    parser.add_argument("--objects", nargs="+", default=["random_tapered", "paper"])
    parser.add_argument("--episodes", type=int, default=24)
    parser.add_argument("--budget", type=int, default=20)
    parser.add_argument("--noise", type=float, default=0.02)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--touches", type=int, nargs="+", default=[5, 10, 20])
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args(argv)
    if args.other is None:
        parser.error("--other is required: a checkout, or 'control'")
    if args.other != "control":
        args.other = Path(args.other)
        if not (args.other / "hapticsim" / "fitting").is_dir():
            parser.error(f"--other {args.other}: not a hapticsim checkout")
    load = os.getloadavg()[0]
    start = time.perf_counter()
    this = run(args, None)
    this_seconds = time.perf_counter() - start
    that = run(args, args.other)
    key = lambda e: (e["policy"], e["objects"], e["episode"])  # noqa: E731
    mine = {key(e): e for e in this.episodes}
    theirs = {key(e): e for e in that.episodes}
    cells = []
    for objects in args.objects:
        for policy in args.policies:
            ks = [k for k in mine if k[0] == policy and k[1] == objects]
            # contacts agree when the object and every touch's contact count do
            same = sum(
                mine[k]["truth"] == theirs[k]["truth"]
                and mine[k]["n_contacts"] == theirs[k]["n_contacts"]
                for k in ks
            )
            for n in args.touches:
                a = np.array([mine[k]["epsilon"][n - 1] for k in ks])
                b = np.array([theirs[k]["epsilon"][n - 1] for k in ks])
                d = a - b
                cells.append({
                    "objects": objects, "policy": policy, "touches": n, "episodes": len(ks),
                    "this": float(a.mean()), "other": float(b.mean()),
                    "difference": float(d.mean()),
                    "standard_error": float(d.std(ddof=1) / np.sqrt(len(d))),
                    "worse_by_more_than_0.01": bool(d.mean() > 0.01),
                    "same_object_and_contact_counts": same,
                })  # fmt: skip
    result = {
        "command": "python scripts/paired_fitters.py "
        + " ".join(sys.argv[1:] if argv is None else argv),
        "other": str(args.other), "backend": args.backend, "episodes": args.episodes,
        "seconds": {"this": this_seconds, "total": time.perf_counter() - start},
        "load_average_1min": {"start": load, "end": os.getloadavg()[0]},
        "cells": cells,
    }  # fmt: skip
    text = json.dumps(result, indent=2) + "\n"
    if args.out is not None:
        from hapticsim._files import write_text_atomic

        write_text_atomic(args.out, text)
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
