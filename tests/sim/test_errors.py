"""Bad input and impossible simulations end in hapticsim errors with clear messages."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError, SimulationError
from hapticsim.exploration import explore
from hapticsim.geometry import Superquadric
from hapticsim.perception.vision import RoughObject
from hapticsim.sim.scene import build_scene
from hapticsim.sim.session import run_exploration
from hapticsim.sim.simulator import Simulator
from hapticsim.sim.strategies import get_strategy

REPO = Path(__file__).resolve().parents[2]


def test_unknown_object_lists_the_bodies(tmp_path) -> None:
    with pytest.raises(InvalidInputError, match="tapered_box.*cube.*cylinder.*ellipsoid"):
        explore(object_name="sphere", out_dir=tmp_path / "out", progress=False)
    assert not (tmp_path / "out").exists()


def test_unknown_strategy_lists_the_strategies(tmp_path) -> None:
    with pytest.raises(InvalidInputError, match="paper.*patch.*stripe.*sweep|paper, patch"):
        explore(strategy="wander", out_dir=tmp_path / "out", progress=False)
    with pytest.raises(InvalidInputError, match="paper"):
        get_strategy("wander")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"method": "XX"}, "LS"), ({"noise": -0.1}, "noise"), ({"seed": -1}, "seed")],
)
def test_bad_arguments(tmp_path, kwargs, match) -> None:
    with pytest.raises(InvalidInputError, match=match):
        explore(out_dir=tmp_path / "out", progress=False, **kwargs)


def test_object_too_far_for_the_hand() -> None:
    far = Superquadric(a=(0.03, 0.03, 0.03), eps=(0.1, 0.1), center=(1.5, 0.0, 0.0))
    with pytest.raises(SimulationError, match="too far"):
        run_exploration(far, "patch", count=20)


def test_object_too_large_for_the_hand() -> None:
    big = Superquadric(a=(0.2, 0.2, 0.2), eps=(1.0, 1.0))
    with pytest.raises(SimulationError, match="too large"):
        build_scene(big)


def test_no_reachable_surface_is_a_simulation_error() -> None:
    # the controllers believe the object floats 12 cm above where it is: every probe misses,
    # and the exploration ends with fewer contacts than a fit needs
    truth = Superquadric(a=(0.03, 0.03, 0.03), eps=(1.0, 1.0))
    wrong = RoughObject(truth.replace(center=(0.0, 0.0, 0.12)), has_edges=False)
    with pytest.raises(SimulationError, match="gathered only 0 contacts"):
        run_exploration(truth, "patch", count=20, rough=wrong)


@pytest.mark.parametrize("field", ["qvel", "qfrc_applied", "qpos"])
def test_instability_raises_instead_of_nan(field: str, tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)  # MuJoCo's default handler would write MUJOCO_LOG.TXT here
    scene = build_scene(Superquadric(a=(0.03, 0.03, 0.03), eps=(1.0, 1.0)))
    sim = Simulator(scene)
    sim.reset(np.array([0.0, 0.0, 0.2]), np.eye(3))
    getattr(sim.data, field)[:] = 1e30 if field != "qpos" else np.nan  # blow the state up
    with pytest.raises(SimulationError, match="unstable") as info:
        for _ in range(10):
            sim.tick()
    if field != "qpos":  # a NaN position is caught before MuJoCo warns
        assert "MuJoCo: Nan, Inf or huge value" in str(info.value)
    assert list(tmp_path.iterdir()) == []  # issue 14: no MUJOCO_LOG.TXT


_UNSTABLE = """
import numpy as np
from hapticsim.errors import SimulationError
from hapticsim.geometry import Superquadric
from hapticsim.sim.scene import build_scene
from hapticsim.sim.simulator import Simulator
sim = Simulator(build_scene(Superquadric(a=(0.03, 0.03, 0.03), eps=(1.0, 1.0))))
sim.reset(np.array([0.0, 0.0, 0.2]), np.eye(3))
sim.data.qvel[:] = 1e30
try:
    for _ in range(10):
        sim.tick()
except SimulationError:
    print("raised")
"""


def test_an_unstable_simulation_writes_no_log_file_and_prints_nothing(tmp_path) -> None:
    # issue 14: MuJoCo wrote MUJOCO_LOG.TXT into the working directory (and printed a warning)
    env = os.environ | {"PYTHONPATH": str(REPO), "MUJOCO_GL": "egl"}
    proc = subprocess.run(
        [sys.executable, "-c", _UNSTABLE], capture_output=True, text=True, env=env,
        cwd=tmp_path, timeout=120,
    )  # fmt: skip
    assert (proc.returncode, proc.stdout, proc.stderr) == (0, "raised\n", "")
    assert list(tmp_path.iterdir()) == []


def test_cli_unknown_object_is_one_line_exit_2() -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "hapticsim.cli", "explore", "--object", "sphere", "--quiet"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert len(proc.stderr.strip().splitlines()) == 1 and "cube" in proc.stderr


def test_an_unstable_exploration_names_object_strategy_and_seed(
    tmp_path, monkeypatch, capsys
) -> None:
    from hapticsim.cli import main
    from hapticsim.sim import simulator

    real, calls = simulator.Simulator.tick, []

    def blow_up(self, read=True):
        calls.append(1)
        if len(calls) == 300:  # well into the first pattern
            self.data.qvel[:] = 1e30
        return real(self, read)

    monkeypatch.setattr(simulator.Simulator, "tick", blow_up)
    out = tmp_path / "run"
    argv = ["explore", "--object", "cylinder", "--strategy", "stripe", "--seed", "3",
            "--count", "60", "--out", str(out), "--quiet"]  # fmt: skip
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and len(captured.err.splitlines()) == 1
    assert "went unstable" in captured.err and "MuJoCo: Nan, Inf or huge value" in captured.err
    assert (
        "to reproduce: hapticsim explore --object cylinder --strategy stripe --seed 3 --count 60"
        in captured.err
    )
    assert not out.exists()
