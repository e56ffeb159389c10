"""The choices `armtool calibrate` offers, defined once for the core and the command line.

Numpy-free on purpose: the command modules import it at start-up to build their options, and
`armtool --help` must not pay for numpy (tests/test_startup_imports.py).
"""

from __future__ import annotations

from enum import Enum
from typing import Literal


class Setup(str, Enum):
    """Where the camera is: fixed, looking at a tag on the flange, or on the flange, looking at a fixed tag."""

    EYE_TO_HAND = "eye_to_hand"
    EYE_IN_HAND = "eye_in_hand"


class Quality(str, Enum):
    """Image conditions of a simulated dataset (blur, noise, contrast; see `simulate.QUALITY`)."""

    GOOD = "good"
    TYPICAL = "typical"
    POOR = "poor"


class ReportFormat(str, Enum):
    """`--format`: a report on stderr for people, or a JSON summary on stdout for scripts."""

    TEXT = "text"
    JSON = "json"


class DistortionModel(str, Enum):
    """Which OpenCV distortion coefficients are fitted (the others are held at 0)."""

    NONE = "none"  # already rectified images
    K1K2 = "k1k2"  # k1, k2, p1, p2: most lenses with up to ~70° field of view
    PLUMB_BOB = "plumb_bob"  # k1, k2, p1, p2, k3: ROS's default model
    RATIONAL = "rational"  # k1..k6, p1, p2: wide-angle lenses; needs many well-spread images


class ChessboardDetector(str, Enum):
    """Which OpenCV detector finds a chessboard's inner corners (both refined by `cornerSubPix`)."""

    CLASSIC = "classic"  # findChessboardCorners: found the real boards that SB missed
    SB = "sb"  # findChessboardCornersSB (Duda & Frese's detector)


class Intrinsics(str, Enum):
    """`calibrate handeye --intrinsics`: hold the camera as its file says, refine it with the frames,
    or let the k-fold held-out reprojection decide."""

    FIXED = "fixed"
    REFINE = "refine"
    AUTO = "auto"


class Criterion(str, Enum):
    """`--criterion`: what chooses the parameter set on held-out poses: every block of the
    residual, each divided by its noise (position and rotation together), or the position alone."""

    COMBINED = "combined"
    POSITION = "position"


class StillBy(str, Enum):
    """What "settled" means when a bag is cut into poses: positions that stay put, or reported velocities near 0."""

    POSITION = "position"
    VELOCITY = "velocity"


# What a sample did in a fit: fitted, held out to validate, named as an outlier, or rejected
# before the fit (no usable tag detection).
SampleRole = Literal["fit", "holdout", "outlier", "rejected"]

# How bad a dataset problem is: an error stops `calibrate fit`, a warning does not.
Severity = Literal["error", "warning"]
