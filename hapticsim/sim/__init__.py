"""MuJoCo simulation of haptic exploration: a four-fingered hand touches a superquadric object.

- :mod:`~hapticsim.sim.scene`: MJCF hand (``models/hand.xml``) + table + object, via MjSpec;
- :mod:`~hapticsim.sim.simulator`: palm mocap, fingertip servo (damped least squares), stepping;
- :mod:`~hapticsim.sim.contacts`: fingertip contacts from MuJoCo's contact data;
- :mod:`~hapticsim.sim.controllers`: probing (patches) and contour following (stripes);
- :mod:`~hapticsim.sim.explorer`: palm planning and transit, running controllers;
- :mod:`~hapticsim.sim.strategies`: named strategies (``patch``, ``stripe``, ``sweep``,
  ``paper``).

On headless Linux (no ``DISPLAY``) ``MUJOCO_GL`` defaults to ``egl`` (offscreen rendering)
unless the user chose a GL backend: the one place that decides it. MuJoCo reads it when it is
first imported, which every module of the package does through ``sim`` (importing this package
first). Nothing below ``sim`` imports mujoco.
"""

import os
import sys

if sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
    os.environ.setdefault("MUJOCO_GL", "egl")
