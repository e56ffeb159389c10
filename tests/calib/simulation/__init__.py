"""Tests of armtool.calib.simulation."""
