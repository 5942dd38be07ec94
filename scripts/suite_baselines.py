"""Regenerate the committed suite baselines docs/suites/*.json and their tables in the README.

One command after a change that moves the numbers (a faster or better fitter, a new policy):

    python scripts/suite_baselines.py                  # all shipped suites, 2 worker processes
    python scripts/suite_baselines.py fit-v1           # one suite
    python scripts/suite_baselines.py --scheduler local:2
    python scripts/suite_baselines.py --tables-only    # rewrite the tables from the JSON files

Each suite is run as ``hapticsim suite run NAME --workers 2 --out docs/suites/NAME.json``; then
docs/suites/README.md gets one section per baseline (group tables, run time, load, commit)
between the markers ``<!-- baselines:start -->`` and ``<!-- baselines:end -->``. The rest of the
README (written by hand: what the suites are for, measured figures) is kept. Run it from a clean
checkout, so that the recorded commit is the code that made the numbers.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

from hapticsim._files import write_text_atomic
from hapticsim.suites import run_suite, suite_names
from hapticsim.suites.report import results_markdown

START, END = "<!-- baselines:start -->", "<!-- baselines:end -->"

HEADER = """# Suite baselines

Results of the regression suites shipped with hapticsim (`hapticsim suite list`) at the commit
named in each section: the baselines that `hapticsim suite compare docs/suites/NAME.json
RESULTS.json` checks new results against. Regenerate them all with
`python scripts/suite_baselines.py` (README.md, section "Regression suites in your CI").
"""


def readme_text(old: str | None, sections: list[str]) -> str:
    """The README with the baseline sections between the markers (the rest of `old` kept)."""
    block = f"{START}\n\n" + "\n".join(sections) + f"\n{END}"
    if old is None or START not in old or END not in old:
        return f"{HEADER}\n{block}\n"
    head, _, rest = old.partition(START)
    _, _, tail = rest.partition(END)
    return head + block + tail


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("suites", nargs="*", help="suite ids (default: all shipped suites)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--scheduler", default=None, help="a Dask cluster instead of processes")
    parser.add_argument("--out", type=Path, default=Path("docs/suites"))
    parser.add_argument(
        "--tables-only", action="store_true", help="run nothing; rewrite the README's tables"
    )
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name in [] if args.tables_only else args.suites or suite_names():
        engine = f"--scheduler {args.scheduler}" if args.scheduler else f"--workers {args.workers}"
        command = f"hapticsim suite run {name} {engine} --out {args.out / name}.json"
        load = [round(x, 2) for x in os.getloadavg()]
        print(f"{command}   (load average {load})", file=sys.stderr)
        results = run_suite(
            name, args.out / f"{name}.json", workers=None if args.scheduler else args.workers,
            scheduler=args.scheduler, command=command.split(),
        )  # fmt: skip
        summary = results["summary"]
        print(
            f"{name}: {summary['cases']} cases, {summary['failed']} failed, "
            f"{summary['seconds']:.0f} s, load average {summary['load_average']}",
            file=sys.stderr,
        )
    sections = []
    for path in sorted(args.out / f"{name}.json" for name in suite_names()):
        if not path.is_file():  # other JSON there (benchmarks) is not a baseline
            continue
        results = json.loads(path.read_text())
        command = " ".join(results["provenance"]["command"] or [])
        sections.append(results_markdown(results, command))
    readme = args.out / "README.md"
    old = readme.read_text() if readme.is_file() else None
    write_text_atomic(readme, readme_text(old, sections))
    return 0


if __name__ == "__main__":
    sys.exit(main())
