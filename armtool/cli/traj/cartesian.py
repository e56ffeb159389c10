"""`armtool traj cartesian`: options in, `armtool.traj.plan` out."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer

from armtool.cli.options import finite_float, positive_float
from armtool.cli.traj.common import (
    Base,
    MoveItConfig,
    PackagePaths,
    RobotConfig,
    To,
    XacroArgs,
    emit,
    robot,
    start,
)
from armtool.traj.choices import PathSolver, TrajFormat


def cartesian(
    urdf: Annotated[
        Path | None, typer.Argument(help="URDF or xacro of the arm (default: the --moveit-config package's).")
    ] = None,
    base: Base = None,
    tip: Annotated[str | None, typer.Option(help="Tool link (default: the end of the longest chain).")] = None,
    start_q: Annotated[
        str | None,
        typer.Option(
            "--start",
            help="Start configuration, comma-separated joint values (default: the SRDF's home/ready state, "
            "else mid-range when it is not singular, else a well-conditioned configuration near it).",
        ),
    ] = None,
    srdf: Annotated[
        Path | None,
        typer.Option(
            help="SRDF or .srdf.xacro: its home/ready group state is the default start, and it defines --group "
            "(default: the --moveit-config package's, else one beside the URDF for the same robot, in its "
            "package or a sibling *moveit_config* package)."
        ),
    ] = None,
    group: Annotated[
        str | None,
        typer.Option(
            help="MoveIt planning group whose chain to follow, built as MoveIt builds it (needs --srdf or "
            "--moveit-config; with --moveit-config the default is the one group its kinematics.yaml configures)."
        ),
    ] = None,
    line: Annotated[
        str | None, typer.Option(help="Straight line to X,Y,Z (m, base frame), keeping the orientation.")
    ] = None,
    relative: Annotated[bool, typer.Option(help="--line X,Y,Z is an offset from the start position.")] = False,
    center_offset: Annotated[
        str | None,
        typer.Option(help="Circle through the start: its centre as DX,DY,DZ from the start position (m, base frame)."),
    ] = None,
    center: Annotated[
        str | None, typer.Option(help="Circle through the start: its centre X,Y,Z (m, base frame).")
    ] = None,
    radius: Annotated[
        float | None,
        typer.Option(
            callback=positive_float(unit="m"),
            help="Circle of this radius (m) about --center/--center-offset (default: the start position), "
            "reached by a straight line first: the lecture's circle.",
        ),
    ] = None,
    normal: Annotated[
        str, typer.Option(help="Circle: plane normal (base frame); the tool turns right-handed about it.")
    ] = "1,0,0",
    angle: Annotated[
        float, typer.Option(callback=finite_float(), help="Circle: angle to turn (rad; default a full circle).")
    ] = 2 * math.pi,
    arc_via: Annotated[
        str | None, typer.Option(help="Arc through three points: the interim point X,Y,Z (with --arc-to).")
    ] = None,
    arc_to: Annotated[str | None, typer.Option(help="Arc through three points: the end point X,Y,Z.")] = None,
    waypoints: Annotated[
        Path | None, typer.Option(help="CSV of poses: x_m,y_m,z_m[,roll_rad,pitch_rad,yaw_rad] (base frame).")
    ] = None,
    eef_step: Annotated[
        float,
        typer.Option(callback=positive_float(unit="m"), help="Largest tool step between path points (m)."),
    ] = 0.01,
    eef_step_rad: Annotated[
        float,
        typer.Option(callback=positive_float(unit="rad"), help="Largest tool rotation between path points (rad)."),
    ] = 0.05,
    precision: Annotated[
        float,
        typer.Option(
            callback=positive_float(unit="m"),
            help="Largest deviation of a joint midpoint from the path (m); points are inserted until met.",
        ),
    ] = 1e-3,
    precision_rad: Annotated[
        float,
        typer.Option(
            callback=positive_float(unit="rad"), help="Largest orientation deviation of a joint midpoint (rad)."
        ),
    ] = 0.01,
    jump_factor: Annotated[
        float,
        typer.Option(
            callback=finite_float(0.0), help="Relative jump rule: a step over FACTOR × the mean step (0: off)."
        ),
    ] = 10.0,
    max_step: Annotated[
        float,
        typer.Option(
            callback=finite_float(0.0, unit="rad"), help="Absolute jump rule: largest joint step (rad; 0: off)."
        ),
    ] = 0.5,
    max_step_m: Annotated[
        float,
        typer.Option(callback=finite_float(0.0, unit="m"), help="Absolute jump rule for prismatic joints (m; 0: off)."),
    ] = 0.1,
    solver: Annotated[
        PathSolver,
        typer.Option(
            help="IK solver from `armtool ik-bench`; auto: analytic (closed form, the solution nearest the previous "
            "point) where the chain has one, else lm."
        ),
    ] = PathSolver.AUTO,
    lock: Annotated[
        list[str] | None,
        typer.Option(
            help="Hold a joint at a value: JOINT=VALUE (rad or m), repeatable or a comma list; a 7-DoF arm "
            "locked at one joint has a closed form (Panda: panda_joint7=0.785)."
        ),
    ] = None,
    report: Annotated[
        Path | None,
        typer.Option(help="Also write the report (fraction, jumps, branch switches, where it stopped) here as JSON."),
    ] = None,
    min_fraction: Annotated[
        float,
        typer.Option(
            callback=finite_float(0.0, 1.0),
            help="Below this fraction achieved: write nothing, exit 2 (0: write what was achieved).",
        ),
    ] = 1.0,
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write the joint path here (default: stdout, CSV).")
    ] = None,
    to: To = None,
    plot: Annotated[
        Path | None,
        typer.Option(
            help="Also draw the tool path and each step's midpoint deviation from the path (PNG, SVG or PDF)."
        ),
    ] = None,
    moveit_config: MoveItConfig = None,
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: RobotConfig = None,
) -> None:
    start({"-o": output, "--plot": plot, "--report": report}, [urdf, waypoints, srdf])
    from armtool.ik.locks import parse_locks

    locks = parse_locks(lock)
    if plot is not None:
        from armtool.plotting import plot_format

        plot_format(plot)  # before the work
    given = robot(
        urdf, None, moveit_config, xacro_arg, package_path, config, urdf_option="the URDF argument", srdf=srdf
    )
    assert given is not None  # a robot is required
    group_why = ""
    if moveit_config is not None and group is None and base is None and tip is None:
        from armtool.errors import ArmtoolError
        from armtool.ik.group import planning_group

        if given.srdf is None:
            raise ArmtoolError(
                "the --moveit-config package has no SRDF: its planning group's chain is unknown",
                str(moveit_config),
                "pass --srdf FILE (and --group NAME), or --base/--tip",
            )
        group = planning_group(given.kinematics, moveit_config)
        group_why = "the one group of --moveit-config's kinematics.yaml"
    from rich.markup import escape

    from armtool.console import stderr
    from armtool.traj import plan
    from armtool.traj.cartesian import CartesianOptions

    spec = plan.PathSpec(line, relative, center, center_offset, radius, normal, angle, arc_via, arc_to, waypoints)
    steps = CartesianOptions(
        eef_step,
        eef_step_rad,
        precision,
        precision_rad,
        jump_factor=jump_factor or None,
        max_step_rad=max_step or None,
        max_step_m=max_step_m or None,
    )
    done = plan.plan_cartesian(
        given.urdf,
        base,
        tip,
        start_q,
        spec,
        steps,
        solver.value,
        given.srdf,
        dict(given.xacro_args),
        given.package_paths,
        group=group,
        group_why=group_why,
        srdf_xacro_args=dict(given.srdf_xacro_args),
        locks=locks,
    )
    for text in plan.report_lines(done.result, done):
        stderr().print(escape(text))
    if report is not None:
        from armtool.fileio import write_atomic

        write_atomic(report, plan.report_json(done))
        stderr().print(f"wrote {escape(str(report))}")
    plan.require_fraction(done.result, min_fraction)
    emit(done.trajectory, output, to, TrajFormat.CSV, None)
    if plot is not None:
        from armtool.traj.plot import write_cartesian_plot

        r = done.result
        write_cartesian_plot(
            plot, done.chain, r.q, r.midpoint_deviation_m, r.midpoint_deviation_rad, precision, precision_rad
        )
        stderr().print(f"wrote {plot}")
