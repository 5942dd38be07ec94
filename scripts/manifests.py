"""Every committed result folder under docs/ gets a manifest.json (SPEC §14); docs/index.md lists
the pages and the result folders.

    python scripts/manifests.py            # write the missing manifests and the index
    python scripts/manifests.py --check    # exit 1 if a result folder has no manifest

A result folder is a folder under docs/ holding result files (JSON, CSV, NPZ) other than a
manifest. A new result is committed with its manifest made where it ran
(``hapticsim.suites.provenance.manifest(command)``: command, commit, date, machine, packages).
For results committed before manifests existed, this script writes one from what is known: the
commit that last changed the folder's result files and its date (git), the command where the
folder's own README names one ("Made by `...`" or a ``python scripts/...`` line), and the
machine and packages where a results file records them (a suite's ``provenance``); what was
not recorded is null, and ``"retrofitted": true`` says so.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
DOCS = REPO / "docs"
RESULT_SUFFIXES = (".json", ".csv", ".npz")


def result_folders() -> list[Path]:
    """Folders under docs/ that hold result files, sorted."""
    found = {
        p.parent for p in DOCS.rglob("*")
        if p.is_file() and p.suffix in RESULT_SUFFIXES and p.name != "manifest.json"
    }  # fmt: skip
    return sorted(found)


def _git(*args: str) -> str:
    return subprocess.run(["git", "-C", str(REPO), *args], capture_output=True, text=True,
                          check=False).stdout.strip()  # fmt: skip


def _command(folder: Path) -> str | None:
    """The command the folder's README (or its parent's page) names for its results."""
    for page in (folder / "README.md", folder.with_suffix(".md")):
        if page.is_file():
            text = page.read_text()
            run = re.search(r"`(python scripts/[^`]+)`", text)
            if run:
                return " ".join(run.group(1).split())
            made = re.search(r"Made by `([^`]+)`", text)
            if made:
                return " ".join(made.group(1).split())
    return None


def _recorded(files: list[Path]) -> tuple[dict | None, dict | None]:
    """Machine and packages where a results file records them (a suite's provenance)."""
    for f in files:
        if f.suffix != ".json":
            continue
        try:
            data = json.loads(f.read_text())
        except (OSError, ValueError):
            continue
        prov = data.get("provenance") if isinstance(data, dict) else None
        if isinstance(prov, dict) and "machine" in prov:
            return prov.get("machine"), prov.get("packages")
    return None, None


def retrofit(folder: Path) -> dict:
    """A manifest for results committed before manifests existed (module docstring)."""
    files = sorted(
        p for p in folder.iterdir() if p.suffix in RESULT_SUFFIXES and p.name != "manifest.json"
    )
    rel = [str(p.relative_to(REPO)) for p in files]
    commit = _git("log", "-1", "--format=%H", "--", *rel) or None
    date = _git("log", "-1", "--format=%cI", "--", *rel) or None
    machine, packages = _recorded(files)
    return {
        "command": _command(folder),
        "commit": commit,
        "date": date,
        "machine": machine,
        "packages": packages,
        "files": [p.name for p in files],
        "retrofitted": True,
        "note": "written after the fact from git history and the folder's own records; what "
        "was not recorded when the results were made is null",
    }


def index_text(folders: list[Path]) -> str:
    """docs/index.md: every page, then every result folder with its manifest's command."""
    pages = sorted(p for p in DOCS.rglob("*.md") if p.name != "index.md")
    lines = [
        "# hapticsim documentation",
        "",
        "A physics-simulated haptic exploration testbed: a multi-fingered MuJoCo hand touches",
        "objects, fitters recover their shape from sparse contacts with normals, volume metrics",
        "score it. The repository's README has the set-up (two commands); this site holds the",
        "guide, the topic pages with their measured figures, every committed result with its",
        "manifest, and the API reference.",
        "",
        "## Pages",
        "",
    ]
    for page in pages:
        rel = page.relative_to(DOCS)
        title = next((ln[2:].strip() for ln in page.read_text().splitlines()
                      if ln.startswith("# ")), str(rel))  # fmt: skip
        lines.append(f"- [{title}]({rel.as_posix()})")
    lines += ["", "## Results (one folder per experiment, each with manifest.json)", "",
              "| folder | files | command | commit |", "|---|---|---|---|"]  # fmt: skip
    for folder in folders:
        m = json.loads((folder / "manifest.json").read_text())
        rel = folder.relative_to(DOCS).as_posix() or "."
        command = (m.get("command") or "not recorded")
        if isinstance(command, list):
            command = " ".join(command)
        commit = (m.get("commit") or (m.get("git") or {}).get("commit") or "")[:10]
        count = sum(1 for f in folder.iterdir()  # the result files committed here
                    if f.suffix in RESULT_SUFFIXES and f.name != "manifest.json")  # fmt: skip
        command = command.replace("|", "\\|")  # a table cell
        lines.append(f"| `{rel}` | {count} | `{command}` | {commit} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only check; exit 1 if missing")
    args = parser.parse_args(argv)
    folders = result_folders()
    missing = [f for f in folders if not (f / "manifest.json").is_file()]
    if args.check:
        for f in missing:
            print(f"no manifest: {f.relative_to(REPO)}", file=sys.stderr)
        return 1 if missing else 0
    for folder in missing:
        (folder / "manifest.json").write_text(json.dumps(retrofit(folder), indent=2) + "\n")
        print(f"wrote {folder.relative_to(REPO)}/manifest.json", file=sys.stderr)
    (DOCS / "index.md").write_text(index_text(folders))
    print(f"{len(folders)} result folders, {len(missing)} manifests written", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
