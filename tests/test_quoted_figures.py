"""Figures the documentation quotes come from the committed result files (one source)."""

from __future__ import annotations

import json
import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def _means(path: str) -> dict[str, float]:
    data = json.loads((REPO / path).read_text())["epsilon_after_last_touch"]
    return {name: round(value["mean"], 3) for name, value in data.items()}


def test_the_learned_policy_figures_in_the_readme_are_the_summaries() -> None:
    text = " ".join((REPO / "docs/guide/environments.md").read_text().split())
    sentence = re.search(r"On 100 held-out random objects its mean ε after 10 touches is "
                         r"([\d.]+) against random's ([\d.]+) and the uncertainty policy's "
                         r"([\d.]+) \(with the hand on the paper's bodies ([\d.]+) against "
                         r"([\d.]+);", text)  # fmt: skip
    assert sentence, "the guide's sentence on the learned policy changed: update this test"
    quoted = [float(x) for x in sentence.groups()]
    analytic = _means("docs/policies/learned/analytic/summary.json")
    mujoco = _means("docs/policies/learned/mujoco/summary.json")
    assert quoted == [analytic["learned"], analytic["random"], analytic["uncertainty"],
                      mujoco["learned"], mujoco["random"]]  # fmt: skip


def test_the_touch_policy_figures_in_the_readme_are_the_summary() -> None:
    text = " ".join((REPO / "docs/guide/environments.md").read_text().split())
    sentence = re.search(r"On the same 100 held-out random objects its mean ε after 10 touches "
                         r"is ([\d.]+), against the `learned` actor's ([\d.]+) and the "
                         r"uncertainty policy's ([\d.]+)", text)  # fmt: skip
    assert sentence, "the guide's sentence on learned-touch changed: update this test"
    quoted = [float(x) for x in sentence.groups()]
    data = json.loads((REPO / "docs/policies/learned_touch/summary.json").read_text())
    mean = data["random"]["mean"]
    assert quoted == [round(mean[k], 3) for k in ("learned-touch", "learned", "uncertainty")]


def test_the_tactile_touch_actor_figures_in_the_readme_are_the_results() -> None:
    import numpy as np
    from scipy.stats import wilcoxon

    text = " ".join((REPO / "docs/guide/environments.md").read_text().split())
    sentence = re.search(r"trained on it for ([\d,]+) steps .*? blanking them changes nothing "
                         r"\(p = ([\d.]+)\)", text)  # fmt: skip
    assert sentence, "the guide's sentence on the tactile touch actor changed: update this test"
    folder = REPO / "docs/policies/learned_touch_tactile"
    steps = json.loads((folder / "training/summary.json").read_text())["steps"]
    assert int(sentence.group(1).replace(",", "")) == steps

    def final(name: str) -> np.ndarray:
        rows = json.loads((folder / "json" / name).read_text())["episodes_epsilon"]
        return np.array([row[-1] for row in rows])

    p = wilcoxon(final("random-tactile.json"), final("ablate-no-taxels.json")).pvalue
    assert float(sentence.group(2)) == round(float(p), 2)
    summary = json.loads((folder / "summary.json").read_text())
    tests = [row["tactile vs"]["learned-touch"]["p_value"] for row in summary.values()]
    assert min(tests) >= 0.05  # "no difference significant"


def test_the_threads_model_table_in_docs_vector_is_its_json() -> None:
    text = (REPO / "docs/vector.md").read_text()
    data = json.loads((REPO / "docs/vector/threads_model.json").read_text())["speedup"]
    header = re.search(r"\| share of the step holding the GIL \|(.*)\|\n", text)
    assert header, "docs/vector.md's threads model table changed: update this test"
    shares = [cell.strip() for cell in header.group(1).split("|")]
    for label, key in (("pool of 2 threads, environments in order", "in_order"),
                       ("... largest step first", "largest_first")):  # fmt: skip
        row = re.search(r"\| " + re.escape(label) + r" \|(.*)\|\n", text)
        assert row, f"the row {label!r} of docs/vector.md's threads model table is gone"
        quoted = [float(cell.strip().rstrip("x")) for cell in row.group(1).split("|")]
        assert quoted == [round(data[share][key], 2) for share in shares]


