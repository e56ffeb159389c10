"""`armtool traj check | plot`: judge or draw a trajectory against a URDF's limits."""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Annotated

import typer

from armtool.cli.options import finite_float
from armtool.cli.traj.common import (
    URDF,
    AccLimit,
    Base,
    JerkLimit,
    JointLimitsYaml,
    MoveItConfig,
    PackagePaths,
    RobotConfig,
    TrajIn,
    Urdf,
    VelLimit,
    XacroArgs,
    robot,
    sources,
    start,
)
from armtool.errors import ExitCode
from armtool.extras import require
from armtool.output.registry import OutputFormat


def check_cmd(
    path: TrajIn,
    urdf: Urdf = None,
    joint_limits: JointLimitsYaml = None,
    vel: VelLimit = None,
    acc: AccLimit = None,
    jerk: JerkLimit = None,
    jump_factor: Annotated[
        float,
        typer.Option(
            callback=finite_float(0.0),
            help="Relative jump rule for untimed paths: a step over FACTOR × the mean (0: off).",
        ),
    ] = 10.0,
    max_step: Annotated[
        float | None,
        typer.Option(callback=finite_float(0.0), help="Absolute jump rule: largest step of any joint between points."),
    ] = None,
    output_format: Annotated[
        OutputFormat | None,
        typer.Option("--format", help="text (default; github inside GitHub Actions), json, sarif, github."),
    ] = None,
    exit_zero: Annotated[bool, typer.Option("--exit-zero", help="Exit 0 even when problems are found.")] = False,
    moveit_config: MoveItConfig = None,
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: RobotConfig = None,
) -> None:
    require("traj")  # exit 2 with the install command when the extra is missing
    from armtool.console import stderr, write_stdout
    from armtool.traj.check import CheckOptions, check
    from armtool.traj.pipeline import read_input, render_findings, without_acceleration_limit

    given = robot(urdf, joint_limits, moveit_config, xacro_arg, package_path, config, urdf_option=URDF)
    traj = read_input(path).trajectory
    limit_sources = sources(given, vel, acc, jerk)
    assert limit_sources is not None  # a robot is required
    limits = limit_sources.load()
    no_acc = without_acceleration_limit(traj, limits)
    if no_acc:
        stderr().print(
            f"note: no acceleration limit for {', '.join(no_acc)}: accelerations not checked "
            "(give --joint-limits or --acc-limit)"
        )
    findings = check(traj, limits, CheckOptions(jump_factor=jump_factor, max_step=max_step))
    fmt = output_format or (OutputFormat.GITHUB if os.environ.get("GITHUB_ACTIONS") == "true" else OutputFormat.TEXT)
    write_stdout(render_findings(findings, fmt, color=sys.stdout.isatty() and "NO_COLOR" not in os.environ))
    failing = any(f.severity.value == "error" for f in findings)
    raise typer.Exit(ExitCode.FINDINGS if failing and not exit_zero else ExitCode.OK)


def plot_cmd(
    path: TrajIn,
    output: Annotated[Path, typer.Option("--output", "-o", help="Figure to write: PNG, SVG or PDF, by the extension.")],
    urdf: Urdf = None,
    joint_limits: JointLimitsYaml = None,
    acc: AccLimit = None,
    base: Base = None,
    tip: Annotated[str | None, typer.Option(help="Tool link: also draw the tool path (x-y, x-z, y-z).")] = None,
    moveit_config: MoveItConfig = None,
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: RobotConfig = None,
) -> None:
    start({"-o": output}, [path, urdf, joint_limits])
    from armtool.console import stderr
    from armtool.plotting import plot_format

    plot_format(output, "-o")  # before the work
    from armtool.traj.pipeline import read_input
    from armtool.traj.plot import write_plot

    given = robot(urdf, joint_limits, moveit_config, xacro_arg, package_path, config, urdf_option=URDF)
    assert given is not None  # a robot is required
    traj = read_input(path).trajectory
    limit_sources = sources(given, None, acc)
    assert limit_sources is not None
    limits = limit_sources.load()
    chain = None
    if tip is not None:
        from armtool.model.chain import load_chain

        chain = load_chain(given.urdf, base, tip, xacro_args=dict(given.xacro_args), package_paths=given.package_paths)
    write_plot(output, traj, limits, chain)
    stderr().print(f"wrote {output}")
