"""Time a suite on each engine and check that the engines agree, byte for byte (JSON on stdout).

    python scripts/bench_suite.py                        # fit-v1: --workers 2, then local:2
    python scripts/bench_suite.py explore-v1 --engines workers:2
    python scripts/bench_suite.py --baseline docs/suites/fit-v1.json   # and the committed digest

Issue bar: ``suite run fit-v1`` in at most 5 minutes with 2 workers, and the same per-case
metrics with ``--scheduler local:2``. The machine is shared: the load average is printed beside
every time, and the CPU time of this process and its (joined) workers beside the wall time.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import sys
import time

from hapticsim.suites import run_suite


def cpu_seconds() -> float:
    """User + system CPU time of this process and of its children that have ended [s]."""
    own, children = (
        resource.getrusage(r) for r in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)
    )
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("suite", nargs="?", default="fit-v1")
    parser.add_argument(
        "--engines", nargs="+", default=["workers:2", "local:2"],
        help="workers:N (local processes) or local:N / tcp://... (Dask)",
    )  # fmt: skip
    parser.add_argument("--cases", default=None, help="case-id pattern")
    parser.add_argument(
        "--baseline", default=None, help="a results file (docs/suites/NAME.json) to check against"
    )
    args = parser.parse_args(argv)
    report: dict = {"suite": args.suite, "cases": args.cases, "runs": []}
    digests = set()
    for engine in args.engines:
        kind, _, value = engine.partition(":")
        options = {"workers": int(value)} if kind == "workers" else {"scheduler": engine}
        load = os.getloadavg()
        start, cpu = time.perf_counter(), cpu_seconds()
        results = run_suite(args.suite, cases=args.cases, **options)
        seconds, cpu = time.perf_counter() - start, cpu_seconds() - cpu
        digest = results["summary"]["metrics_sha256"]
        digests.add(digest)
        report["runs"].append({
            "engine": engine, "seconds": round(seconds, 1), "cpu_seconds": round(cpu, 1),
            "cases": results["summary"]["cases"], "failed": results["summary"]["failed"],
            "metrics_sha256": digest,
            "load_average_before": [round(x, 2) for x in load],
            "load_average_after": [round(x, 2) for x in os.getloadavg()],
        })  # fmt: skip
    report["identical"] = len(digests) == 1
    if args.baseline:
        with open(args.baseline) as f:
            baseline_digest = json.load(f)["summary"]["metrics_sha256"]
        report["baseline"] = args.baseline
        report["identical_to_baseline"] = digests == {baseline_digest}
    sys.stdout.write(json.dumps(report, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
