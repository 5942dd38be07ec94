"""Fuzz every ``hapticsim`` command and print the tally as JSON (issue 14 item 2).

    python scripts/fuzz.py [--examples 600] [--seed 14] [--commands fit,score,...]
                           [--memory-gb 8]

Runs hypothesis-generated cases (:mod:`tests.fuzz.commands`: mutated contacts and superquadric
files, directories instead of files, random argument values) in this process and checks each
against the SPEC §6 contract (:mod:`tests.fuzz.harness`): exit 0 with valid JSON, or exit 2 with
one line on stderr; no traceback; no output file unless the run succeeded. Prints invocation
counts by command and exit status, the seed, the number of tracebacks and of contract
violations (with the first few cases). Exit status 1 when any case broke the contract.

The address space of this process, and so of the worker processes some commands start, is
capped (``RLIMIT_AS``, ``--memory-gb``; 0: no cap): a case that allocates without bound ends in
a MemoryError, counted as a traceback, instead of taking the machine's memory (one did, before
the counts and budgets were bounded).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
os.environ.setdefault("MUJOCO_GL", "egl")

from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import seed as hypothesis_seed  # noqa: E402

from tests.fuzz.commands import COMMANDS, Case, cases, command_names  # noqa: E402
from tests.fuzz.runner import Tally, run_case  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--examples", type=int, default=600, help="cases to generate")
    parser.add_argument("--seed", type=int, default=14, help="hypothesis seed")
    parser.add_argument("--commands", default=None, help="comma-separated subset of commands")
    parser.add_argument("--memory-gb", type=float, default=8.0,
                        help="cap of the address space [GiB], 0: none")  # fmt: skip
    args = parser.parse_args()
    if args.memory_gb > 0:
        hard = resource.getrlimit(resource.RLIMIT_AS)[1]
        limit = int(args.memory_gb * 2**30)
        if hard != resource.RLIM_INFINITY:
            limit = min(limit, hard)
        resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    names = tuple(args.commands.split(",")) if args.commands else command_names()
    tally = Tally()
    start = time.perf_counter()

    @hypothesis_seed(args.seed)
    @settings(
        max_examples=args.examples, deadline=None, database=None,
        suppress_health_check=list(HealthCheck),
    )  # fmt: skip
    @given(case=cases(names))
    def run(case: Case) -> None:
        run_case(case, tally)  # record, never stop: the tally lists every violation

    run()
    report = {
        "command": " ".join(["python", "scripts/fuzz.py", *sys.argv[1:]]),
        "seed": args.seed,
        "examples": args.examples,
        "memory_cap_gb": args.memory_gb,
        "commands": list(names),
        "generic_strategy": [n for n in names if n not in COMMANDS],
        **tally.to_dict(),
        "wall_seconds": round(time.perf_counter() - start, 1),
        "load_average": [round(x, 2) for x in os.getloadavg()],
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}",
    }
    print(json.dumps(report, indent=2))
    return 1 if tally.failures else 0


if __name__ == "__main__":
    sys.exit(main())
