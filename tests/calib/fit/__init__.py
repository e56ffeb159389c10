"""Tests of armtool.calib.fit."""
