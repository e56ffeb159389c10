"""Simulator fixtures shared by the servo tests (no hardware: every bus is a pty)."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from armtool.servo.sim import SimBus

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "servo"

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="the simulator needs a pty")


def sim_config(protocol: str = "dxl1", ids: tuple[int, ...] = (1, 2), **extra: Any) -> dict[str, Any]:
    model = {"dxl1": "AX-12A", "dxl2": "XL430-W250", "feetech": "STS3215"}[protocol]
    stops = {"dxl1": [92, 914], "dxl2": [700, 3400], "feetech": [800, 3300]}[protocol]
    cfg: dict[str, Any] = {
        "protocol": protocol,
        "baud": 1000000,
        "return_delay": 0,
        "joints": [{"id": i, "model": model, "stops": stops} for i in ids],
    }
    cfg.update(extra)
    return cfg


@pytest.fixture
def ax_sim() -> Iterator[SimBus]:
    with SimBus.start(sim_config("dxl1")) as sim:
        yield sim
