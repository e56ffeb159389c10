"""`armtool traj check | plot`: judge or draw a trajectory against a URDF's limits."""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Annotated

import typer

from armtool.cli.options import finite_float
from armtool.cli.traj.common import AccLimit, Base, JerkLimit, JointLimitsYaml, TrajIn, Urdf, VelLimit, start
from armtool.errors import ExitCode
from armtool.extras import require
from armtool.output.registry import OutputFormat


def check_cmd(
    path: TrajIn,
    urdf: Urdf,
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
) -> None:
    require("traj")  # exit 2 with the install command when the extra is missing
    from armtool.console import stderr, write_stdout
    from armtool.traj.check import CheckOptions, check
    from armtool.traj.pipeline import LimitSources, read_input, render_findings, without_acceleration_limit

    traj = read_input(path).trajectory
    limits = LimitSources(urdf, joint_limits, tuple(vel or ()), tuple(acc or ()), tuple(jerk or ())).load()
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
    urdf: Urdf,
    output: Annotated[Path, typer.Option("--output", "-o", help="PNG to write.")],
    joint_limits: JointLimitsYaml = None,
    acc: AccLimit = None,
    base: Base = None,
    tip: Annotated[str | None, typer.Option(help="Tool link: also draw the tool path (x-y, x-z, y-z).")] = None,
) -> None:
    start({"-o": output}, [path, urdf, joint_limits])
    from armtool.console import stderr
    from armtool.traj.pipeline import LimitSources, read_input
    from armtool.traj.plot import write_plot

    traj = read_input(path).trajectory
    limits = LimitSources(urdf, joint_limits, (), tuple(acc or ())).load()
    chain = None
    if tip is not None:
        from armtool.model.chain import load_chain

        chain = load_chain(urdf, base, tip)
    write_plot(output, traj, limits, chain)
    stderr().print(f"wrote {output}")
