"""MuJoCo simulation of haptic exploration: a hand touches an object (any solid, SPEC §10).

- :mod:`~hapticsim.sim.hand_description`, :mod:`~hapticsim.sim.hand`: the hands (hapticsim's
  four-fingered one, ``models/hand.xml``, and those of gymnasium-robotics, extra ``hands``);
- :mod:`~hapticsim.sim.scene`: hand + table + object, via MjSpec
  (:mod:`~hapticsim.sim.object_mesh`: the objects' collision geometry and stand);
- :mod:`~hapticsim.sim.simulator`: palm mocap, fingertip servo (damped least squares), stepping;
- :mod:`~hapticsim.sim.contacts`: fingertip contacts from MuJoCo's contact data;
  :mod:`~hapticsim.sim.tactile`: the tactile hand, a taxel pad on every fingertip;
- :mod:`~hapticsim.sim.controllers`: probing (patches) and contour following (stripes);
- :mod:`~hapticsim.sim.explorer`, :mod:`~hapticsim.sim.planning`: palm placement and transit,
  running controllers, strokes;
- :mod:`~hapticsim.sim.strategies`: named strategies (``patch``, ``stripe``, ``sweep``,
  ``paper``, ...);
- :mod:`~hapticsim.sim.session`, :mod:`~hapticsim.sim.recorder`, :mod:`~hapticsim.sim.video`,
  :mod:`~hapticsim.sim.render`: an exploration run, its record, video and pictures.

On headless Linux (no ``DISPLAY``) ``MUJOCO_GL`` defaults to ``egl`` (offscreen rendering)
unless the user chose a GL backend: the one place that decides it. MuJoCo reads it when it is
first imported, which every module of the package does through ``sim`` (importing this package
first). Nothing below ``sim`` imports mujoco.
"""

import os
import sys

if sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
    os.environ.setdefault("MUJOCO_GL", "egl")
