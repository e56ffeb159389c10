"""`armtool servo-lut fit`, `export` and `apply`: the commands that work on files only (no servo)."""

from __future__ import annotations

from pathlib import Path

import typer

from armtool.cli import options as opt
from armtool.cli.servo_lut.common import write_output
from armtool.console import stderr
from armtool.errors import ArmtoolError
from armtool.extras import require
from armtool.output.summary import print_summary
from armtool.servo.lut.choices import Approach, ExportFormat, Method


def fit(
    measurements: Path = typer.Argument(..., help="Measurement CSV (from `servo-lut measure` or your own)."),
    output: Path | None = typer.Option(None, "--output", "-o", help="Write the table JSON here (default: stdout)."),
    method: Method = typer.Option(Method.PCHIP, "--method", help="pchip (monotone, default), linear or poly."),
    degree: int = typer.Option(3, "--degree", min=1, max=9, help="Polynomial degree for --method poly."),
    holdout: float = typer.Option(
        0.2,
        "--holdout",
        callback=opt.finite_float(0, 1, hi_open=True),
        help="Fraction of points kept out of the fit to test it (0 = none).",
    ),
    seed: int = typer.Option(
        0, "--seed", callback=opt.seed(), help="Random seed for choosing the held-out points (any integer)."
    ),
    approach: Approach | None = typer.Option(
        None, "--approach", help="Use readings approached up, down, or the mean of both (default: what the file has)."
    ),
    model: str | None = typer.Option(
        None, "--model", help="Servo model if the CSV does not state it (AX-12A, XL430-W250, STS3215...)."
    ),
    monotone_tol: float | None = typer.Option(
        None,
        "--monotone-tol",
        callback=opt.finite_float(0, 90, unit="degrees"),
        help="Degrees a reading may step back and count as noise [default: 1 tick or 4 standard errors].",
    ),
    grid_step: float = typer.Option(
        1.0,
        "--grid-step",
        callback=opt.positive_float(360, "degrees"),
        help="Degrees between entries of the table's uniform grid (at most 65536 entries).",
    ),
) -> None:
    require("servo")  # exit 2 with the install command when the extra is missing
    from armtool.fileio import check_output_paths
    from armtool.servo.lut.csv_format import read_measurements
    from armtool.servo.lut.table import fit_table, table_json

    check_output_paths({"-o": output}, inputs=[measurements])
    meas = read_measurements(measurements, model)
    if meas.meta.get("complete") == "no":
        stderr().print(f"[yellow]warning:[/yellow] {measurements} holds the readings of an interrupted run")
    table = fit_table(
        meas, method, degree=degree, holdout=holdout, seed=seed, approach=approach, monotone_tol_deg=monotone_tol
    )
    text = table_json(table, grid_step)
    assert table.report is not None  # a fitted table has its report
    print_summary(table.report.summary(table))
    write_output(text, output, "table")


def export(
    table_path: Path = typer.Argument(..., metavar="LUT_JSON", help="Table from `servo-lut fit`."),
    output_format: ExportFormat = typer.Option(ExportFormat.C, "--format", help="c, csv, json or yaml."),
    step: float = typer.Option(
        1.0,
        "--step",
        callback=opt.positive_float(360, "degrees"),
        help="Degrees between grid entries (a whole number of hundredths for C).",
    ),
    name: str = typer.Option("servo_lut", "--name", help="C array name (macros are its upper-case form)."),
    output: Path | None = typer.Option(None, "--output", "-o", help="Write here (default: stdout)."),
) -> None:
    require("servo")  # exit 2 with the install command when the extra is missing
    from armtool.fileio import check_output_paths
    from armtool.servo.lut.export import render
    from armtool.servo.lut.table import read_table

    check_output_paths({"-o": output}, inputs=[table_path])
    table = read_table(table_path)
    write_output(render(table, output_format, step_deg=step, name=name), output, output_format.value)


def apply(
    table_path: Path = typer.Argument(..., metavar="LUT_JSON", help="Table from `servo-lut fit`."),
    input_csv: Path | None = typer.Argument(None, metavar="[CSV]", help="CSV with an angle column (- for stdin)."),
    angles: str | None = typer.Option(
        None, "--angles", help="Comma-separated servo angles in degrees, instead of a CSV."
    ),
    column: str | None = typer.Option(
        None, "--column", help="Column to convert: angle_deg, or a joint column such as shoulder_rad."
    ),
    zero_deg: float | None = typer.Option(
        None,
        "--zero-deg",
        callback=opt.finite_float(-3600, 3600, unit="degrees"),
        help="Servo angle at joint zero: the column holds joint angles (needed for *_rad).",
    ),
    direction: int = typer.Option(1, "--direction", help="1 or -1: servo angle = zero + direction * joint angle."),
    clip: bool = typer.Option(False, "--clip", help="Clamp angles outside the measured range instead of refusing."),
    output: Path | None = typer.Option(None, "--output", "-o", help="Write here (default: stdout)."),
) -> None:
    require("servo")  # exit 2 with the install command when the extra is missing
    from armtool.fileio import check_output_paths
    from armtool.servo.lut.apply import apply_csv, apply_list, read_input
    from armtool.servo.lut.table import read_table

    if direction not in (1, -1):
        raise ArmtoolError(f"--direction must be 1 or -1, got {direction}")
    if (angles is None) == (input_csv is None):
        raise ArmtoolError(
            "give either a CSV or --angles", hint="e.g. armtool servo-lut apply lut.json --angles 90,150,210"
        )
    check_output_paths({"-o": output}, inputs=[table_path, input_csv])
    table = read_table(table_path)
    if input_csv is not None:
        text, source = read_input(input_csv)
        result = apply_csv(table, text, source, column=column, zero_deg=zero_deg, direction=direction, clip=clip)
    else:
        values = [
            opt.check_float(v.strip(), f"--angles value {i + 1}", unit="degrees")
            for i, v in enumerate(str(angles).split(","))
        ]
        if zero_deg is not None:
            values = [zero_deg + direction * v for v in values]
        result = apply_list(table, values, clip=clip)
    if result.clipped:
        stderr().print(f"[yellow]{result.clipped} of {result.rows} angle(s) clamped to the measured range[/yellow]")
    write_output(result.text, output, "commands")
