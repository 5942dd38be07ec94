"""Benchmarks and report writers on top of the library (STYLE.md: not library layers).

- :mod:`~hapticsim.benchmarks.env`: steps per second of the environment (one, vectorised, the
  touch alone);
- :mod:`~hapticsim.benchmarks.sim`: the simulator's physics and exploration speed, and the
  contact accuracy on meshed objects;
- :mod:`~hapticsim.benchmarks.comparison`: exploration policies compared on the same episodes
  (``hapticsim policies evaluate``, ``scripts/compare_policies.py``), written as JSON, CSV,
  Markdown and a plot.

Nothing in the library imports this package; ``cli`` and ``scripts/`` do.
"""
