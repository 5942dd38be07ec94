"""Shared fixtures of the environment tests."""

from __future__ import annotations

import os

# Offscreen rendering on a headless machine; MuJoCo reads this when it is first imported.
os.environ.setdefault("MUJOCO_GL", "egl")