def test_the_rllib_held_out_figures_in_the_readme_are_its_json() -> None:
    text = " ".join((REPO / "docs/guide/environments.md").read_text().split())
    sentence = re.search(r"its best module scores ([\d.]+)-([\d.]+) against random touches' "
                         r"([\d.]+) \(p <= ([\d.e-]+)\), though single validations jump and "
                         r"SB3's SAC actor \(([\d.]+)\) stays ahead", text)  # fmt: skip
    assert sentence, "the guide's sentence on RLlib held out changed: update this test"
    data = json.loads((REPO / "docs/vector/rllib_heldout.json").read_text())
    rllib = {k: v for k, v in data["runs"].items() if k != "learned"}
    means = [v["mean"] for v in rllib.values()]
    assert float(sentence.group(1)) == round(min(means), 3)
    assert float(sentence.group(2)) == round(max(means), 3)
    assert float(sentence.group(3)) == round(data["random"]["mean"], 3)
    worst_p = max(v["wilcoxon_p_vs_random"] for v in rllib.values())
    assert sentence.group(4) == f"{worst_p:.1e}"
    assert float(sentence.group(5)) == round(data["runs"]["learned"]["mean"], 3)


def test_the_behaviour_cloning_table_is_its_results() -> None:
    import numpy as np
    from scipy.stats import wilcoxon

    text = (REPO / "docs/policies/learned_touch/README.md").read_text()
    folder = REPO / "docs/policies/learned_touch"

    def final(path: Path) -> np.ndarray:
        return np.array([row[-1] for row in json.loads(path.read_text())["episodes_epsilon"]])

    for label, obs in (("the touch network", "touch"), ("the compact network (the control)",
                                                        "compact")):  # fmt: skip
        row = re.search(r"\| " + re.escape(label) + r" \| ([\d.]+) \(([\d.]+)\) \| (\d+) \| "
                        r"better in (\d+)/100, p = ([\d.e-]+) \| better in (\d+)/100, "
                        r"p = ([\d.e-]+) \|", text)  # fmt: skip
        assert row, f"the behaviour cloning row {label!r} changed: update this test"
        bc = final(folder / "bc" / obs / "random.json")
        unc = final(folder / "json" / "random-uncertainty.json")
        touch = final(folder / "json" / "random-learned-touch.json")
        assert float(row.group(1)) == round(bc.mean(), 4)
        assert float(row.group(2)) == round(float(np.median(bc)), 4)
        assert int(row.group(3)) == int(np.sum(bc > 0.05))
        assert int(row.group(4)) == int(np.sum(bc < unc))
        assert row.group(5) == f"{wilcoxon(bc, unc).pvalue:.1e}"
        assert int(row.group(6)) == int(np.sum(bc < touch))
        assert float(row.group(7)) == float(f"{wilcoxon(bc, touch).pvalue:.2g}")


def test_the_vector_speedups_in_the_readme_and_docs_are_the_benchmark() -> None:
    data = json.loads((REPO / "docs/vector/bench.json").read_text())
    speed = {b: {k: round(data[b][k]["speedup"], 2) for k in ("native", "native_plain", "async")}
             for b in ("analytic", "mujoco")}  # fmt: skip
    readme = " ".join((REPO / "docs/guide/environments.md").read_text().split())
    sentence = re.search(r"On 2 cores ([\d.]+)x one environment's steps/s \(analytic\) and "
                         r"([\d.]+)x \(MuJoCo hand\), against Gymnasium's async ([\d.]+)x and "
                         r"([\d.]+)x", readme)  # fmt: skip
    assert sentence, "the guide's sentence on the vector speed changed: update this test"
    assert [float(x) for x in sentence.groups()] == [
        speed["analytic"]["native"], speed["mujoco"]["native"],
        speed["analytic"]["async"], speed["mujoco"]["async"],
    ]  # fmt: skip
    docs = " ".join((REPO / "docs/vector.md").read_text().split())
    bars = re.search(r"are met: ([\d.]+)x and ([\d.]+)x\*\*", docs)
    assert bars, "docs/vector.md's sentence on the bars changed: update this test"
    assert [float(x) for x in bars.groups()] == [speed["analytic"]["native"],
                                                 speed["mujoco"]["native"]]  # fmt: skip
    assert speed["analytic"]["native"] >= 1.8 and speed["mujoco"]["native"] >= 1.6
    row = re.search(r"\| native without either [^|]*\| [\d.]+ \| ([\d.]+)x \| [\d.]+ \| "
                    r"([\d.]+)x \|", docs)  # fmt: skip
    assert row, "docs/vector.md's plain-shards row changed: update this test"
    assert [float(x) for x in row.groups()] == [speed["analytic"]["native_plain"],
                                                speed["mujoco"]["native_plain"]]  # fmt: skip
