"""`armtool servo-lut`: measure a servo's real angle per command, fit, export and check a
compensation table (wanted angle -> command), and apply it to angles or trajectories."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from armtool.cli import options as opt
from armtool.errors import ArmtoolError, ExitCode
from armtool.extras import require
from armtool.servo.lut.choices import Approach, ExportFormat, MeasureApproach, Method
from armtool.servo.registry import Protocol, transport_class

if TYPE_CHECKING:  # numpy and scipy load only when a subcommand runs
    from armtool.servo.bus import ServoBus
    from armtool.servo.lut.table import ErrorStats, LutTable

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


class ReportFormat(str, Enum):
    TEXT = "text"
    JSON = "json"


def _write(text: str, output: Path | None, what: str) -> None:
    from armtool.console import stderr, write_stdout
    from armtool.servo.lut.csv_format import write_atomic

    if output is None or str(output) == "-":
        write_stdout(text)
    else:
        write_atomic(output, text)
        stderr().print(f"wrote {what} {output}")


def _cell(stats: ErrorStats) -> str:
    return "-" if stats.n == 0 else f"{stats.rms_deg:.3f} / {stats.max_deg:.3f}"


def print_fit_report(table: LutTable) -> None:
    """The fit's before/after table on stderr."""
    from rich.table import Table

    from armtool.console import stderr

    report, model = table.report, table.model
    assert report is not None
    lo, hi = table.valid_range_deg
    t = Table(
        title=f"servo-lut fit: {model.name}, method {table.method.value}, approach {table.approach}, "
        f"{lo:.2f}..{hi:.2f}°",
        title_justify="left",
    )
    for col in ("points", "n", "nominal map RMS / max (°)", "with table RMS / max (°)"):
        t.add_column(col, justify="right" if col != "points" else "left")
    t.add_row("train (knots)", str(report.train), _cell(report.train_nominal), _cell(report.train_lut))
    t.add_row("held out", str(report.holdout), _cell(report.holdout_nominal), _cell(report.holdout_lut))
    stderr().print(t)
    hyst = "" if report.hysteresis_max_deg is None else f", hysteresis up/down up to {report.hysteresis_max_deg:.2f}°"
    stderr().print(
        f"raw data: {report.samples} readings at {report.points} commands, off the datasheet map by up to "
        f"{report.nominal_max_deg:.2f}°, non-linearity (deviation from the best straight line) "
        f"{report.nonlinearity_deg:.2f}°, slope {report.line_deg_per_tick:.4f}°/tick "
        f"(datasheet {model.deg_per_tick:.4f}){hyst}"
    )
    if report.pooled:
        stderr().print(
            f"{report.pooled} point(s) pooled with a neighbour: readings stepped back by less than "
            f"{report.monotone_tol_deg:.3f}° (noise)"
        )


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
    import json

    from armtool.fileio import check_output_paths
    from armtool.servo.lut.csv_format import read_measurements
    from armtool.servo.lut.table import fit_table

    check_output_paths({"-o": output}, inputs=[measurements])
    meas = read_measurements(measurements, model)
    if meas.meta.get("complete") == "no":
        from armtool.console import stderr

        stderr().print(f"[yellow]warning:[/yellow] {measurements} holds the readings of an interrupted run")
    table = fit_table(
        meas, method, degree=degree, holdout=holdout, seed=seed, approach=approach, monotone_tol_deg=monotone_tol
    )
    from armtool.servo.lut.table import check_table_document

    doc = table.to_dict(grid_step_deg=grid_step, flag="--grid-step")
    check_table_document(doc, "the fitted table")  # never write a table that would not read back
    print_fit_report(table)
    _write(json.dumps(doc, indent=2, allow_nan=False) + "\n", output, "table")


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
    _write(render(table, output_format, step_deg=step, name=name), output, output_format.value)


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
    import sys

    from armtool.console import stderr
    from armtool.servo.lut.apply import apply_csv, apply_list
    from armtool.servo.lut.table import read_table

    if direction not in (1, -1):
        raise ArmtoolError(f"--direction must be 1 or -1, got {direction}")
    if (angles is None) == (input_csv is None):
        raise ArmtoolError(
            "give either a CSV or --angles", hint="e.g. armtool servo-lut apply lut.json --angles 90,150,210"
        )
    from armtool.fileio import check_output_paths

    check_output_paths({"-o": output}, inputs=[table_path, input_csv])
    table = read_table(table_path)
    if angles is not None:
        values = []
        for i, text in enumerate(angles.split(",")):
            values.append(opt.check_float(text.strip(), f"--angles value {i + 1}", unit="degrees"))
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


