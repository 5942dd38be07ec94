"""Registration of the environment when hapticsim is imported."""

from __future__ import annotations

import subprocess
import sys

import gymnasium as gym

import hapticsim
from hapticsim.envs.registration import HAPTIC_EXPLORE_ID, register_envs


def test_importing_hapticsim_registers_the_env_by_string_entry_point() -> None:
    assert hapticsim.__name__ == "hapticsim"
    spec = gym.spec(HAPTIC_EXPLORE_ID)
    assert spec.entry_point == "hapticsim.envs.haptic_explore_v0:HapticExploreEnv"
    assert spec.version == 0


def test_register_envs_is_idempotent() -> None:
    before = gym.spec(HAPTIC_EXPLORE_ID)
    register_envs()
    register_envs()
    assert gym.spec(HAPTIC_EXPLORE_ID) is before


def test_registration_in_a_fresh_process_imports_neither_mujoco_nor_the_env() -> None:
    code = (
        "import sys, gymnasium as gym, hapticsim\n"
        f"assert {HAPTIC_EXPLORE_ID!r} in gym.registry\n"
        "assert 'mujoco' not in sys.modules, 'registration imported mujoco'\n"
        "assert 'hapticsim.envs.haptic_explore_v0' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)
