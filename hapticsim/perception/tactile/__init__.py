"""Tactile sensing: taxel pads, the skin's elastic model, sensor models and contact estimation.

- :mod:`~hapticsim.perception.tactile.pad`: a pad's taxel grid on a fingertip sphere or a flat
  plate;
- :mod:`~hapticsim.perception.tactile.skin`: the skin's elastic model (pressure from depth), the
  sensor model (noise, quantisation, gains, dead taxels, crosstalk, threshold) and named
  presets;
- :mod:`~hapticsim.perception.tactile.presets`: the shipped skins (``ideal``, ``vision``,
  ``capacitive``) and skin files;
- :mod:`~hapticsim.perception.tactile.depth`: the depth of taxels inside any solid (hapticsim's
  own taxel model, for objects MuJoCo's ``<tactile>`` sensor cannot read);
- :mod:`~hapticsim.perception.tactile.traction`: the traction field (pressure and shear per
  taxel, Coulomb friction, stick and slip);
- :mod:`~hapticsim.perception.tactile.estimate`: a contact (location, normal, area, force,
  uncertainty) from one pad's reading.

numpy only, beside ``data``: it imports ``geometry`` only, never ``mujoco``; the simulation
(:mod:`hapticsim.sim.tactile`) and the environment use it.
"""

from hapticsim.perception.tactile.depth import taxel_depths
from hapticsim.perception.tactile.estimate import TactileContact, estimate_contact
from hapticsim.perception.tactile.pad import PadError, PadLayout
from hapticsim.perception.tactile.presets import DEFAULT_SKIN, SKIN_NAMES, SkinError, load_skin
from hapticsim.perception.tactile.skin import FixedPattern, SensorModel, SkinModel, SkinPreset
from hapticsim.perception.tactile.traction import (
    TAXEL_STATES,
    contact_share,
    traction_field,
    winkler_stick_radius,
)

__all__ = [
    "DEFAULT_SKIN",
    "FixedPattern",
    "PadError",
    "PadLayout",
    "SKIN_NAMES",
    "SensorModel",
    "SkinError",
    "SkinModel",
    "SkinPreset",
    "TAXEL_STATES",
    "TactileContact",
    "contact_share",
    "estimate_contact",
    "load_skin",
    "taxel_depths",
    "traction_field",
    "winkler_stick_radius",
]
