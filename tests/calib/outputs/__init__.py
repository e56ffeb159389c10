"""Tests of armtool.calib.outputs."""