# --------------------------------------------------------------------------------------------
# commands that move a servo


def _ask(text: str) -> str:
    return str(typer.prompt(text, err=True))


def _confirm(question: str, yes: bool) -> None:
    """Energising needs a yes: --yes, or an interactive answer."""
    import sys

    if yes:
        return
    if not sys.stdin.isatty():
        raise ArmtoolError(
            "this would energise a servo and no one can confirm (stdin is not a terminal)",
            hint="pass --yes for scripted use, once the workspace is clear",
        )
    if not typer.confirm(question, default=False, err=True):
        raise ArmtoolError("not confirmed: nothing was moved")


def _connect(port: str, protocol: Protocol, baud: int, sid: int, expected_model: str | None) -> ServoBus:
    from armtool.servo.bus import open_bus
    from armtool.servo.lut.csv_format import model_named

    bus = open_bus(port, protocol.value, baud, echo_check_id=sid)
    try:
        want = {sid: model_named(expected_model, "--model")} if expected_model else None
        bus.identify([sid], want)
    except BaseException:
        bus.close()
        raise
    return bus


def _range(
    bus: ServoBus,
    sid: int,
    limits: Path | None,
    lo: int | None,
    hi: int | None,
    fallback: tuple[int, int] | None = None,
) -> tuple[int, int, str]:
    """The command range to stay inside: recorded limits, --min/--max, or the fallback; never
    wider than the model's ticks or the servo's own angle-limit registers."""
    from armtool.servo.lut.measure import read_limits

    model = bus.model(sid)
    source = ""
    if limits is not None:
        lo_l, hi_l, model_name = read_limits(limits, sid)
        if model_name and model_name.lower() not in (model.name.lower(), *model.aliases):
            raise ArmtoolError(
                f"the limits for ID {sid} were recorded on a {model_name}, the servo is a {model.name}", str(limits)
            )
        lo = lo_l if lo is None else max(lo, lo_l)
        hi = hi_l if hi is None else min(hi, hi_l)
        source = f"limits {limits}"
    elif lo is None or hi is None:
        if fallback is None:
            raise ArmtoolError(
                "no range to measure in",
                hint="pass --limits limits.yaml (from `armtool limits`) or "
                "--min and --max in ticks, inside the joint's mechanical stops",
            )
        lo = fallback[0] if lo is None else lo
        hi = fallback[1] if hi is None else hi
        source = "the table's measured range"
    else:
        source = "--min/--max"
    if not 0 <= lo < hi <= model.max_tick:
        raise ArmtoolError(f"range {lo}..{hi} ticks is not inside 0..{model.max_tick} ({model.name}) with min < max")
    reg_lo, reg_hi = bus.read(sid, "min_limit"), bus.read(sid, "max_limit")
    if transport_class(model.protocol).wheel_mode_when_limits_zero and reg_lo == 0 and reg_hi == 0:
        raise ArmtoolError(f"ID {sid} is in wheel mode (both angle limits 0): it cannot hold a position")
    if lo < reg_lo or hi > reg_hi:
        lo, hi = max(lo, reg_lo), min(hi, reg_hi)
        source += f", narrowed to the servo's angle-limit registers {reg_lo}..{reg_hi}"
        if lo >= hi:
            raise ArmtoolError(f"the servo's angle limits {reg_lo}..{reg_hi} leave nothing of the range")
    return lo, hi, source


def _partial(output: Path | None) -> Path | None:
    """Where an interrupted run keeps its readings (None when -o is stdout or a device)."""
    if output is None or str(output) == "-" or (output.exists() and not output.is_file()):
        return None
    return output.with_name(output.name + ".partial")


def _csv_reference_path(spec: str) -> Path | None:
    kind, _, arg = spec.partition(":")
    return Path(arg) if kind.strip().lower() == "csv" and arg else None


