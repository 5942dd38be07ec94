"""Same seed, same bytes, across interpreters: ``synth``, ``fit`` and a short ``explore`` run in
two fresh Python processes with different ``PYTHONHASHSEED`` and must write identical files
(issue 14 item 5). Only wall-clock timings may differ; they are dropped from the JSON compared.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
#: Keys whose values are wall-clock measurements.
TIMING_KEYS = {"seconds", "setup_seconds", "wall_time", "steps_per_second"}

_RUN = """
import sys
from hapticsim.cli import main
for argv in (
    ["synth", "tapered_box", "--seed", "3", "--noise", "0.1", "--out", "c.npz",
     "--truth-out", "t.json"],
    ["fit", "c.npz", "--method", "nH", "--seed", "5", "--out", "fit.json"],
    ["explore", "--object", "cylinder", "--strategy", "stripe", "--count", "30", "--seed", "2",
     "--noise", "0.05", "--out", "run", "--quiet"],
):
    code = main(argv)
    if code:
        sys.exit(code)
"""


def _without_timings(value):
    if isinstance(value, dict):
        return {k: _without_timings(v) for k, v in value.items() if k not in TIMING_KEYS}
    if isinstance(value, list):
        return [_without_timings(v) for v in value]
    return value


def _contents(root: Path) -> dict[str, bytes]:
    """Every file under `root`: its bytes, or for JSON its canonical bytes without timings."""
    out = {}
    for path in sorted(p for p in root.rglob("*") if p.is_file()):
        data = path.read_bytes()
        if path.suffix == ".json":
            value = _without_timings(json.loads(data))
            data = json.dumps(value, sort_keys=True).encode()
        out[str(path.relative_to(root))] = data
    return out


def test_two_fresh_interpreters_write_the_same_bytes(tmp_path: Path) -> None:
    procs = []
    for hash_seed in ("1", "2"):
        work = tmp_path / f"hashseed{hash_seed}"
        work.mkdir()
        env = os.environ | {"PYTHONPATH": str(REPO), "PYTHONHASHSEED": hash_seed,
                            "MUJOCO_GL": "egl"}  # fmt: skip
        procs.append((work, subprocess.Popen(
            [sys.executable, "-c", _RUN], cwd=work, env=env, stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE, text=True,
        )))  # fmt: skip
    for _, proc in procs:
        _, err = proc.communicate(timeout=600)
        assert proc.returncode == 0, err
    first, second = (_contents(work) for work, _ in procs)
    expected = {"c.npz", "t.json", "fit.json", "run/contacts.npz", "run/fit.json",
                "run/metrics.json", "run/report.png", "run/truth.json"}  # fmt: skip
    assert set(first) == set(second) and expected <= set(first)
    for name in first:
        assert first[name] == second[name], f"{name} differs between the interpreters"
