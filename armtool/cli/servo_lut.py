"""`armtool servo-lut`: measure a servo's real angle per command, fit, export and check a
compensation table (wanted angle -> command), and apply it to angles or trajectories."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import Optional

import typer

from armtool.errors import ArmtoolError, ExitCode

HELP = "Build, export and check compensation tables for a servo's non-linear response."

app = typer.Typer(name="servo-lut", help=HELP, no_args_is_help=True, add_completion=False,
                  pretty_exceptions_enable=False, context_settings={"help_option_names": ["-h", "--help"]})

MEAS_FORMAT = """Measurement CSV: '# key: value' metadata lines (servo_model: AX-12A, servo_id, reference), then a header
with units in the column names: command_ticks,present_ticks,reference_deg,load_pct,temperature_c,voltage_v,approach,repeat.
command_ticks and reference_deg (or reference_rad, servo frame: 0° at tick 0) are required."""


class MethodOption(str, Enum):
    PCHIP = "pchip"
    LINEAR = "linear"
    POLY = "poly"


class ApproachChoice(str, Enum):
    UP = "up"
    DOWN = "down"
    MEAN = "mean"


class ExportFormatOption(str, Enum):
    C = "c"
    CSV = "csv"
    JSON = "json"
    YAML = "yaml"


class ReportFormat(str, Enum):
    TEXT = "text"
    JSON = "json"


def _write(text: str, output: Optional[Path], what: str) -> None:
    from armtool.console import stderr, write_stdout
    from armtool.servo.lut_meas import write_atomic

    if output is None or str(output) == "-":
        write_stdout(text)
    else:
        write_atomic(output, text)
        stderr().print(f"wrote {what} {output}")


def _stats_row(label: str, nominal: object, lut: object) -> list[str]:
    def cell(s: object) -> str:
        rms, mx, n = getattr(s, "rms_deg"), getattr(s, "max_deg"), getattr(s, "n")
        return "-" if n == 0 else f"{rms:.3f} / {mx:.3f}"

    return [label, str(getattr(nominal, "n")), cell(nominal), cell(lut)]


def print_fit_report(table: object) -> None:
    """The fit's before/after table on stderr."""
    from rich.table import Table

    from armtool.console import stderr

    report = getattr(table, "report")
    model = getattr(table, "model")
    lo, hi = getattr(table, "valid_range_deg")
    t = Table(title=f"servo-lut fit: {model.name}, method {getattr(table, 'method').value}, approach "
                    f"{getattr(table, 'approach')}, {lo:.2f}..{hi:.2f}°", title_justify="left")
    for col in ("points", "n", "nominal map RMS / max (°)", "with table RMS / max (°)"):
        t.add_column(col, justify="right" if col != "points" else "left")
    t.add_row(*_stats_row("train (knots)", report.train_nominal, report.train_lut))
    t.add_row(*_stats_row("held out", report.holdout_nominal, report.holdout_lut))
    stderr().print(t)
    hyst = "" if report.hysteresis_max_deg is None else f", hysteresis up/down up to {report.hysteresis_max_deg:.2f}°"
    stderr().print(f"raw data: {report.samples} readings at {report.points} commands, off the datasheet map by up to "
                   f"{report.nominal_max_deg:.2f}°, non-linearity (deviation from the best straight line) "
                   f"{report.nonlinearity_deg:.2f}°, slope {report.line_deg_per_tick:.4f}°/tick "
                   f"(datasheet {model.deg_per_tick:.4f}){hyst}")
    if report.pooled:
        stderr().print(f"{report.pooled} point(s) pooled with a neighbour: readings stepped back by less than "
                       f"{report.monotone_tol_deg:.3f}° (noise)")


@app.command("fit", help="Fit the table (wanted angle -> command) from a measurement CSV.\n\n" + MEAS_FORMAT)
def fit(
    measurements: Path = typer.Argument(..., help="Measurement CSV (from `servo-lut measure` or your own)."),
    output: Optional[Path] = typer.Option(None, "--output", "-o", help="Write the table JSON here (default: stdout)."),
    method: MethodOption = typer.Option(MethodOption.PCHIP, "--method", help="pchip (monotone, default), linear or poly."),
    degree: int = typer.Option(3, "--degree", min=1, max=9, help="Polynomial degree for --method poly."),
    holdout: float = typer.Option(0.2, "--holdout", help="Fraction of points kept out of the fit to test it (0 = none)."),
    seed: int = typer.Option(0, "--seed", help="Random seed for choosing the held-out points."),
    approach: Optional[ApproachChoice] = typer.Option(None, "--approach", help="Use readings approached up, down, or the mean of both (default: what the file has)."),
    model: Optional[str] = typer.Option(None, "--model", help="Servo model if the CSV does not state it (AX-12A, XL430-W250, STS3215...)."),
    monotone_tol: Optional[float] = typer.Option(None, "--monotone-tol", help="Degrees a reading may step back and count as noise [default: 1 tick or 4 standard errors]."),
    grid_step: float = typer.Option(1.0, "--grid-step", help="Degrees between entries of the table's uniform grid."),
) -> None:
    import json

    from armtool.servo.lut import Approach, Method, fit_table
    from armtool.servo.lut_meas import read_measurements

    meas = read_measurements(measurements, model)
    table = fit_table(meas, Method(method.value), degree=degree, holdout=holdout, seed=seed,
                      approach=None if approach is None else Approach(approach.value), monotone_tol_deg=monotone_tol)
    doc = table.to_dict(grid_step_deg=grid_step)
    print_fit_report(table)
    _write(json.dumps(doc, indent=2) + "\n", output, "table")


