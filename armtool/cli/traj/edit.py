"""`armtool traj time | retime | thin | join`: one trajectory (or several) in, one out, checked
against the limits before it is written."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from armtool.cli.options import finite_float, positive_float
from armtool.cli.traj.common import (
    URDF,
    AccLimit,
    JerkLimit,
    JointLimitsYaml,
    MoveItConfig,
    OptionalUrdf,
    Output,
    PackagePaths,
    RobotConfig,
    To,
    TrajIn,
    Urdf,
    VelLimit,
    XacroArgs,
    emit,
    robot,
    sources,
    start,
)
from armtool.traj.choices import TrajFormat

if TYPE_CHECKING:
    from armtool.cli.traj.common import Robot
    from armtool.traj.trajectory import Trajectory


def time_cmd(
    path: Annotated[
        Path, typer.Argument(help="Joint path or trajectory (its times, if any, are ignored); - for stdin.")
    ],
    urdf: Urdf = None,
    joint_limits: JointLimitsYaml = None,
    vel: VelLimit = None,
    acc: AccLimit = None,
    jerk: JerkLimit = None,
    vscale: Annotated[
        float | None,
        typer.Option(
            "--velocity-scaling",
            callback=finite_float(0.0, 1.0, lo_open=True),
            help="Fraction of the velocity limits to use (default: joint_limits.yaml's, else 1).",
        ),
    ] = None,
    ascale: Annotated[
        float | None,
        typer.Option(
            "--acceleration-scaling",
            callback=finite_float(0.0, 1.0, lo_open=True),
            help="Fraction of the acceleration limits to use (default: joint_limits.yaml's, else 1).",
        ),
    ] = None,
    output: Output = None,
    to: To = None,
    moveit_config: MoveItConfig = None,
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: RobotConfig = None,
) -> None:
    start({"-o": output}, [path, urdf, joint_limits])
    from armtool.console import stderr
    from armtool.traj.pipeline import read_input
    from armtool.traj.timing import time_path

    given = robot(urdf, joint_limits, moveit_config, xacro_arg, package_path, config, urdf_option=URDF)
    traj, in_fmt = read_input(path)
    limit_sources = sources(given, vel, acc, jerk, vscale, ascale)
    assert limit_sources is not None  # a robot is required
    limits = limit_sources.load()
    done = time_path(traj, limits)
    timed = done.trajectory
    stderr().print(f"interpolation: {done.interpolation}")
    kind = "jerk-limited" if limits.subset(traj.joint_names).has_jerk_limits() else "time-optimal"
    stderr().print(
        f"{kind}: {timed.duration_s:.4f} s over {timed.n_points} samples "
        f"(velocity scaling {limits.velocity_scaling:g}, acceleration scaling {limits.acceleration_scaling:g})"
    )
    emit(timed, output, to, in_fmt, limits)


def retime_cmd(
    path: Annotated[Path, typer.Argument(help="Timed trajectory; - for stdin.")],
    scale: Annotated[
        float, typer.Option(callback=positive_float(), help="Speed factor S > 0 (0.25: four times slower).")
    ],
    urdf: OptionalUrdf = None,
    joint_limits: JointLimitsYaml = None,
    acc: AccLimit = None,
    output: Output = None,
    to: To = None,
    moveit_config: MoveItConfig = None,
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: RobotConfig = None,
) -> None:
    start({"-o": output}, [path, urdf, joint_limits])
    from armtool.traj.edit import retime
    from armtool.traj.pipeline import read_input

    traj, in_fmt = read_input(path)
    given = sources(
        robot(urdf, joint_limits, moveit_config, xacro_arg, package_path, config, urdf_option=URDF, required=False),
        None,
        acc,
    )
    limits = None if given is None else given.load()
    hint = "a smaller --scale, or leave out --urdf to write it unchecked"
    emit(retime(traj, scale), output, to, in_fmt, limits, hint)


def thin_cmd(
    path: TrajIn,
    every: Annotated[int | None, typer.Option(help="Drop points K, 2K, 3K, ... (1-based).")] = None,
    tolerance: Annotated[
        float | None,
        typer.Option(
            callback=positive_float(),
            help="Drop points within this joint-space distance (rad/m) of the path through the kept ones.",
        ),
    ] = None,
    urdf: OptionalUrdf = None,
    joint_limits: JointLimitsYaml = None,
    vel: VelLimit = None,
    acc: AccLimit = None,
    output: Output = None,
    to: To = None,
    moveit_config: MoveItConfig = None,
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: RobotConfig = None,
) -> None:
    start({"-o": output}, [path, urdf, joint_limits])
    from armtool.console import stderr
    from armtool.traj.edit import thin
    from armtool.traj.pipeline import read_input

    given = robot(urdf, joint_limits, moveit_config, xacro_arg, package_path, config, urdf_option=URDF, required=False)
    traj, in_fmt = read_input(path)
    out = thin(traj, every, tolerance)
    stderr().print(f"thinned {traj.n_points} -> {out.n_points} points")
    _retime_and_emit(out, given, vel, acc, output, to, in_fmt)


def join_cmd(
    paths: Annotated[list[Path], typer.Argument(help="Two or more trajectories, in order.")],
    tolerance: Annotated[
        float,
        typer.Option(
            callback=finite_float(0.0), help="Largest gap per joint between an end and the next start (rad/m)."
        ),
    ] = 1e-3,
    urdf: OptionalUrdf = None,
    joint_limits: JointLimitsYaml = None,
    vel: VelLimit = None,
    acc: AccLimit = None,
    output: Output = None,
    to: To = None,
    moveit_config: MoveItConfig = None,
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: RobotConfig = None,
) -> None:
    start({"-o": output}, [*paths, urdf, joint_limits])
    from armtool.console import stderr
    from armtool.traj.edit import join
    from armtool.traj.pipeline import read_input

    given = robot(urdf, joint_limits, moveit_config, xacro_arg, package_path, config, urdf_option=URDF, required=False)
    loaded = [read_input(p) for p in paths]
    out = join([lt.trajectory for lt in loaded], tolerance)
    stderr().print(f"joined {len(loaded)} trajectories: {out.n_points} points")
    _retime_and_emit(out, given, vel, acc, output, to, loaded[0].format)


def _retime_and_emit(
    traj: Trajectory,
    given: Robot | None,
    vel: list[str] | None,
    acc: list[str] | None,
    output: Path | None,
    to: TrajFormat | None,
    fallback: TrajFormat,
) -> None:
    """thin's and join's optional --urdf: re-time the edited path within the limits, then write."""
    from armtool.console import stderr
    from armtool.traj.pipeline import retime

    timed, limits, interpolation = retime(traj, sources(given, vel, acc))
    if limits is not None:
        stderr().print(f"re-timed: {timed.duration_s:.4f} s ({interpolation})")
    emit(timed, output, to, fallback, limits)
