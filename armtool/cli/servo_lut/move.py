"""`armtool servo-lut measure` and `check`: the two servo-lut commands that energise a servo.
The session (connect, range, energise, run) is
`armtool.servo.lut.session`, this module only asks, prints and exits."""

from __future__ import annotations

import json
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from armtool.cli import options as opt
from armtool.cli.servo_lut.common import write_output
from armtool.console import say, stderr
from armtool.errors import ArmtoolError, ExitCode
from armtool.extras import require
from armtool.servo.lut.choices import MeasureApproach, ReportFormat
from armtool.servo.registry import Protocol

if TYPE_CHECKING:  # numpy loads only when a command runs
    from armtool.servo.lut.session import Hooks

LIVE_REF = "encoder:PORT[@BAUD], manual or camera:DEVICE."
SPEED, TORQUE = "Moving speed, degrees per second.", "RAM torque limit in percent (restored afterwards)."
DWELL = "Seconds to wait after the servo stops before reading."
YES = "Do not ask before energising the servo."


def _confirm(question: str, yes: bool) -> None:
    """Energising needs a yes: --yes, or an interactive answer."""
    if yes:
        return
    if not sys.stdin.isatty():
        raise ArmtoolError(
            "this would energise a servo and no one can confirm (stdin is not a terminal)",
            hint="pass --yes for scripted use, once the workspace is clear",
        )
    if not typer.confirm(question, default=False, err=True):
        raise ArmtoolError("not confirmed: nothing was moved")


@contextmanager
def _progress(shown: bool, label: str, total: int) -> Iterator[Callable[[int, int], None] | None]:
    """A progress bar on stderr (not while someone types readings); yields its update function."""
    if not shown:
        yield None
        return
    from armtool.console import progress_bar

    with progress_bar(label_width=0) as bar:
        task = bar.add_task(label, total=total)
        yield lambda done, n: bar.update(task, completed=done, total=n)


def _hooks(yes: bool) -> Hooks:
    from armtool.servo.lut.session import Hooks

    return Hooks(
        ask=lambda text: str(typer.prompt(text, err=True)),
        confirm=lambda question: _confirm(question, yes),
        note=say,
        progress=_progress,
    )


def measure(
    port: str = opt.servo_port("Serial port of the servo bus (e.g. /dev/ttyUSB0)."),
    sid: int = opt.servo_id(),
    reference: str = typer.Option(..., "--reference", help="encoder:PORT[@BAUD], manual, csv:FILE or camera:DEVICE."),
    output: Path | None = typer.Option(None, "--output", "-o", help="Measurement CSV to write (default: stdout)."),
    protocol: Protocol = opt.servo_protocol(Protocol.DXL1, "dxl1 (AX), dxl2 (X series) or feetech (STS/SCS)."),
    baud: int = opt.bus_baud(1_000_000),
    model: str | None = typer.Option(None, "--model", help="Refuse unless the servo is this model."),
    limits: Path | None = typer.Option(
        None, "--limits", help="Limits YAML from `armtool limits`: measure inside safe_min/max_ticks."
    ),
    lo: int | None = opt.tick_bound("--min", "Lowest command in ticks (inside the mechanical stop)."),
    hi: int | None = opt.tick_bound("--max", "Highest command in ticks (inside the mechanical stop)."),
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
    speed: float = opt.speed_deg_s(60.0, SPEED),
    torque_limit: float = opt.torque_percent(50.0, TORQUE),
    dwell: float = typer.Option(0.15, "--dwell", callback=opt.seconds(60, allow_zero=True), help=DWELL),
    settle_timeout: float = typer.Option(
        3.0,
        "--settle-timeout",
        callback=opt.finite_float(0.1, 600, unit="seconds"),
        help="Seconds to wait for a point to settle.",
    ),
    yes: bool = opt.yes(YES),
) -> None:
    require("servo")  # exit 2 with the install command when the extra is missing
    from armtool.fileio import check_output_paths
    from armtool.servo.lut import session as S
    from armtool.servo.reference import check_reference_spec, reference_file

    if points is not None and step is not None:
        raise ArmtoolError("give --points or --step, not both")
    check_reference_spec(reference, port, sys.stdin.isatty())
    # every output checked before the servo moves: readings are never lost to an unwritable -o
    partial = {"-o": output, "-o (readings of an interrupted run)": S.partial_path(output)}
    check_output_paths(partial, inputs=[limits, reference_file(reference)])
    setup = S.Setup(port, protocol.value, baud, sid, speed, torque_limit, dwell, settle_timeout)
    req = S.MeasureRequest(reference, model, limits, lo, hi, approach, backoff, points, step, reads, sweeps, output)
    write_output(S.run_measure(setup, req, _hooks(yes)), output, "measurements", rescue="armtool-measure")
    if output is not None:
        stderr().print(f"next: armtool servo-lut fit {output} -o lut.json")


def check(
    table_path: Path = typer.Argument(..., metavar="LUT_JSON", help="Table from `servo-lut fit`."),
    port: str = opt.servo_port("Serial port of the servo bus."),
    sid: int = opt.servo_id(),
    reference: str = typer.Option(..., "--reference", help=LIVE_REF),
    protocol: Protocol = opt.servo_protocol(Protocol.DXL1, "dxl1, dxl2 or feetech."),
    baud: int = opt.bus_baud(1_000_000),
    limits: Path | None = typer.Option(
        None, "--limits", help="Limits YAML [default: the table's measured command range]."
    ),
    lo: int | None = opt.tick_bound("--min", "Lowest command in ticks."),
    hi: int | None = opt.tick_bound("--max", "Highest command in ticks."),
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
    speed: float = opt.speed_deg_s(60.0, SPEED),
    torque_limit: float = opt.torque_percent(50.0, TORQUE),
    dwell: float = typer.Option(0.15, "--dwell", callback=opt.seconds(60, allow_zero=True), help=DWELL),
    output_format: ReportFormat = typer.Option(ReportFormat.TEXT, "--format", help="text or json on stdout."),
    yes: bool = opt.yes(YES),
) -> None:
    require("servo")  # exit 2 with the install command when the extra is missing
    from armtool.console import write_stdout
    from armtool.servo.lut import session as S
    from armtool.servo.reference import check_reference_spec

    check_reference_spec(reference, port, sys.stdin.isatty())
    setup = S.Setup(port, protocol.value, baud, sid, speed, torque_limit, dwell)
    result = S.run_check(setup, table_path, reference, (limits, lo, hi), n, seed, reads, _hooks(yes))
    write_stdout(json.dumps(result.to_dict(), indent=2) if output_format is ReportFormat.JSON else result.text())
    if result.lut["max_deg"] > max_err:
        stderr().print(f"[red]table error {result.lut['max_deg']:.3f}° is above --max-err {max_err:g}°[/red]")
        raise typer.Exit(ExitCode.FINDINGS)
