"""Tests of hapticsim.data."""
