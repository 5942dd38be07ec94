"""MuJoCo simulation of haptic exploration: a four-fingered hand touches a superquadric object.

- :mod:`~hapticsim.sim.scene`: MJCF hand (``models/hand.xml``) + table + object, via MjSpec;
- :mod:`~hapticsim.sim.simulator`: palm mocap, fingertip servo (damped least squares), stepping;
- :mod:`~hapticsim.sim.contacts`: fingertip contacts from MuJoCo's contact data;
- :mod:`~hapticsim.sim.controllers`: probing (patches) and contour following (stripes);
- :mod:`~hapticsim.sim.explorer`: palm planning and transit, running controllers;
- :mod:`~hapticsim.sim.strategies`: named strategies (``patch``, ``stripe``, ``sweep``,
  ``paper``).

``MUJOCO_GL`` defaults to ``egl`` (headless rendering) before mujoco is imported.
Nothing below ``sim`` imports mujoco.
"""

import os

os.environ.setdefault("MUJOCO_GL", "egl")
