"""Tests of armtool.calib.targets."""
