"""What the hand and camera perceive, below the simulation: no MuJoCo here.

- :mod:`hapticsim.perception.vision`: the vision estimate a planner starts from (one noisy depth
  image: a rough pose and extent, never the true exponents or taper; SPEC §7).
- :mod:`hapticsim.perception.tactile`: taxel pads, the skin's elastic and sensor models, the
  presets, and contact estimation from a pad's image (SPEC §11).
"""
