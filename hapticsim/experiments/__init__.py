"""hapticsim.experiments."""
