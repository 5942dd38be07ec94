"""The lab beside the library: speed benchmarks, training glue, report writers and table makers.

Nothing in the installed package (``hapticsim``) imports it; it imports the library. It is not
installed: run it from a checkout (``python scripts/...``, whose scripts put the checkout on
``sys.path``; the tests find it from the repository's root).

- :mod:`lab.benchmarks`: speed benchmarks of the environment, the vector environments and the
  simulation (``scripts/bench*.py``), and the policy comparison's report writer;
- :mod:`lab.training`: training exploration policies with stable-baselines3 (the ``rl`` extra)
  and Ray RLlib (the ``ray`` extra), and the export of a trained actor to a weight file.
"""
