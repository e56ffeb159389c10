"""CSV readers: what the csv module refuses (a 200 kB field) is an input error at
file:line in every reader of trajectories, waypoints and servo measurements, never an internal error."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from armtool.csvrows import csv_rows
from armtool.errors import ArmtoolError

HUGE = "1" * 200_000


def test_rows_carry_the_line_they_start_on() -> None:
    lines = ["a,b", "1,2", "", '"x', 'y",3', "4,5"]
    assert csv_rows(lines, "f.csv", first_line=3) == [
        (3, ["a", "b"]),
        (4, ["1", "2"]),
        (5, []),
        (6, ["x\ny", "3"]),
        (8, ["4", "5"]),
    ]


def test_what_the_csv_module_refuses_is_an_input_error_at_its_line() -> None:
    with pytest.raises(ArmtoolError) as info:
        csv_rows(["time_s,j1_rad", "0,0", f'1,"{HUGE}"'], "t.csv", 1, "trajectory CSV")
    assert "a field longer than 131072 characters" in info.value.what and info.value.what.startswith(
        "trajectory CSV cannot be read as CSV"
    )
    assert info.value.where == "t.csv:3" and info.value.hint


def _trajectory(path: Path) -> object:
    from armtool.traj.formats import read_trajectory

    path.write_text(f"# comment\ntime_s,j1_rad\n0,0\n1,{HUGE}\n")
    return read_trajectory(path)


def _waypoints(path: Path) -> object:
    from armtool.traj.plan import waypoint_segments

    path.write_text(f"# poses\nx_m,y_m,z_m\n0.1,0.2,0.3\n0.1,0.2,{HUGE}\n")
    return waypoint_segments(path, np.eye(4))


def _measurements(path: Path) -> object:
    from armtool.servo.lut.csv_format import read_measurements

    path.write_text(f"# servo_model: AX-12A\ncommand_ticks,reference_deg\n512,0\n600,{HUGE}\n")
    return read_measurements(path)


def _angles(path: Path) -> object:
    from armtool.servo.lut.apply import apply_csv

    path.write_text(f"# angles\nangle_deg\n10\n{HUGE}\n")
    return apply_csv(None, path.read_text(), str(path))  # type: ignore[arg-type]  # fails before the table is used


def _reference(path: Path) -> object:
    from armtool.servo.reference import CsvReference

    path.write_text(f"# protractor\ncommand_ticks,reference_deg\n512,0\n600,{HUGE}\n")
    return CsvReference.load(path)


@pytest.mark.parametrize("reader", [_trajectory, _waypoints, _measurements, _angles, _reference])
def test_every_csv_reader_refuses_a_200_kB_field_at_file_and_line(
    tmp_path: Path, reader: Callable[[Path], object]
) -> None:
    path = tmp_path / "input.csv"
    with pytest.raises(ArmtoolError) as info:
        reader(path)
    assert "a field longer than 131072 characters" in info.value.what
    assert info.value.where == f"{path}:4"