def _check_reference(spec: str, bus_port: str) -> None:
    """Before anything opens: the reference is not the servo bus, and a typed one has a typist."""
    import os
    import sys

    kind, _, arg = spec.partition(":")
    kind = kind.strip().lower()
    if kind == "encoder" and arg:
        enc_port = arg.partition("@")[0]
        if os.path.realpath(enc_port) == os.path.realpath(bus_port):
            raise ArmtoolError(
                f"--reference encoder:{enc_port} is the servo bus (--port {bus_port})",
                hint="the encoder is a separate device on its own port, e.g. encoder:/dev/ttyACM1",
            )
    if kind == "manual" and not sys.stdin.isatty():
        raise ArmtoolError(
            "--reference manual asks you to type each angle, but stdin is not a terminal",
            hint="run it in a terminal, or use encoder:PORT or csv:FILE",
        )


def _check_motion_range(commands: list[int], lo: int, hi: int, backoff: int) -> None:
    """Every planned command inside the range the user gave: refused before anything moves."""
    outside = [c for c in commands if not lo <= c <= hi]
    if outside:
        raise ArmtoolError(
            f"planned commands {outside[:5]} lie outside the range {lo}..{hi} ticks",
            hint=f"with --backoff {backoff} the points must leave room inside --min/--max",
        )


def _progress(enabled: bool):  # type: ignore[no-untyped-def]
    from contextlib import nullcontext

    if not enabled:
        return nullcontext(None)
    from armtool.console import progress_bar

    return progress_bar(label_width=0)


