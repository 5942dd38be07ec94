"""The paper's evaluation as functions that anyone can rerun (the top layer).

- :mod:`~hapticsim.experiments.fig4`: the four bodies fitted by LS, H, nLS, nH at equal budgets
  (table and picture grid, paper Fig. 4).
- :mod:`~hapticsim.experiments.fig5`: quality against evaluation budget n and noise sigma_N
  (paper Fig. 5).
- :mod:`~hapticsim.experiments.reproduce`: both, the claim checks
  (:mod:`~hapticsim.experiments.claims`) and ``RESULTS.md``
  (:mod:`~hapticsim.experiments.report`); the ``hapticsim reproduce`` command.
- :mod:`~hapticsim.experiments.trial`: one synthesise-fit-score trial;
  the sweeps run on :mod:`hapticsim.parallel` (keyed seeds, local processes or Dask).

Training glue (stable-baselines3, RLlib) and speed benchmarks sit in the lab beside the library
(``lab/``), which nothing here imports.
"""
