"""docs/ holds no result without a manifest (SPEC §14), and its index lists every result folder."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def test_every_result_folder_has_a_manifest_and_is_indexed() -> None:
    proc = subprocess.run(
        [sys.executable, str(REPO / "scripts" / "manifests.py"), "--check"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    index = (REPO / "docs" / "index.md").read_text()
    for manifest in sorted((REPO / "docs").rglob("manifest.json")):
        data = json.loads(manifest.read_text())
        assert {"command", "commit", "date", "machine", "packages"} <= set(data), manifest
        folder = manifest.parent.relative_to(REPO / "docs").as_posix() or "."
        assert f"| `{folder}` |" in index, f"docs/index.md does not list {folder}"
