"""hapticsim's geometry, fitting and metrics import and run without gymnasium installed."""

from __future__ import annotations

import subprocess
import sys

CODE = """
import sys
sys.modules["gymnasium"] = None  # as if not installed: importing it raises ImportError
import numpy as np
import hapticsim
from hapticsim.data import get_body, paper_dataset
c = paper_dataset(get_body("cube"), noise=0.02, rng=0)
r = hapticsim.fit(c.points, c.normals, method="nH", budget=500, rng=0)
print(hapticsim.score(r.superquadric, get_body("cube")).epsilon < 1.0)
"""


def test_no_gymnasium_no_environments_but_the_rest_works() -> None:
    done = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True,
                          timeout=300)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "True"
