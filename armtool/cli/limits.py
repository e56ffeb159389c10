"""`armtool limits`: record each joint's real range over a Dynamixel or Feetech bus."""

from __future__ import annotations

import select
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from armtool.cli import options as opt
from armtool.console import stderr
from armtool.errors import ArmtoolError, ExitCode
from armtool.extras import require
from armtool.output.summary import print_summary
from armtool.servo.limits.choices import Mode
from armtool.servo.registry import Protocol

if TYPE_CHECKING:
    from armtool.servo.limits.record import Hooks
    from armtool.servo.summary import Cell, Summary


def limits(
    port: str | None = typer.Option(
        None,
        "--port",
        help="Serial port of the bus adapter (e.g. /dev/ttyUSB0); required unless --from-lerobot converts a file.",
    ),
    mode: Mode | None = typer.Option(
        None,
        "--mode",
        help="manual: you move the joints (torque off); auto: seek each stop at low torque. Required with --port.",
    ),
    protocol: Protocol | None = typer.Option(
        None,
        "--protocol",
        help="dxl1 (AX/MX), dxl2 (X series) or feetech (STS/SCS) [default: the arm file's, else dxl1].",
    ),
    baud: int | None = opt.bus_baud(None, "Baud rate [default: the arm file's, else 1000000]."),
    ids: str | None = typer.Option(
        None, "--ids", callback=opt.id_list(0, 252), help="Servo IDs, e.g. 1,2,3 or 1-6 (or use --arm)."
    ),
    model: str | None = typer.Option(None, "--model", help="With --ids: the model every ID must be (e.g. AX-12A)."),
    arm: Path | None = typer.Option(
        None, "--arm", help="Arm YAML: joints with name, id, model, zero_ticks, direction."
    ),
    output: Path | None = typer.Option(None, "-o", "--output", help="Write the limits YAML here (default: stdout)."),
    margin: float = typer.Option(
        2.0, "--margin", callback=opt.finite_float(0, 90, unit="degrees"), help="Degrees kept inside each recorded end."
    ),
    duration: float | None = typer.Option(
        None, "--duration", callback=opt.seconds(), help="Manual: record this many seconds (default: until Enter)."
    ),
    rate: float = typer.Option(
        50.0, "--rate", callback=opt.positive_float(1000, "samples per second"), help="Manual: samples per second."
    ),
    min_dwell: float = typer.Option(
        0.3,
        "--min-dwell",
        callback=opt.seconds(3600, allow_zero=True),
        help="Manual: seconds a joint must rest at an end to confirm it.",
    ),
    torque_limit: float = opt.torque_percent(30.0, "Auto: torque (or PWM) limit in percent of full."),
    speed: float = opt.speed_deg_s(30.0, "Auto: seek speed in degrees per second."),
    stall_window: float = typer.Option(
        0.12,
        "--stall-window",
        callback=opt.seconds(60),
        help="Auto: seconds without motion that, with high load, mean a stop.",
    ),
    stall_load: float = typer.Option(
        70.0,
        "--stall-load",
        callback=opt.percent(),
        help="Auto: load, in percent of the torque limit, that means a stop.",
    ),
    back_off: float = typer.Option(
        3.0,
        "--back-off",
        callback=opt.finite_float(0, 90, unit="degrees"),
        help="Auto: degrees to back off after each stop.",
    ),
    max_seek: float | None = typer.Option(
        None,
        "--max-seek",
        callback=opt.seconds(3600),
        help="Auto: seconds per direction before giving up [default: range/speed x 1.5 + 2].",
    ),
    first_dir: str = typer.Option("-", "--first-dir", help="Auto: seek the low (-) or high (+) end first."),
    urdf: Path | None = typer.Option(
        None,
        "--urdf",
        help="Write <limit lower upper> into this URDF (keeps its text and comments); a xacro is expanded "
        "(--xacro-arg, --package-path) and written whole with --urdf-out.",
    ),
    in_place: bool = typer.Option(
        False,
        "--in-place",
        help="With --urdf: edit it in place, keeping the previous version "
        "in FILE.bak (or FILE.bak.1, .2 ... when that exists: a backup is never overwritten).",
    ),
    urdf_out: Path | None = typer.Option(None, "--urdf-out", help="With --urdf: write the edited URDF here."),
    allow_widen: bool = typer.Option(
        False, "--allow-widen", help="Write URDF limits even where they are wider than the URDF's."
    ),
    write_eeprom: bool = typer.Option(
        False, "--write-eeprom", help="Also write the safe range into the servos' angle-limit registers."
    ),
    yes: bool = opt.yes("Answer the safety and EEPROM prompts with yes (scripted use)."),
    dry_run: bool = typer.Option(
        False, "--dry-run", help="With --write-eeprom: show the EEPROM writes, do not make them."
    ),
    timeout_ms: float = typer.Option(
        25.0, "--timeout-ms", callback=opt.positive_float(10_000, "milliseconds"), help="Reply timeout per transaction."
    ),
    lerobot_calibration: Path | None = typer.Option(
        None,
        "--lerobot-calibration",
        help="Also write a LeRobot calibration JSON (motor names = the arm file's joint names), with homing offsets that keep every range off the 0/4095 seam.",
    ),
    lerobot_full_turn: str | None = typer.Option(
        None,
        "--lerobot-full-turn",
        help="With --lerobot-calibration: joints that get LeRobot's full-turn range 0..4095 (e.g. wrist_roll).",
    ),
    from_lerobot: Path | None = typer.Option(
        None,
        "--from-lerobot",
        help="Read a LeRobot calibration JSON: without --port, convert its ranges to limits YAML / URDF limits; "
        "with --port and --mode, record the arm and compare each motor's range with the file's (exit 1 when the file reaches past a recorded end).",
    ),
    xacro_arg: opt.XacroArgs = None,
    package_path: opt.PackagePaths = None,
    config: opt.RobotConfig = None,
) -> None:
    require("servo")  # exit 2 with the install command when the extra is missing
    from armtool.servo.limits.record import run
    from armtool.servo.limits.request import Request

    robot = opt.RobotOptions(xacro_arg, package_path, config)
    # fmt: off
    request = Request(
        port, mode, protocol, baud, ids, model, arm, output, margin, duration, rate, min_dwell, torque_limit, speed,
        stall_window, stall_load, back_off, max_seek, first_dir, urdf, in_place, urdf_out, allow_widen, write_eeprom,
        yes, dry_run, timeout_ms, lerobot_calibration, lerobot_full_turn, from_lerobot,
        tuple(robot.xacro_args(urdf).items()) if urdf is not None else (), tuple(robot.package_paths),
    )
    # fmt: on
    if not run(request, _hooks(), sys.stdin.isatty()):
        raise typer.Exit(ExitCode.FINDINGS)


