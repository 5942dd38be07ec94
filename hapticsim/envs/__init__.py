"""hapticsim.envs."""
