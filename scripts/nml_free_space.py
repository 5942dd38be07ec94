"""nML with and without free space on contacts from the simulated hand.

For each of the paper's bodies and each seed, ``hapticsim explore`` (MuJoCo hand, ``paper``
strategy, sigma_N = ``--noise``, the default nH fit) gathers contacts and writes ``contacts.npz``
with the fingertip centres along the run near the contacts (``free_space``: inside the
fingertip, so outside the object). The same noisy contacts are then fitted with nML without
and with those free-space points, with margin 0 (``nML+free``: the centres outside the solid)
and with margin 0.75 times the fingertip radius (``nML+free_r``: the fingertip's own sphere,
less a quarter for the first-order distance), the noise estimated from the data; every fit is
scored against the truth
(``hapticsim.metrics.score``: Monte Carlo, 100 000 points per solid).

Prints JSON on stdout: per body and overall, the mean epsilon of nH (explore's own fit), nML,
and nML with free space (both margins), the median fit seconds; ``--rows`` writes every run.

    python scripts/nml_free_space.py                      # 4 bodies x seeds 0-4, sigma_N 0.1
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np


def _case(body: str, seed: int, noise: float, count: int, radius: float) -> dict[str, Any]:
    from hapticsim.data.io import FREE_SPACE_KEY, read_contacts
    from hapticsim.exploration import explore
    from hapticsim.fitting import fit
    from hapticsim.fitting.ml import with_options
    from hapticsim.geometry import Superquadric
    from hapticsim.metrics import score

    with tempfile.TemporaryDirectory() as tmp:
        summary = explore(object_name=body, strategy="paper", noise=noise, method="nH",
                          seed=seed, out_dir=tmp, progress=False, count=count)  # fmt: skip
        contacts = read_contacts(Path(tmp) / "contacts.npz")
        truth = Superquadric.from_json(Path(tmp) / "truth.json")
        nh = json.loads((Path(tmp) / "metrics.json").read_text())["epsilon"]
    free = contacts.extra[FREE_SPACE_KEY]  # (f, 3) fingertip centres near the contacts
    row: dict[str, Any] = {"body": body, "seed": seed, "noise": noise, "contacts": len(contacts),
                           "complete": summary.get("complete", True), "nH": nh,
                           "free_points": len(free)}  # fmt: skip
    margin = with_options(None, free_margin=0.75 * radius)
    for name, extra in (("nML", {}), ("nML+free", {"free": free}),
                        ("nML+free_r", {"free": free, "options": margin})):  # fmt: skip
        result = fit(contacts.points, contacts.normals, method="nML", rng=seed, **extra)
        row[name] = score(result.superquadric, truth, rng=seed).epsilon
        row[f"{name}_seconds"] = result.seconds
        row[f"{name}_noise"] = result.noise
    return row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bodies", default="tapered_box,cube,cylinder,ellipsoid")
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--noise", type=float, default=0.1)
    parser.add_argument("--count", type=int, default=150)
    parser.add_argument("--tip-radius", type=float, default=0.008, help="fingertip radius [m]")
    parser.add_argument("--rows", default=None)
    args = parser.parse_args(argv)
    os.environ.setdefault("MUJOCO_GL", "egl")
    start, load = time.perf_counter(), os.getloadavg()
    rows = [_case(b, s, args.noise, args.count, args.tip_radius) for b in args.bodies.split(",")
            for s in range(args.seeds)]  # fmt: skip
    if args.rows:
        Path(args.rows).write_text(json.dumps(rows))
    table: dict[str, Any] = {}
    for group in [*args.bodies.split(","), "all"]:
        sel = [r for r in rows if group in ("all", r["body"])]
        table[group] = {
            k: float(np.mean([r[k] for r in sel])) for k in ("nH", "nML", "nML+free", "nML+free_r")
        }
        table[group]["runs"] = len(sel)
    out = {
        "table": table,
        "seconds_median": {
            k: float(np.median([r[f"{k}_seconds"] for r in rows]))
            for k in ("nML", "nML+free", "nML+free_r")
        },  # fmt: skip
        "noise_estimate_mean": float(np.mean([r["nML_noise"] for r in rows])),
        "volume_method": "Monte Carlo, 100000 points per solid (hapticsim.metrics.score)",
        "wall_seconds": time.perf_counter() - start,
        "load_average": {"start": load, "end": os.getloadavg()},
    }
    sys.stdout.write(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
