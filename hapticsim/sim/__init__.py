"""hapticsim.sim."""
