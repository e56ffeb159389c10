"""Planning points, reading limits files, register conversions, check-angle placement."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.servo.lut.measure import check_angles, plan_commands, read_limits, speed_register, torque_register
from armtool.servo.lut.table import LutTable, Method
from armtool.servo.models import by_name

AX = by_name("AX-12A")


def test_plan_leaves_room_to_back_off() -> None:
    assert plan_commands(100, 200, "up", 10, points=5) == [110, 132, 155, 178, 200]
    assert plan_commands(100, 200, "down", 10, points=3) == [100, 145, 190]
    assert plan_commands(100, 200, "both", 10, step=40) == [110, 150, 190]
    with pytest.raises(ArmtoolError, match="leaves no room"):
        plan_commands(100, 120, "both", 10)
    with pytest.raises(ArmtoolError, match="--points must be at least 2"):
        plan_commands(100, 200, "up", 10, points=1)


def test_read_limits(tmp_path: Path) -> None:
    path = tmp_path / "limits.yaml"
    path.write_text(
        "joints:\n  - {id: 1, model: AX-12A, safe_min_ticks: 99, safe_max_ticks: 907}\n"
        "  - {id: 2, safe_min_ticks: 500, safe_max_ticks: 400}\n  - {id: 3, safe_min_ticks: 1}\n"
    )
    assert read_limits(path, 1) == (99, 907, "AX-12A")
    with pytest.raises(ArmtoolError, match="is not below safe_max_ticks"):
        read_limits(path, 2)
    with pytest.raises(ArmtoolError) as info:
        read_limits(path, 3)
    assert "'safe_max_ticks' is missing" in info.value.what and info.value.where == f"{path}: joints[2]"
    with pytest.raises(ArmtoolError, match="ID 4 is not in the limits file"):
        read_limits(path, 4)
    path.write_text("joints: [\n")
    with pytest.raises(ArmtoolError, match="not valid YAML"):
        read_limits(path, 1)


def test_register_conversions() -> None:
    assert speed_register(AX, 60) == 90  # 60°/s / (6 x 0.111 rpm) = 90.09: nearest, as limits always did
    assert speed_register(by_name("XL430-W250"), 60) == 44
    assert torque_register(AX, 50) == 512
    with pytest.raises(ArmtoolError):
        torque_register(AX, 0)
    with pytest.raises(ArmtoolError):
        speed_register(AX, -1)


def test_check_angles_avoid_knots_and_stay_in_range() -> None:
    table = LutTable(AX, Method.PCHIP, tuple(np.linspace(30, 270, 25)), tuple(np.linspace(100, 920, 25)))
    angles = check_angles(table, 30, seed=3, lo=150, hi=800)
    assert len(angles) == 30
    knots = np.asarray(table.knots_deg)
    assert all(np.min(np.abs(knots - a)) >= 2.5 - 1e-9 for a in angles)  # a quarter of the 10° spacing
    assert all(150 <= table.command_ticks([a])[0] <= 800 for a in angles)
    with pytest.raises(ArmtoolError, match="could not place"):
        check_angles(table, 5, seed=0, lo=500, hi=501)
