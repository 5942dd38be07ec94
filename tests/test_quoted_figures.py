"""Figures the README quotes come from the committed result files (one source)."""

from __future__ import annotations

import json
import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def _means(path: str) -> dict[str, float]:
    data = json.loads((REPO / path).read_text())["epsilon_after_last_touch"]
    return {name: round(value["mean"], 3) for name, value in data.items()}


def test_the_learned_policy_figures_in_the_readme_are_the_summaries() -> None:
    text = " ".join((REPO / "README.md").read_text().split())
    sentence = re.search(r"On 100 held-out random objects its mean ε after 10 touches is "
                         r"([\d.]+) against random's ([\d.]+) and the uncertainty policy's "
                         r"([\d.]+) \(with the hand on the paper's bodies ([\d.]+) against "
                         r"([\d.]+);", text)  # fmt: skip
    assert sentence, "the README's sentence on the learned policy changed: update this test"
    quoted = [float(x) for x in sentence.groups()]
    analytic = _means("docs/policies/learned/analytic/summary.json")
    mujoco = _means("docs/policies/learned/mujoco/summary.json")
    assert quoted == [analytic["learned"], analytic["random"], analytic["uncertainty"],
                      mujoco["learned"], mujoco["random"]]  # fmt: skip


def test_the_touch_policy_figures_in_the_readme_are_the_summary() -> None:
    text = " ".join((REPO / "README.md").read_text().split())
    sentence = re.search(r"On the same 100 held-out random objects its mean ε after 10 touches "
                         r"is ([\d.]+), against the `learned` actor's ([\d.]+) and the "
                         r"uncertainty policy's ([\d.]+)", text)  # fmt: skip
    assert sentence, "the README's sentence on learned-touch changed: update this test"
    quoted = [float(x) for x in sentence.groups()]
    data = json.loads((REPO / "docs/policies/learned_touch/summary.json").read_text())
    mean = data["random"]["mean"]
    assert quoted == [round(mean[k], 3) for k in ("learned-touch", "learned", "uncertainty")]