@app.command(
    "measure",
    help="Step a servo through its range and log command, present position, reference angle, "
    "load, temperature and voltage to a measurement CSV. Energises the servo (asks first).",
)
def measure(
    port: str = typer.Option(..., "--port", help="Serial port of the servo bus (e.g. /dev/ttyUSB0)."),
    sid: int = typer.Option(..., "--id", min=0, max=252, help="Servo ID (0..252)."),
    reference: str = typer.Option(..., "--reference", help="encoder:PORT[@BAUD], manual, csv:FILE or camera:DEVICE."),
    output: Path | None = typer.Option(None, "--output", "-o", help="Measurement CSV to write (default: stdout)."),
    protocol: Protocol = typer.Option(
        Protocol.DXL1, "--protocol", help="dxl1 (AX), dxl2 (X series) or feetech (STS/SCS)."
    ),
    baud: int = typer.Option(1_000_000, "--baud", callback=opt.baud(), help="Bus baud rate."),
    model: str | None = typer.Option(None, "--model", help="Refuse unless the servo is this model."),
    limits: Path | None = typer.Option(
        None, "--limits", help="Limits YAML from `armtool limits`: measure inside safe_min/max_ticks."
    ),
    lo: int | None = typer.Option(
        None, "--min", callback=opt.ticks(), help="Lowest command in ticks (inside the mechanical stop)."
    ),
    hi: int | None = typer.Option(
        None, "--max", callback=opt.ticks(), help="Highest command in ticks (inside the mechanical stop)."
    ),
    points: int | None = typer.Option(
        None, "--points", callback=opt.int_range(2, 4096), help="Number of commands, evenly spaced [default: 32]."
    ),
    step: int | None = typer.Option(
        None, "--step", callback=opt.int_range(1, 4095, "ticks"), help="Ticks between commands (instead of --points)."
    ),
    approach: MeasureApproach = typer.Option(
        MeasureApproach.UP, "--approach", help="Reach each point moving up, down, or both (records hysteresis)."
    ),
    backoff: int | None = typer.Option(
        None,
        "--backoff",
        callback=opt.int_range(1, 4095, "ticks"),
        help="Ticks to back off before approaching a point [default: ~3°].",
    ),
    reads: int = typer.Option(3, "--reads", callback=opt.int_range(1, 100), help="Reference readings per point."),
    sweeps: int = typer.Option(1, "--sweeps", callback=opt.int_range(1, 100), help="Times to go through all points."),
    speed: float = typer.Option(
        60.0,
        "--speed",
        callback=opt.positive_float(10_000, "degrees per second"),
        help="Moving speed, degrees per second.",
    ),
    torque_limit: float = typer.Option(
        50.0, "--torque-limit", callback=opt.percent(), help="RAM torque limit in percent (restored afterwards)."
    ),
    dwell: float = typer.Option(
        0.15,
        "--dwell",
        callback=opt.seconds(60, allow_zero=True),
        help="Seconds to wait after the servo stops before reading.",
    ),
    settle_timeout: float = typer.Option(
        3.0,
        "--settle-timeout",
        callback=opt.finite_float(0.1, 600, unit="seconds"),
        help="Seconds to wait for a point to settle.",
    ),
    yes: bool = typer.Option(False, "--yes", "-y", help="Do not ask before energising the servo."),
) -> None:
    require("servo")  # exit 2 with the install command when the extra is missing
    import time

    from rich.markup import escape

    from armtool.console import stderr
    from armtool.fileio import check_output_paths, rescue_write
    from armtool.servo.guard import TorqueGuard
    from armtool.servo.lut.csv_format import Sample, render_measurements
    from armtool.servo.lut.measure import (
        Driver,
        Motion,
        align_reference,
        plan_commands,
        speed_register,
        torque_register,
    )
    from armtool.servo.lut.measure import measure as run_measure
    from armtool.servo.reference import CsvReference, ManualReference, open_reference

    if points is not None and step is not None:
        raise ArmtoolError("give --points or --step, not both")
    _check_reference(reference, port)
    # every output checked before the servo moves: readings are never lost to an unwritable -o
    check_output_paths(
        {"-o": output, "-o (readings of an interrupted run)": _partial(output)},
        inputs=[limits, _csv_reference_path(reference)],
    )
    ref = open_reference(reference, ask=_ask)
    samples: list[Sample] = []
    bus = None
    meta: dict[str, str] = {}
    try:
        bus = _connect(port, protocol, baud, sid, model)
        servo_model = bus.model(sid)
        r_lo, r_hi, range_source = _range(bus, sid, limits, lo, hi)
        b = backoff if backoff is not None else max(1, round(3.0 / servo_model.deg_per_tick))
        if isinstance(ref, CsvReference):
            commands = ref.commands
            outside = [c for c in commands if not r_lo <= c <= r_hi]
            if outside:
                raise ArmtoolError(
                    f"the reference file has commands outside the range {r_lo}..{r_hi}: {outside[:5]}", str(ref.path)
                )
            reads = 1
        else:
            commands = plan_commands(r_lo, r_hi, approach.value, b, points, step)
        _check_motion_range(commands, r_lo, r_hi, b)
        deg = servo_model.deg_per_tick
        stderr().print(
            f"ID {sid}: {servo_model.name} on {port}; {len(commands)} points {commands[0]}..{commands[-1]} ticks "
            f"({commands[0] * deg:.1f}..{commands[-1] * deg:.1f}°) inside {r_lo}..{r_hi} ({range_source}), "
            f"approach {approach.value}, reference {ref.spec}"
        )
        _confirm(f"Energise servo {sid} and move it through this range? Clear the workspace first.", yes)
        meta = {
            "servo_id": str(sid),
            "servo_model": servo_model.name,
            "reference": ref.spec,
            "port": port,
            "range_ticks": f"{r_lo}..{r_hi} ({range_source})",
            "backoff_ticks": str(b),
            "started": time.strftime("%Y-%m-%dT%H:%M:%S"),
        }
        cap = torque_register(servo_model, torque_limit)
        motion = Motion(
            backoff_ticks=b,
            settle_timeout_s=settle_timeout,
            dwell_s=dwell,
            tolerance_ticks=servo_model.settle_ticks,
            torque_cap=cap / servo_model.reg("torque_limit").hi,
        )
        t0 = time.monotonic()
        with TorqueGuard(bus) as guard, _progress(not isinstance(ref, ManualReference)) as bar:
            guard.set_ram(sid, "moving_speed", speed_register(servo_model, speed))
            guard.set_ram(sid, "torque_limit", cap)
            guard.torque_on(sid)
            driver = Driver(bus, guard, sid, motion, bounds=(r_lo, r_hi))
            note = align_reference(driver, ref, r_lo, r_hi, "down" if approach.value == "down" else "up")
            if note is not None:
                meta["reference_alignment"] = note
                stderr().print(f"{ref.spec} aligned to the servo: {note}")
            task = bar.add_task("measuring", total=len(commands)) if bar is not None else None
            run_measure(
                driver,
                ref,
                commands,
                approach.value,
                r_lo,
                r_hi,
                reads=reads,
                sweeps=sweeps,
                on_sample=samples.append,
                progress=(lambda k, n: bar.update(task, completed=k, total=n)) if bar is not None else None,
            )
        unsettled = sum(1 for s in samples if s.settled is False)
        stderr().print(
            f"measured {len(samples)} readings at {len(commands)} points in {time.monotonic() - t0:.1f} s"
            + (f"; {unsettled} reading(s) taken before the servo settled" if unsettled else "")
            + "; torque off"
        )
    except BaseException:
        if samples and output is not None:
            partial = rescue_write(output, render_measurements({**meta, "complete": "no"}, samples), "armtool-measure")
            stderr().print(f"wrote the readings so far to {escape(str(partial))}")
        raise
    finally:
        ref.close()
        if bus is not None:
            bus.close()
    text = render_measurements(meta, samples)
    try:
        _write(text, output, "measurements")
    except ArmtoolError as exc:  # the servo has moved: keep what it measured
        saved = rescue_write(output, text, "armtool-measure")
        raise ArmtoolError(f"{exc.what}; the readings were saved to {saved}", exc.where, exc.hint) from None
    if output is not None:
        stderr().print(f"next: armtool servo-lut fit {output} -o lut.json")


