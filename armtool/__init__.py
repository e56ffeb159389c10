"""armtool: lint robot descriptions, benchmark IK, calibrate arms, record servo limits."""

__version__ = "0.1.0"
