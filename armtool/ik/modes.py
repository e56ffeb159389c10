"""ik-bench's choices, numpy-free: the core (bench.py) and the CLI's options share these enums,
and the CLI declares its options before numpy may load (`armtool --help` stays light)."""

from __future__ import annotations

from enum import Enum


class SeedMode(str, Enum):
    """Where each benchmark solve starts: mid-range, a random configuration, or near the answer."""

    MID = "mid"
    RANDOM = "random"
    NEAR = "near"


class BenchFormat(str, Enum):
    """How `armtool ik-bench` writes its report on stdout."""

    TABLE = "table"
    JSON = "json"
    CSV = "csv"