def _note(cell: Cell) -> None:
    from rich.text import Text

    stderr().print(Text(cell) if isinstance(cell, str) else Text.assemble(*cell))


def _confirm(question: str, refusal: str) -> None:
    if not typer.confirm(question, err=True):
        raise ArmtoolError(refusal)


@contextmanager
def _live(first: Summary) -> Iterator[Callable[[Summary], None]]:
    """A table redrawn in place on stderr (the manual recording's extents)."""
    from rich.live import Live

    from armtool.output.summary import summary_table

    with Live(summary_table(first), console=stderr(), refresh_per_second=8, transient=False) as live:
        yield lambda table: live.update(summary_table(table))


@contextmanager
def _progress() -> Iterator[Callable[[int, str], None]]:
    """One status line per joint with its elapsed time (the auto seek)."""
    from rich.progress import Progress, TaskID, TextColumn, TimeElapsedColumn

    tasks: dict[int, TaskID] = {}
    with Progress(TextColumn("{task.description}"), TimeElapsedColumn(), console=stderr(), transient=False) as bar:

        def status(key: int, text: str) -> None:
            if key in tasks:
                bar.update(tasks[key], description=text)
            else:
                tasks[key] = bar.add_task(text)

        yield status


def _enter_pressed() -> bool:
    """Enter typed on a terminal since the last look (the line is consumed)."""
    if not sys.stdin.isatty() or not select.select([sys.stdin], [], [], 0)[0]:
        return False
    sys.stdin.readline()
    return True


def _hooks() -> Hooks:
    from armtool.console import write_stdout
    from armtool.servo.limits.record import Hooks

    return Hooks(_confirm, _note, print_summary, _live, _progress, _enter_pressed, write_stdout)