@app.command(
    "check",
    help="Command random angles (not table knots) through the table and through the nominal linear "
    "map, measure both with the reference, print both errors; exit 1 above --max-err.",
)
def check(
    table_path: Path = typer.Argument(..., metavar="LUT_JSON", help="Table from `servo-lut fit`."),
    port: str = typer.Option(..., "--port", help="Serial port of the servo bus."),
    sid: int = typer.Option(..., "--id", min=0, max=252, help="Servo ID (0..252)."),
    reference: str = typer.Option(..., "--reference", help="encoder:PORT[@BAUD], manual or camera:DEVICE."),
    protocol: Protocol = typer.Option(Protocol.DXL1, "--protocol", help="dxl1, dxl2 or feetech."),
    baud: int = typer.Option(1_000_000, "--baud", callback=opt.baud(), help="Bus baud rate."),
    limits: Path | None = typer.Option(
        None, "--limits", help="Limits YAML [default: the table's measured command range]."
    ),
    lo: int | None = typer.Option(None, "--min", callback=opt.ticks(), help="Lowest command in ticks."),
    hi: int | None = typer.Option(None, "--max", callback=opt.ticks(), help="Highest command in ticks."),
    n: int = typer.Option(25, "--n", callback=opt.int_range(1, 1000), help="Number of random angles."),
    seed: int = typer.Option(0, "--seed", callback=opt.seed(), help="Random seed for the angles (any integer)."),
    max_err: float = typer.Option(
        0.5,
        "--max-err",
        callback=opt.finite_float(0, 360, unit="degrees"),
        help="Exit 1 when the table's largest error exceeds this (degrees).",
    ),
    reads: int = typer.Option(
        3, "--reads", callback=opt.int_range(1, 100), help="Reference readings averaged per point."
    ),
    speed: float = typer.Option(
        60.0,
        "--speed",
        callback=opt.positive_float(10_000, "degrees per second"),
        help="Moving speed, degrees per second.",
    ),
    torque_limit: float = typer.Option(
        50.0, "--torque-limit", callback=opt.percent(), help="RAM torque limit in percent (restored afterwards)."
    ),
    dwell: float = typer.Option(
        0.15,
        "--dwell",
        callback=opt.seconds(60, allow_zero=True),
        help="Seconds to wait after the servo stops before reading.",
    ),
    output_format: ReportFormat = typer.Option(ReportFormat.TEXT, "--format", help="text or json on stdout."),
    yes: bool = typer.Option(False, "--yes", "-y", help="Do not ask before energising the servo."),
) -> None:
    require("servo")  # exit 2 with the install command when the extra is missing
    import json

    from armtool.console import stderr, write_stdout
    from armtool.servo.guard import TorqueGuard
    from armtool.servo.lut.measure import Driver, Motion, align_reference, check_angles, speed_register, torque_register
    from armtool.servo.lut.measure import check as run_check
    from armtool.servo.lut.table import read_table
    from armtool.servo.reference import CsvReference, ManualReference, open_reference

    _check_reference(reference, port)
    table = read_table(table_path)
    bus = _connect(port, protocol, baud, sid, None)
    ref = None
    try:
        servo_model = bus.model(sid)
        if servo_model.name != table.model.name:
            raise ArmtoolError(
                f"{table_path} was made for a {table.model.name}, but ID {sid} is a {servo_model.name}",
                f"{table_path}: servo.model",
                hint="measure and fit a table on this servo",
            )
        knots = (int(min(table.knots_ticks)), int(max(table.knots_ticks)))
        same_servo = table.servo_id is not None and table.servo_id == sid
        if not same_servo and limits is None and (lo is None or hi is None):
            measured_on = f"ID {table.servo_id}" if table.servo_id is not None else "an unnamed servo"
            raise ArmtoolError(
                f"{table_path} was measured on {measured_on}, not ID {sid}: its command range "
                f"{knots[0]}..{knots[1]} says nothing about this joint's stops",
                f"{table_path}: servo.id",
                hint="pass --limits limits.yaml (from `armtool limits`) or --min and --max in ticks",
            )
        torque = torque_register(servo_model, torque_limit)
        r_lo, r_hi, _ = _range(bus, sid, limits, lo, hi, fallback=knots if same_servo else None)
        ref = open_reference(reference, ask=_ask)
        if isinstance(ref, CsvReference):
            raise ArmtoolError("check needs a live reference (encoder, manual or camera), not a file")
        angles = check_angles(table, n, seed, r_lo, r_hi)
        b = max(1, round(3.0 / servo_model.deg_per_tick))
        _check_motion_range([int(table.command_ticks([a])[0]) for a in angles], r_lo, r_hi, 0)
        _confirm(f"Energise servo {sid} and move it to {n} angles between ticks {r_lo} and {r_hi}?", yes)
        motion = Motion(
            backoff_ticks=b,
            dwell_s=dwell,
            tolerance_ticks=servo_model.settle_ticks,
            torque_cap=torque / servo_model.reg("torque_limit").hi,
        )
        with TorqueGuard(bus) as guard, _progress(not isinstance(ref, ManualReference)) as bar:
            guard.set_ram(sid, "moving_speed", speed_register(servo_model, speed))
            guard.set_ram(sid, "torque_limit", torque)
            guard.torque_on(sid)
            driver = Driver(bus, guard, sid, motion, bounds=(r_lo, r_hi))
            align_reference(driver, ref, r_lo, r_hi, "down" if table.approach == "down" else "up")
            task = bar.add_task("checking", total=n) if bar is not None else None
            result = run_check(
                driver,
                ref,
                table,
                angles,
                r_lo,
                r_hi,
                reads=reads,
                progress=(lambda k, t: bar.update(task, completed=k, total=t)) if bar is not None else None,
            )
    finally:
        if ref is not None:
            ref.close()
        bus.close()
    if output_format is ReportFormat.JSON:
        write_stdout(json.dumps(result.to_dict(), indent=2))
    else:
        lines = [
            f"{'':8} {'RMS (°)':>8} {'max (°)':>8}",
            f"{'nominal':8} {result.nominal['rms_deg']:8.3f} {result.nominal['max_deg']:8.3f}",
            f"{'table':8} {result.lut['rms_deg']:8.3f} {result.lut['max_deg']:8.3f}",
            f"({len(result.points)} random angles, not knots; error = measured - wanted)",
        ]
        write_stdout("\n".join(lines))
    if result.lut["max_deg"] > max_err:
        stderr().print(f"[red]table error {result.lut['max_deg']:.3f}° is above --max-err {max_err:g}°[/red]")
        raise typer.Exit(ExitCode.FINDINGS)
