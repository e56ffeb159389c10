"""The choices `armtool limits` offers, defined once for the core and the command line."""

from __future__ import annotations

from enum import Enum


class Mode(str, Enum):
    """How the ends are found: a person moves the joints (torque off), or a low-torque seek."""

    MANUAL = "manual"
    AUTO = "auto"
