"""What the `armtool traj` subcommands share: option declarations (typer `Annotated` types, one
declaration per option) and the first and last step of each command. No numpy at import."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from armtool.extras import require
from armtool.traj.choices import TrajFormat

if TYPE_CHECKING:
    from armtool.traj.limits import JointLimits
    from armtool.traj.pipeline import LimitSources
    from armtool.traj.trajectory import Trajectory

FORMATS_HELP = (
    "Trajectory files: CSV (time_s, <joint>_rad or _m, optional _rad_s / _rad_s2 columns), ROS JointTrajectory "
    "YAML as `ros2 topic echo` (sec/nanosec) or `rostopic echo` (secs/nsecs) prints it, MoveIt RobotTrajectory "
    "YAML, or JSON; detected from the content. - reads stdin."
)

TrajIn = Annotated[Path, typer.Argument(help="Trajectory or joint path; - for stdin.")]
Urdf = Annotated[Path, typer.Option("--urdf", help="URDF or xacro: joint names, position and velocity limits.")]
OptionalUrdf = Annotated[
    Path | None,
    typer.Option("--urdf", help="Re-time (thin, join) or check (retime) the result within this URDF's limits."),
]
JointLimitsYaml = Annotated[
    Path | None,
    typer.Option("--joint-limits", help="MoveIt joint_limits.yaml (acceleration and jerk limits, scaling factors)."),
]
VelLimit = Annotated[
    list[str] | None,
    typer.Option(
        "--vel-limit",
        help="Velocity limit (rad/s or m/s): VALUE for every joint or JOINT=VALUE[,..]; overrides the URDF.",
    ),
]
AccLimit = Annotated[
    list[str] | None,
    typer.Option(
        "--acc-limit",
        help="Acceleration limit (rad/s², m/s²): VALUE or JOINT=VALUE[,..]; overrides joint_limits.yaml.",
    ),
]
JerkLimit = Annotated[
    list[str] | None,
    typer.Option(
        "--jerk-limit",
        help="Jerk limit (rad/s³, m/s³): VALUE or JOINT=VALUE[,..]; overrides joint_limits.yaml's max_jerk.",
    ),
]
Output = Annotated[Path | None, typer.Option("--output", "-o", help="Write here (default: stdout).")]
To = Annotated[
    TrajFormat | None,
    typer.Option("--to", help="Output format (default: from -o's extension, else the (first) input's)."),
]
Base = Annotated[str | None, typer.Option("--base", help="Base link (default: the URDF's root).")]


def start(outputs: dict[str, Path | None], inputs: list[Path | None]) -> None:
    """Every writing subcommand's first step: the extra installed (else exit 2 with the install
    command), and no output path that names an input, a directory or a missing directory."""
    require("traj")
    from armtool.fileio import check_output_paths

    check_output_paths(outputs, inputs)


def sources(
    urdf: Path | None, joint_limits: Path | None, vel: list[str] | None, acc: list[str] | None
) -> LimitSources | None:
    """Where the limits come from (None without --urdf)."""
    from armtool.traj.pipeline import LimitSources

    return None if urdf is None else LimitSources(urdf, joint_limits, tuple(vel or ()), tuple(acc or ()))


def emit(
    traj: Trajectory,
    output: Path | None,
    to: TrajFormat | None,
    fallback: TrajFormat,
    limits: JointLimits | None,
    hint: str | None = None,
) -> None:
    """The last step: check against `limits`, then write atomically to `output` or print to stdout."""
    from armtool.console import stderr, write_stdout
    from armtool.fileio import write_atomic
    from armtool.traj.formats import format_for_output
    from armtool.traj.pipeline import BUG_HINT, checked_text

    text = checked_text(traj, format_for_output(output, to, fallback), limits, hint or BUG_HINT)
    if output is None or str(output) == "-":
        write_stdout(text)
    else:
        write_atomic(output, text)
        stderr().print(f"wrote {traj.n_points} points to {output}")
