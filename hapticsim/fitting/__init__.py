"""hapticsim.fitting."""
