"""Kinematic calibration from AprilTag observations: the core of `armtool calibrate`."""