@app.command("export", help="Write the table as a C header (uint16_t on a uniform angle grid), CSV, JSON or YAML.")
def export(
    table_path: Path = typer.Argument(..., metavar="LUT_JSON", help="Table from `servo-lut fit`."),
    output_format: ExportFormatOption = typer.Option(ExportFormatOption.C, "--format", help="c, csv, json or yaml."),
    step: float = typer.Option(1.0, "--step", help="Degrees between grid entries (a whole number of hundredths for C)."),
    name: str = typer.Option("servo_lut", "--name", help="C array name (macros are its upper-case form)."),
    output: Optional[Path] = typer.Option(None, "--output", "-o", help="Write here (default: stdout)."),
) -> None:
    from armtool.servo.lut import read_table
    from armtool.servo.lut_export import ExportFormat, render

    table = read_table(table_path)
    _write(render(table, ExportFormat(output_format.value), step_deg=step, name=name), output, output_format.value)


@app.command("apply", help="Turn wanted servo angles (a list, or a CSV column) into compensated commands.")
def apply(
    table_path: Path = typer.Argument(..., metavar="LUT_JSON", help="Table from `servo-lut fit`."),
    input_csv: Optional[Path] = typer.Argument(None, metavar="[CSV]", help="CSV with an angle column (- for stdin)."),
    angles: Optional[str] = typer.Option(None, "--angles", help="Comma-separated servo angles in degrees, instead of a CSV."),
    column: Optional[str] = typer.Option(None, "--column", help="Column to convert: angle_deg, or a joint column such as shoulder_rad."),
    zero_deg: Optional[float] = typer.Option(None, "--zero-deg", help="Servo angle at joint zero: the column holds joint angles (needed for *_rad)."),
    direction: int = typer.Option(1, "--direction", help="1 or -1: servo angle = zero + direction * joint angle."),
    clip: bool = typer.Option(False, "--clip", help="Clamp angles outside the measured range instead of refusing."),
    output: Optional[Path] = typer.Option(None, "--output", "-o", help="Write here (default: stdout)."),
) -> None:
    import sys

    from armtool.console import stderr
    from armtool.servo.lut import read_table
    from armtool.servo.lut_apply import apply_csv, apply_list

    if direction not in (1, -1):
        raise ArmtoolError(f"--direction must be 1 or -1, got {direction}")
    if (angles is None) == (input_csv is None):
        raise ArmtoolError("give either a CSV or --angles", hint="e.g. armtool servo-lut apply lut.json --angles 90,150,210")
    table = read_table(table_path)
    if angles is not None:
        values = []
        for i, text in enumerate(angles.split(",")):
            try:
                values.append(float(text))
            except ValueError:
                raise ArmtoolError(f"not a number: {text.strip()!r}", f"--angles value {i + 1}") from None
        if zero_deg is not None:
            values = [zero_deg + direction * v for v in values]
        result = apply_list(table, values, clip=clip)
    else:
        assert input_csv is not None
        if str(input_csv) == "-":
            text, source = sys.stdin.read(), "<stdin>"
        else:
            try:
                text, source = input_csv.read_text(encoding="utf-8-sig"), str(input_csv)
            except FileNotFoundError:
                raise ArmtoolError(f"no such file: {input_csv}") from None
            except (OSError, UnicodeDecodeError) as exc:
                raise ArmtoolError(f"cannot read {input_csv}: {exc}") from None
        result = apply_csv(table, text, source, column=column, zero_deg=zero_deg, direction=direction, clip=clip)
    if result.clipped:
        stderr().print(f"[yellow]{result.clipped} of {result.rows} angle(s) clamped to the measured range[/yellow]")
    _write(result.text, output, "commands")
