"""Benchmarks and report writers on top of the library (STYLE.md: not library layers).

- :mod:`~lab.benchmarks.env`: steps per second of the environment (one, vectorised, the
  touch alone);
- :mod:`~lab.benchmarks.sim`: the simulator's physics and exploration speed, and the
  contact accuracy on meshed objects;
- :mod:`~lab.benchmarks.comparison`: exploration policies compared on the same episodes
  (``hapticsim policies evaluate``, ``scripts/compare_policies.py``), written as JSON, CSV,
  Markdown and a plot.

Nothing in the library imports this package; ``cli`` and ``scripts/`` do.
"""
