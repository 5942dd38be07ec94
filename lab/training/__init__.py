"""Training exploration policies: stable-baselines3 glue (:mod:`lab.training.sb3`), Ray RLlib
(:mod:`lab.training.rllib`) and the export of a trained actor (:mod:`lab.training.export`)."""
