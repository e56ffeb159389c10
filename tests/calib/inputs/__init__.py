"""Tests of armtool.calib.inputs."""
