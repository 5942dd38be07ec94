"""Tests of hapticsim.metrics."""
