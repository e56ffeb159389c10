"""The measurement CSV: units in column names, metadata, and refusals that name the row and field."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from armtool.errors import ArmtoolError
from armtool.servo.lut.csv_format import Sample, parse_measurements, read_measurements, render_measurements

FIXTURE = Path(__file__).resolve().parents[2] / "fixtures" / "servo" / "lut" / "ax12a_meas.csv"
HEAD = "# servo_model: AX-12A\n# servo_id: 3\n# reference: encoder:/dev/ttyACM1\n"


def parse(body: str, head: str = HEAD, model: str | None = None):  # type: ignore[no-untyped-def]
    return parse_measurements(head + body, "m.csv", model)


def error(body: str, head: str = HEAD) -> ArmtoolError:
    with pytest.raises(ArmtoolError) as info:
        parse(body, head)
    return info.value


def test_fixture_reads_with_metadata() -> None:
    meas = read_measurements(FIXTURE)
    assert meas.model.name == "AX-12A" and meas.servo_id == 1 and meas.reference.startswith("encoder:")
    assert len(meas.samples) == 51 * 3
    first = meas.samples[0]
    assert (first.line, first.command_ticks, first.approach, first.repeat) == (7, 101, "up", 0)


def test_minimal_file_and_radians() -> None:
    meas = parse("command_ticks,reference_rad\n100,0.5\n200,1.0\n")
    assert [s.reference_deg for s in meas.samples] == pytest.approx([math.degrees(0.5), math.degrees(1.0)])
    assert meas.samples[0].present_ticks is None and meas.samples[0].approach == "up"


def test_missing_columns_are_named() -> None:
    exc = error("command_ticks,present_ticks\n100,100\n")
    assert "missing column reference_deg" in exc.what and "m.csv:4" == exc.where
    assert "found: command_ticks, present_ticks" in str(exc.hint)


@pytest.mark.parametrize(
    "column, wanted",
    [
        ("reference", "reference_deg"),
        ("load", "load_pct"),
        ("angle", "reference_deg"),
        ("temperature", "temperature_c"),
    ],
)
def test_column_without_unit_is_refused(column: str, wanted: str) -> None:
    exc = error(f"command_ticks,reference_deg,{column}\n100,30,1\n")
    assert "does not state its unit" in exc.what and wanted in str(exc.hint)


def test_unknown_unit_is_refused() -> None:
    exc = error("command_ticks,reference_grad\n100,30\n")
    assert "unit 'grad' not understood" in exc.what and "reference_deg or reference_rad" in str(exc.hint)


@pytest.mark.parametrize("value", ["nan", "NaN", "inf"])
def test_nan_names_line_and_field(value: str) -> None:
    exc = error(f"command_ticks,reference_deg,temperature_c\n100,30,35\n116,{value},35\n")
    assert exc.where == "m.csv:6" and "'reference_deg'" in exc.what


def test_nan_in_optional_field_is_refused_too() -> None:
    exc = error("command_ticks,reference_deg,voltage_v\n100,30,nan\n")
    assert exc.where == "m.csv:5" and "'voltage_v'" in exc.what


def test_empty_required_field_and_text() -> None:
    assert "empty 'reference_deg'" in error("command_ticks,reference_deg\n100,\n").what
    assert "not a number: 'abc'" in error("command_ticks,reference_deg\nabc,3\n").what


def test_command_must_be_whole_tick_in_range() -> None:
    assert "0..1023 (AX-12A)" in error("command_ticks,reference_deg\n1100,30\n").what
    assert "not a whole tick" in error("command_ticks,reference_deg\n100.5,30\n").what


def test_duplicated_command_names_both_lines() -> None:
    exc = error("command_ticks,reference_deg,approach,repeat\n100,30,up,0\n116,35,up,0\n100,30.1,up,0\n")
    assert "duplicated command 100" in exc.what and "first at line 5" in exc.what and exc.where == "m.csv:7"


def test_same_command_other_approach_is_not_a_duplicate() -> None:
    meas = parse("command_ticks,reference_deg,approach,repeat\n100,30,up,0\n100,30.4,down,0\n")
    assert [s.approach for s in meas.samples] == ["up", "down"]


def test_bad_approach_and_short_row() -> None:
    assert "neither 'up' nor 'down'" in error("command_ticks,reference_deg,approach\n100,30,left\n").what
    assert "row has 1 fields" in error("command_ticks,reference_deg\n100\n").what


def test_model_must_be_stated_or_given() -> None:
    exc = error("command_ticks,reference_deg\n100,30\n", head="")
    assert "servo model is not stated" in exc.what and "--model" in str(exc.hint)
    assert parse("command_ticks,reference_deg\n100,30\n", head="", model="xl430").model.name == "XL430-W250"
    assert (
        "unknown servo model 'AX-99'"
        in error("command_ticks,reference_deg\n100,30\n", head="# servo_model: AX-99\n").what
    )


def test_no_rows_and_no_header() -> None:
    assert "no measurement rows" in error("command_ticks,reference_deg\n").what
    assert "no header row" in error("").what


def test_render_parse_round_trip() -> None:
    samples = [
        Sample(0, 100, 29.5, 101.0, -2.5, 34.0, 12.1, "up", 0, True),
        Sample(0, 116, 34.25, None, None, None, None, "down", 1, None),
    ]
    text = render_measurements({"servo_model": "AX-12A", "servo_id": "2", "reference": "manual"}, samples)
    back = parse_measurements(text, "x.csv")
    assert back.servo_id == 2 and back.reference == "manual"
    got = [
        (s.command_ticks, s.reference_deg, s.present_ticks, s.load_pct, s.approach, s.repeat, s.settled)
        for s in back.samples
    ]
    assert got == [(100, 29.5, 101.0, -2.5, "up", 0, True), (116, 34.25, None, None, "down", 1, None)]
