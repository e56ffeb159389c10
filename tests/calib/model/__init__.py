"""Tests of armtool.calib.model."""
