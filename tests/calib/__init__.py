"""Tests of armtool.calib."""
