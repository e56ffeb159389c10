"""`armtool servo-lut`: measure a servo's real angle per command, fit, export and check a
compensation table (wanted angle -> command), and apply it to angles or trajectories."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import typer

from armtool.cli import options as opt
from armtool.console import stderr
from armtool.errors import ArmtoolError
from armtool.extras import require
from armtool.servo.lut.choices import Approach, ExportFormat, Method

if TYPE_CHECKING:  # numpy and scipy load only when a subcommand runs
    from rich.table import Table

    from armtool.servo.summary import Summary

HELP = "Build, export and check compensation tables for a servo's non-linear response."

app = typer.Typer(
    name="servo-lut",
    help=HELP,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)

MEAS_FORMAT = """Measurement CSV: '# key: value' metadata lines (servo_model: AX-12A, servo_id, reference), then a header
with units in the column names: command_ticks,present_ticks,reference_deg,load_pct,temperature_c,voltage_v,approach,repeat.
command_ticks and reference_deg (or reference_rad, servo frame: 0° at tick 0) are required."""


def write_output(text: str, output: Path | None, what: str, rescue: str | None = None) -> None:
    """To -o or stdout. With `rescue` (the servo has moved), a failed write keeps the text in a spare file."""
    from armtool.console import write_stdout
    from armtool.fileio import rescue_write
    from armtool.servo.lut.csv_format import write_atomic

    if output is None or str(output) == "-":
        write_stdout(text)
        return
    try:
        write_atomic(output, text)
    except ArmtoolError as exc:
        if rescue is None:
            raise
        saved = rescue_write(output, text, rescue)
        raise ArmtoolError(f"{exc.what}; the readings were saved to {saved}", exc.where, exc.hint) from None
    stderr().print(f"wrote {what} {output}")


def summary_table(summary: Summary) -> Table:
    """A core-built table as rich draws it."""
    from rich.table import Table
    from rich.text import Text

    table = Table(title=Text(summary.title), title_justify="left")
    for col in summary.columns:
        table.add_column(col, justify="left" if col in summary.left else "right", no_wrap=col in summary.no_wrap)
    for row in summary.rows:
        table.add_row(*(Text(cell) if isinstance(cell, str) else Text.assemble(*cell) for cell in row))
    return table


def print_summary(summary: Summary) -> None:
    """A core-built table, and its notes, on stderr."""
    stderr().print(summary_table(summary))
    from armtool.console import say

    for note in summary.notes:
        say(note)


@app.command("fit", help="Fit the table (wanted angle -> command) from a measurement CSV.\n\n" + MEAS_FORMAT)
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


@app.command("export", help="Write the table as a C header (uint16_t on a uniform angle grid), CSV, JSON or YAML.")
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


@app.command("apply", help="Turn wanted servo angles (a list, or a CSV column) into compensated commands.")
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


from armtool.cli import servo_lut_move  # noqa: E402, F401  (registers `measure` and `check` on `app`)
