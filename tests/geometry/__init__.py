"""Tests of hapticsim.geometry."""
