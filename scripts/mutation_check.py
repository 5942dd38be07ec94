"""Mutation check of the default test run (issue 14 item 5): which tests catch a degraded part.

    python scripts/mutation_check.py [--mutants initial,nls,shift] [--out mutation.json]
                                     [-- PYTEST ARGS]

For each mutant, copies the working tree (without ``.git``; numba's caches and their
modification times come along) into a temporary directory, applies the mutant's source edit
there, runs ``python -m pytest -q -p no:cacheprovider -rfE`` (the default run: not ``slow``)
in the copy with ``PYTHONPATH`` pointing at it (so subprocesses and fresh interpreters run the
mutant too) and collects the failing and erroring tests. The working tree itself is never
changed. Prints JSON: per mutant the edit, the failed tests, the counts and the seconds; exit 1
when a mutant survives (the run passes).

The mutants:

- ``initial``: :func:`hapticsim.fitting.fit` returns its initial estimate (the warm start when
  given, else the paper's initial estimate) instead of the search's best, every method;
- ``nls``: nH is fitted by nLS (least squares from the initial estimate, no genetic algorithm);
- ``shift``: every simulated contact point is shifted 1 mm along its outward normal (the
  MuJoCo recorder and the environment's analytic backend; the synthetic data of SPEC §5, which
  is the paper's generator and not a simulation, is left alone).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: mutant -> (description, [(file, old text, new text)]); each old text occurs exactly once.
MUTANTS: dict[str, tuple[str, list[tuple[str, str, str]]]] = {
    "initial": (
        "fit returns its initial estimate (warm start or the paper's initial estimate)",
        [
            (
                "hapticsim/fitting/driver.py",
                "    best = objective.best_vector\n",
                "    best = (warm if warm is not None else paper_initial(pts)).to_vector()\n",
            )
        ],
    ),
    "nls": (
        "nH replaced by nLS (least squares from the initial estimate)",
        [
            (
                "hapticsim/fitting/driver.py",
                "    elif method in HYBRID_METHODS:\n",
                '    elif method in HYBRID_METHODS and method != "nH":\n',
            )
        ],
    ),
    "shift": (
        "simulated contact points shifted 1 mm along their outward normals",
        [
            (
                "hapticsim/sim/recorder.py",
                "        self.contacts.append(contact)\n",
                "        self.contacts.append(__import__('dataclasses').replace(contact,\n"
                "            point_world=contact.point_world + 1e-3 * contact.normal_world))\n",
            ),
            (
                "hapticsim/envs/analytic.py",
                "        nrm_clean = truth.normals(pts_clean)\n",
                "        nrm_clean = truth.normals(pts_clean)\n"
                "        pts_clean = pts_clean + 1e-3 * nrm_clean\n",
            ),
        ],
    ),
}

_FAILED = re.compile(r"^(FAILED|ERROR) (.+?)(?: - .*)?$")  # test ids may hold spaces
_COUNTS = re.compile(r"(\d+) (passed|failed|errors?|skipped|deselected|xfailed|xpassed)")


def _copy_tree(dest: Path) -> None:
    """The working tree without git's and tools' state (numba caches kept, with their mtimes)."""
    ignore = shutil.ignore_patterns(".git", ".hypothesis", ".ruff_cache", ".pytest_cache", "runs")
    shutil.copytree(ROOT, dest, ignore=ignore, symlinks=True, copy_function=shutil.copy2)


def _apply(tree: Path, edits: list[tuple[str, str, str]]) -> None:
    for name, old, new in edits:
        path = tree / name
        text = path.read_text()
        if text.count(old) != 1:
            raise SystemExit(f"mutation_check: {name}: the text to replace occurs "
                             f"{text.count(old)} times, expected once: {old!r}")  # fmt: skip
        path.write_text(text.replace(old, new))


def run_mutant(name: str, pytest_args: list[str]) -> dict[str, object]:
    """Run the default tests against mutant `name` in a temporary copy of the tree."""
    description, edits = MUTANTS[name]
    with tempfile.TemporaryDirectory(prefix=f"hapticsim-mutant-{name}-") as tmp:
        tree = Path(tmp) / "tree"
        _copy_tree(tree)
        _apply(tree, edits)
        env = {**os.environ, "PYTHONPATH": str(tree), "MUJOCO_GL": "egl"}
        cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-rfE",
               "--tb=no", *pytest_args]  # fmt: skip
        start = time.perf_counter()
        proc = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True)
        seconds = time.perf_counter() - start
    lines = proc.stdout.splitlines()
    caught = sorted({m.group(2) for line in lines if (m := _FAILED.match(line))})
    counts = {kind: int(n) for n, kind in _COUNTS.findall(lines[-1] if lines else "")}
    return {
        "mutant": name,
        "description": description,
        "edits": [{"file": f, "old": old, "new": new} for f, old, new in edits],
        "pytest": " ".join(["python", "-m", "pytest", *cmd[3:]]),
        "exit_status": proc.returncode,
        "caught": bool(caught) or proc.returncode != 0,
        "failed_tests": caught,
        "counts": counts,
        "summary": lines[-1] if lines else proc.stderr[-500:],
        "seconds": round(seconds, 1),
        "load_average_end": [round(x, 2) for x in os.getloadavg()],
    }


def main() -> int:
    argv = sys.argv[1:]
    pytest_args = argv[argv.index("--") + 1 :] if "--" in argv else []
    argv = argv[: argv.index("--")] if "--" in argv else argv
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mutants", default=",".join(MUTANTS), help="comma-separated")
    parser.add_argument("--out", type=Path, default=None, help="also write the JSON here")
    args = parser.parse_args(argv)
    names = args.mutants.split(",")
    unknown = [n for n in names if n not in MUTANTS]
    if unknown:
        parser.error(f"unknown mutants {unknown}; choose from {', '.join(MUTANTS)}")
    report: dict[str, object] = {
        "command": " ".join(["python", "scripts/mutation_check.py", *sys.argv[1:]]),
        "load_average_start": [round(x, 2) for x in os.getloadavg()],
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}",
        "mutants": [],
    }
    for name in names:
        sys.stderr.write(f"mutant {name}: running the default tests ...\n")
        result = run_mutant(name, pytest_args)
        sys.stderr.write(f"mutant {name}: {result['summary']}\n")
        report["mutants"].append(result)  # type: ignore[union-attr]
        if args.out is not None:  # after each mutant, so a long run keeps what it has
            args.out.write_text(json.dumps(report, indent=2) + "\n")
    print(json.dumps(report, indent=2))
    return 0 if all(m["caught"] for m in report["mutants"]) else 1  # type: ignore[union-attr]


if __name__ == "__main__":
    sys.exit(main())
