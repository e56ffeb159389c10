"""Tests of armtool.calib.handeye."""
