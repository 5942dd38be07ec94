"""Scripted fingertip controllers: probing (patches) and contour following (stripes)."""

from hapticsim.sim.controllers.base import FingerTask
from hapticsim.sim.controllers.follow import FollowConfig, FollowTask
from hapticsim.sim.controllers.probe import Probe, ProbeConfig, ProbeTask

__all__ = ["FingerTask", "FollowConfig", "FollowTask", "Probe", "ProbeConfig", "ProbeTask"]
