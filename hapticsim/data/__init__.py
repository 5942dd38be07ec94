"""hapticsim.data."""
