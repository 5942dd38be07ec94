"""hapticsim.metrics."""
