"""What the `armtool traj` subcommands share: option declarations (typer `Annotated` types, one
declaration per option) and the first and last step of each command. No numpy at import."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from armtool.cli.options import MoveItConfig, PackagePaths, RobotConfig, XacroArgs
from armtool.errors import ArmtoolError
from armtool.extras import require
from armtool.traj.choices import TrajFormat

__all__ = ["MoveItConfig", "PackagePaths", "RobotConfig", "XacroArgs"]  # the robot options, for the commands

if TYPE_CHECKING:
    from armtool.traj.limits import JointLimits
    from armtool.traj.pipeline import LimitSources
    from armtool.traj.trajectory import Trajectory

FORMATS_HELP = (
    "Trajectory files: CSV (time_s, <joint>_rad or _m, optional _rad_s / _rad_s2 columns), ROS JointTrajectory "
    "YAML as `ros2 topic echo` (sec/nanosec) or `rostopic echo` (secs/nsecs) prints it, MoveIt RobotTrajectory "
    "YAML, or JSON; detected from the content. - reads stdin."
)

URDF = "--urdf URDF"  # how the commands with a --urdf option ask for the robot, in hints
TrajIn = Annotated[Path, typer.Argument(help="Trajectory or joint path; - for stdin.")]
Urdf = Annotated[
    Path | None,
    typer.Option(
        "--urdf", help="URDF or xacro: joint names, position and velocity limits (or the --moveit-config package's)."
    ),
]
OptionalUrdf = Annotated[
    Path | None,
    typer.Option(
        "--urdf",
        help="Re-time (thin, join) or check (retime) the result within this URDF's limits (or --moveit-config's).",
    ),
]
JointLimitsYaml = Annotated[
    Path | None,
    typer.Option(
        "--joint-limits",
        help="MoveIt joint_limits.yaml, flat or a ROS 2 parameter file (acceleration and jerk limits, scaling "
        "factors; default: the --moveit-config package's).",
    ),
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


@dataclass(frozen=True)
class Robot:
    """The robot a traj command works on: its URDF or xacro (with the xacro arguments and package
    paths the robot options give) and MoveIt's joint_limits.yaml."""

    urdf: Path
    joint_limits: Path | None
    xacro_args: tuple[tuple[str, str], ...]
    package_paths: tuple[Path, ...]
    srdf: Path | None = None  # --srdf, else the --moveit-config package's (cartesian's group and start state)
    srdf_xacro_args: tuple[tuple[str, str], ...] = ()  # for a .srdf.xacro
    kinematics: Path | None = None  # the --moveit-config package's kinematics.yaml (cartesian's group)


def robot(
    urdf: Path | None,
    joint_limits: Path | None,
    moveit_config: Path | None,
    xacro_arg: list[str] | None,
    package_path: list[Path] | None,
    config: Path | None,
    *,
    urdf_option: str,
    required: bool = True,
    srdf: Path | None = None,
) -> Robot | None:
    """--urdf and --joint-limits (and --srdf), or what --moveit-config's package loads (its URDF,
    SRDF, config/joint_limits.yaml and kinematics.yaml); given options win, and the package's
    xacro arguments apply either way (RobotOptions.moveit_package), to the SRDF too. None when no
    robot is given and none is `required`. `urdf_option` is how the command takes a URDF, for
    hints ("--urdf URDF", "the URDF argument")."""
    from armtool.cli.options import RobotOptions

    options = RobotOptions(xacro_arg, package_path, config)
    package_args: dict[str, str] = {}
    kinematics: Path | None = None
    if moveit_config is not None:
        pkg, urdf = options.moveit_package(moveit_config, urdf, urdf_option)
        package_args = pkg.urdf_xacro_args
        joint_limits = joint_limits or pkg.joint_limits
        srdf = srdf or pkg.srdf
        kinematics = pkg.kinematics
    if urdf is None:
        if required:
            raise ArmtoolError("no robot given", hint=f"pass {urdf_option} (or a xacro), or --moveit-config DIR")
        return None
    args = options.xacro_args(urdf, package_args)
    srdf_args = options.xacro_args(srdf, package_args) if srdf is not None else {}
    return Robot(
        urdf,
        joint_limits,
        tuple(args.items()),
        tuple(options.package_paths),
        srdf,
        tuple(srdf_args.items()),
        kinematics,
    )


def sources(
    given: Robot | None,
    vel: list[str] | None,
    acc: list[str] | None,
    jerk: list[str] | None = None,
    velocity_scaling: float | None = None,
    acceleration_scaling: float | None = None,
) -> LimitSources | None:
    """Where the limits come from (None without a robot)."""
    from armtool.traj.pipeline import LimitSources

    if given is None:
        return None
    return LimitSources(
        given.urdf,
        given.joint_limits,
        tuple(vel or ()),
        tuple(acc or ()),
        tuple(jerk or ()),
        velocity_scaling,
        acceleration_scaling,
        given.xacro_args,
        given.package_paths,
    )


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
