"""The choices `servo-lut` offers, defined once for the core and the command line.

Numpy-free on purpose: the command module imports it at start-up to build its options."""

from __future__ import annotations

from enum import Enum
from typing import Literal

Side = Literal["up", "down"]  # the direction one reading's point was approached from
SIDES: tuple[Side, ...] = ("up", "down")


class Method(str, Enum):
    PCHIP = "pchip"
    LINEAR = "linear"
    POLY = "poly"


class Approach(str, Enum):
    """Which approach direction the table is for; `mean` averages up and down (hysteresis split)."""

    UP = "up"
    DOWN = "down"
    MEAN = "mean"


class ExportFormat(str, Enum):
    C = "c"
    CSV = "csv"
    JSON = "json"
    YAML = "yaml"


class MeasureApproach(str, Enum):
    """Which direction `measure` approaches each point from; `both` records up and down."""

    UP = "up"
    DOWN = "down"
    BOTH = "both"


class ReportFormat(str, Enum):
    """What `check` prints on stdout."""

    TEXT = "text"
    JSON = "json"
