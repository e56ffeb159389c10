"""Applying a table: angle lists, CSV columns, joint trajectories, out-of-range refusals."""

from __future__ import annotations

import csv
import io
import math

import pytest

from armtool.errors import ArmtoolError
from armtool.servo.lut.apply import apply_csv, apply_list
from armtool.servo.lut.table import LutTable, Method
from armtool.servo.models import by_name as servo_model

# 10° per 30 ticks below 150°, 10° per 40 ticks above: easy to check by hand
TABLE = LutTable(servo_model("AX-12A"), Method.LINEAR, (30.0, 150.0, 270.0), (90.0, 450.0, 930.0))


def rows(text: str) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(text)))


def test_list() -> None:
    out = apply_list(TABLE, [30, 100, 150, 200, 270])
    assert [int(r["command_ticks"]) for r in rows(out.text)] == [90, 300, 450, 650, 930]


def test_list_out_of_range_and_clip() -> None:
    with pytest.raises(ArmtoolError) as info:
        apply_list(TABLE, [100, 290])
    assert "290.000° is outside the table's range 30.00..270.00°" in info.value.what and info.value.where == "value 2"
    out = apply_list(TABLE, [10, 290], clip=True)
    assert [int(r["command_ticks"]) for r in rows(out.text)] == [90, 930] and out.clipped == 2


def test_csv_angle_column_keeps_other_columns_and_comments() -> None:
    text = "# from the planner\ntime_s,angle_deg,note\n0,30,a\n0.5,100,b\n"
    out = apply_csv(TABLE, text, "in.csv")
    assert out.text.startswith("# from the planner\n")
    got = rows(out.text.split("\n", 1)[1])
    assert [(r["note"], r["command_ticks"]) for r in got] == [("a", "90"), ("b", "300")]


def test_joint_trajectory_in_radians() -> None:
    text = "time_s,shoulder_rad,elbow_rad\n0,0,0.1\n1,0.5,0.2\n2,-0.5,0.3\n"
    out = apply_csv(TABLE, text, "traj.csv", column="shoulder_rad", zero_deg=150, direction=-1)
    got = rows(out.text)
    assert list(got[0]) == ["time_s", "shoulder_rad", "elbow_rad", "shoulder_command_ticks"]
    expected = []
    for q in (0, 0.5, -0.5):
        servo = 150 - math.degrees(q)
        expected.append(round(450 + (servo - 150) * (4 if servo > 150 else 3)))
    assert [int(r["shoulder_command_ticks"]) for r in got] == expected


def test_radians_need_zero() -> None:
    with pytest.raises(ArmtoolError, match="servo angle at joint zero is needed"):
        apply_csv(TABLE, "time_s,shoulder_rad\n0,0\n", "t.csv")


def test_which_column() -> None:
    with pytest.raises(ArmtoolError) as info:
        apply_csv(TABLE, "a_deg,b_deg\n1,2\n", "t.csv")
    assert "which column" in info.value.what and "a_deg, b_deg" in str(info.value.hint)
    with pytest.raises(ArmtoolError, match="no column 'c_deg'"):
        apply_csv(TABLE, "a_deg,b_deg\n1,2\n", "t.csv", column="c_deg")
    with pytest.raises(ArmtoolError, match="does not state its unit"):
        apply_csv(TABLE, "angle,b\n1,2\n", "t.csv", column="angle")


def test_bad_rows_are_named() -> None:
    with pytest.raises(ArmtoolError) as info:
        apply_csv(TABLE, "angle_deg\n100\nnan\n", "t.csv")
    assert info.value.where == "t.csv:3" and "'angle_deg' is nan" in info.value.what
    with pytest.raises(ArmtoolError) as info:
        apply_csv(TABLE, "angle_deg\n100\n400\n", "t.csv")
    assert info.value.where == "t.csv:3"
