"""`armtool traj`: Cartesian paths through IK, time-optimal timing, re-timing, thinning, joining,
a trajectory checker and a plot. Arguments in, core calls, files out; exit 0 / 1 / 2."""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Sequence
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Any

import typer

from armtool.cli.options import finite_float, positive_float
from armtool.errors import ArmtoolError, ExitCode
from armtool.extras import require

if TYPE_CHECKING:  # numpy loads only when a subcommand runs
    from armtool.lint.finding import Finding
    from armtool.traj.cartesian import Segment
    from armtool.traj.formats import LoadedTrajectory, TrajFormat
    from armtool.traj.limits import JointLimits
    from armtool.traj.trajectory import Trajectory

HELP = "Cartesian lines and circles through IK, time-optimal timing, retime/thin/join, and a trajectory checker."

app = typer.Typer(
    name="traj",
    help=HELP,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)

FORMATS_HELP = (
    "Trajectory files: CSV (time_s, <joint>_rad or _m, optional _rad_s / _rad_s2 columns), ROS JointTrajectory "
    "YAML as `ros2 topic echo` (sec/nanosec) or `rostopic echo` (secs/nsecs) prints it, MoveIt RobotTrajectory "
    "YAML, or JSON; detected from the content. - reads stdin."
)


class OutFormat(str, Enum):
    CSV = "csv"
    ROS2 = "ros2"
    ROS1 = "ros1"
    MOVEIT = "moveit"
    JSON = "json"


class CheckFormat(str, Enum):
    TEXT = "text"
    JSON = "json"
    SARIF = "sarif"
    GITHUB = "github"


# ---- shared helpers ----------------------------------------------------------------------------
def _read(path: Path) -> LoadedTrajectory:
    """The trajectory and its detected format (the default output format)."""
    from armtool.traj.formats import read_trajectory

    if str(path) == "-":
        return read_trajectory("<stdin>", sys.stdin.read())
    return read_trajectory(path)


def _check_outputs(outputs: dict[str, Path | None], inputs: Sequence[Path | None]) -> None:
    """Refuse a bad output path (an input, a directory, a missing directory) before any work."""
    from armtool.fileio import check_output_paths

    check_output_paths(outputs, inputs)


def _solver_name(value: str) -> str:
    """--solver at parse time: one of the registered IK solvers."""
    require("traj")  # the registry imports the chain model (numpy): say which extra is missing first
    from armtool.ik.registry import SOLVERS
    from armtool.suggest import did_you_mean

    if value not in SOLVERS:
        raise typer.BadParameter(
            f"unknown solver '{value}'{did_you_mean(value, list(SOLVERS))}; solvers: {', '.join(SOLVERS)}"
        )
    return value


def _limits(
    urdf: Path,
    joint_limits: Path | None,
    vel: Sequence[str],
    acc: Sequence[str],
    jerk: Sequence[str] = (),
    vscale: float | None = None,
    ascale: float | None = None,
) -> JointLimits:
    from armtool.traj.limits import load_limits

    for path, what in ((urdf, "URDF"), (joint_limits, "joint_limits.yaml")):
        if path is not None and path.exists() and not path.is_file():
            raise ArmtoolError(f"{what} is not a regular file (a FIFO, socket, device or directory)", str(path))
    if not urdf.is_file():
        raise ArmtoolError("URDF not found", str(urdf), "pass --urdf path/to/robot.urdf (or .xacro)")
    if joint_limits is not None and not joint_limits.is_file():
        raise ArmtoolError("joint_limits.yaml not found", str(joint_limits))
    return load_limits(
        urdf,
        joint_limits,
        vel_limits=vel,
        acc_limits=acc,
        jerk_limits=jerk,
        velocity_scaling=vscale,
        acceleration_scaling=ascale,
    )


def _out_format(output: Path | None, requested: OutFormat | None, fallback: TrajFormat) -> TrajFormat:
    from armtool.traj.formats import TrajFormat, format_for_output

    return format_for_output(output, None if requested is None else TrajFormat(requested.value), fallback)


def _write(
    traj: Trajectory,
    output: Path | None,
    fmt: TrajFormat,
    limits: JointLimits | None = None,
    over_limit_hint: str = "this is a bug in armtool traj; please report it with the input",
) -> None:
    """Write (atomically) or print; a trajectory with times is checked against `limits` first."""
    from armtool.console import stderr, write_stdout
    from armtool.fileio import write_atomic
    from armtool.traj.formats import format_trajectory

    if limits is not None and traj.times is not None:
        from armtool.traj.check import check

        # Jerk is checked, not planned for: a jerk limit cannot make armtool's own result wrong.
        errors = [f for f in check(traj, limits) if f.severity.value == "error" and f.code != "T303"]
        if errors:
            raise ArmtoolError(
                f"the result fails `traj check`: {errors[0].code} {errors[0].message}; nothing written",
                hint=over_limit_hint,
            )
    text = format_trajectory(traj, fmt)
    if output is None or str(output) == "-":
        write_stdout(text)
    else:
        write_atomic(output, text)
        stderr().print(f"wrote {traj.n_points} points to {output}")


def _floats(text: str, n: int, option: str) -> list[float]:
    try:
        values = [float(v) for v in text.replace(" ", "").split(",") if v != ""]
    except ValueError:
        raise ArmtoolError(f"{option} {text!r}: not {n} comma-separated numbers") from None
    if len(values) != n or not all(math.isfinite(v) for v in values):
        raise ArmtoolError(f"{option} {text!r}: expected {n} finite comma-separated numbers")
    return values


LIMIT_OPTS = dict(
    vel=typer.Option(
        [],
        "--vel-limit",
        help="Velocity limit (rad/s or m/s): VALUE for every joint or JOINT=VALUE[,..]; overrides the URDF.",
    ),
    acc=typer.Option(
        [],
        "--acc-limit",
        help="Acceleration limit (rad/s², m/s²): VALUE or JOINT=VALUE[,..]; overrides joint_limits.yaml.",
    ),
)
# The output options of the commands that read one trajectory and write one.
OUTPUT_OPTS = dict(
    output=typer.Option(None, "--output", "-o", help="Write here (default: stdout)."),
    to=typer.Option(None, "--to", help="Output format (default: from -o's extension, else the input's)."),
)


def _retime_within(
    traj: Trajectory, urdf: Path | None, joint_limits: Path | None, vel: list[str], acc: list[str]
) -> tuple[Trajectory, JointLimits | None]:
    """thin's and join's optional --urdf: the edited path re-timed time-optimally within the limits."""
    if urdf is None:
        return traj, None
    from armtool.console import stderr
    from armtool.traj.timing import time_optimal

    limits = _limits(urdf, joint_limits, vel, acc)
    timed = time_optimal(traj, limits)
    stderr().print(f"re-timed: {timed.duration_s:.4f} s")
    return timed, limits


# ---- cartesian ---------------------------------------------------------------------------------
@app.command(
    "cartesian", help="Follow a straight line, a circle/arc, or a list of poses with the tool; write the joint path."
)
def cartesian(
    urdf: Path = typer.Argument(..., help="URDF or xacro of the arm."),
    base: str | None = typer.Option(None, "--base", help="Base link (default: the URDF's root)."),
    tip: str | None = typer.Option(None, "--tip", help="Tool link (default: the end of the longest chain)."),
    start: str | None = typer.Option(
        None, "--start", help="Start configuration, comma-separated joint values (default: mid-range)."
    ),
    line: str | None = typer.Option(
        None, "--line", help="Straight line to X,Y,Z (m, base frame), keeping the orientation."
    ),
    relative: bool = typer.Option(False, "--relative", help="--line X,Y,Z is an offset from the start position."),
    center_offset: str | None = typer.Option(
        None,
        "--center-offset",
        help="Circle through the start: its centre as DX,DY,DZ from the start position (m, base frame).",
    ),
    center: str | None = typer.Option(
        None, "--center", help="Circle through the start: its centre X,Y,Z (m, base frame)."
    ),
    radius: float | None = typer.Option(
        None,
        "--radius",
        callback=positive_float(unit="m"),
        help="Circle of this radius (m) about --center/--center-offset (default: the start position), reached by a straight line first: the lecture's circle.",
    ),
    normal: str = typer.Option(
        "1,0,0", "--normal", help="Circle: plane normal (base frame); the tool turns right-handed about it."
    ),
    angle: float = typer.Option(
        2 * math.pi, "--angle", callback=finite_float(), help="Circle: angle to turn (rad; default a full circle)."
    ),
    arc_via: str | None = typer.Option(
        None, "--arc-via", help="Arc through three points: the interim point X,Y,Z (with --arc-to)."
    ),
    arc_to: str | None = typer.Option(None, "--arc-to", help="Arc through three points: the end point X,Y,Z."),
    waypoints: Path | None = typer.Option(
        None, "--waypoints", help="CSV of poses: x_m,y_m,z_m[,roll_rad,pitch_rad,yaw_rad] (base frame)."
    ),
    eef_step: float = typer.Option(
        0.01, "--eef-step", callback=positive_float(unit="m"), help="Largest tool step between path points (m)."
    ),
    eef_step_rad: float = typer.Option(
        0.05,
        "--eef-step-rad",
        callback=positive_float(unit="rad"),
        help="Largest tool rotation between path points (rad).",
    ),
    precision: float = typer.Option(
        1e-3,
        "--precision",
        callback=positive_float(unit="m"),
        help="Largest deviation of a joint midpoint from the path (m); points are inserted until met.",
    ),
    precision_rad: float = typer.Option(
        0.01,
        "--precision-rad",
        callback=positive_float(unit="rad"),
        help="Largest orientation deviation of a joint midpoint (rad).",
    ),
    jump_factor: float = typer.Option(
        10.0,
        "--jump-factor",
        callback=finite_float(0.0),
        help="Relative jump rule: a step over FACTOR × the mean step (0: off).",
    ),
    max_step: float = typer.Option(
        0.5,
        "--max-step",
        callback=finite_float(0.0, unit="rad"),
        help="Absolute jump rule: largest joint step (rad; 0: off).",
    ),
    max_step_m: float = typer.Option(
        0.1,
        "--max-step-m",
        callback=finite_float(0.0, unit="m"),
        help="Absolute jump rule for prismatic joints (m; 0: off).",
    ),
    solver: str = typer.Option(
        "lm",
        "--solver",
        callback=_solver_name,
        help="IK solver from `armtool ik-bench` (lm; analytic picks the solution nearest the previous point).",
    ),
    min_fraction: float = typer.Option(
        1.0,
        "--min-fraction",
        callback=finite_float(0.0, 1.0),
        help="Below this fraction achieved: write nothing, exit 2 (0: write what was achieved).",
    ),
    output: Path | None = typer.Option(
        None, "--output", "-o", help="Write the joint path here (default: stdout, CSV)."
    ),
    to: OutFormat | None = typer.Option(None, "--to", help="Output format (default: from -o's extension, else csv)."),
    plot: Path | None = typer.Option(
        None, "--plot", help="Also draw the tool path and each step's midpoint deviation from the path (PNG)."
    ),
) -> None:
    require("traj")  # exit 2 with the install command when the extra is missing
    import numpy as np

    from armtool.console import stderr
    from armtool.model.chain import load_chain
    from armtool.traj import cartesian as cart
    from armtool.traj.path_ik import PathIK
    from armtool.traj.formats import TrajFormat
    from armtool.traj.trajectory import Trajectory

    _check_outputs({"-o": output, "--plot": plot}, [urdf, waypoints])
    if not urdf.is_file():
        raise ArmtoolError("URDF not found", str(urdf))
    if center is not None and center_offset is not None:
        raise ArmtoolError("give --center or --center-offset, not both")
    circle_given = center is not None or center_offset is not None or radius is not None
    chosen = [x for x in (line, circle_given or None, arc_to, waypoints) if x is not None]
    if len(chosen) != 1:
        raise ArmtoolError(
            "give exactly one path: --line, a circle (--center/--center-offset, or --radius), --arc-via/--arc-to, or --waypoints",
            hint="e.g. --center-offset 0,-0.1,0 --normal 1,0,0 for the lecture's circle of radius 0.1 m",
        )
    if (arc_via is None) != (arc_to is None):
        raise ArmtoolError("an arc needs both --arc-via and --arc-to")
    chain = load_chain(urdf, base, tip)
    q0 = np.asarray(_floats(start, chain.n, "--start"), dtype=np.float64) if start is not None else chain.mid()
    if not chain.within_limits(q0):
        raise ArmtoolError(
            "--start is outside the joint limits",
            hint="limits: "
            + ", ".join(f"{n} [{lo:.3g}, {hi:.3g}]" for n, lo, hi in zip(chain.joint_names, chain.lower, chain.upper)),
        )
    T0 = chain.fk(q0)
    if line is not None:
        p = np.asarray(_floats(line, 3, "--line"))
        T1 = T0.copy()
        T1[:3, 3] = T0[:3, 3] + p if relative else p
        if np.linalg.norm(T1[:3, 3] - T0[:3, 3]) < 1e-9:
            raise ArmtoolError("the line ends where it starts", hint="give another end point")
        segments = [cart.line_segment(T0, T1)]
    elif circle_given:
        c = T0[:3, 3].copy()
        if center_offset is not None:
            c = c + np.asarray(_floats(center_offset, 3, "--center-offset"))
        elif center is not None:
            c = np.asarray(_floats(center, 3, "--center"))
        axis = np.asarray(_floats(normal, 3, "--normal"))
        if radius is None:
            segments = [cart.circle_segment(T0, c, axis, angle)]
        else:
            segments = cart.circle_about(T0, c, radius, axis, angle)
    elif arc_to is not None:
        assert arc_via is not None
        segments = [
            cart.arc_through(
                T0, np.asarray(_floats(arc_via, 3, "--arc-via")), np.asarray(_floats(arc_to, 3, "--arc-to"))
            )
        ]
    else:
        assert waypoints is not None
        segments = _waypoint_segments(waypoints, T0)
    ik = PathIK(chain, solver)
    opts = cart.CartesianOptions(
        eef_step,
        eef_step_rad,
        precision,
        precision_rad,
        jump_factor=jump_factor or None,
        max_step_rad=max_step or None,
        max_step_m=max_step_m or None,
    )
    result = cart.compute_cartesian(chain, ik, q0, segments, opts)
    err = stderr()
    err.print(
        f"fraction {result.fraction:.4f}: {len(result.q)} points ({result.inserted} inserted by the precision check), "
        f"worst deviation {result.max_deviation_m * 1000:.3f} mm / {result.max_deviation_rad:.4f} rad"
    )
    rel = ", ".join(map(str, result.relative_jumps)) or "none"
    ab = ", ".join(map(str, result.absolute_jumps)) or "none"
    err.print(f"jumps (step k: point k → k+1): relative rule {rel}; absolute rule {ab}")
    if result.reason:
        from rich.markup import escape

        err.print(
            f"[yellow]stopped[/yellow] at point {len(result.q) - 1} (fraction {result.fraction:.4f}): {result.reason}: {escape(result.detail)}"
        )
    if len(result.q) < 2 or result.fraction < min_fraction:
        raise ArmtoolError(
            f"only {result.fraction:.4f} of the path achieved: stopped after point {len(result.q) - 1} "
            f"({result.reason}: {result.detail}); nothing written",
            hint="check that the path is reachable from --start (another --start, --solver analytic), "
            "or pass --min-fraction 0 to write the part achieved",
        )
    traj = Trajectory(
        tuple(chain.joint_names), result.q, source=str(urdf), prismatic=tuple(not r for r in chain.revolute)
    )
    _write(traj, output, _out_format(output, to, TrajFormat.CSV))
    if plot is not None:
        from armtool.traj.plot import write_cartesian_plot

        write_cartesian_plot(
            plot, chain, result.q, result.midpoint_deviation_m, result.midpoint_deviation_rad, precision, precision_rad
        )
        err.print(f"wrote {plot}")


MAX_WAYPOINT_BYTES = 16 * 1024 * 1024  # ~300 000 poses: far more than a taught path holds


def _waypoint_segments(path: Path, T0: Any) -> list[Segment]:
    import csv

    import numpy as np

    from armtool.fileio import read_text
    from armtool.model.chain import rpy_matrix
    from armtool.traj import cartesian as cart

    text = read_text(path, "waypoints file", MAX_WAYPOINT_BYTES)
    rows = [(i + 1, r) for i, r in enumerate(csv.reader(text.splitlines())) if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise ArmtoolError("no waypoints", str(path))
    header = [h.strip() for h in rows[0][1]]
    need = ["x_m", "y_m", "z_m"]
    if header[:3] != need or header[3:] not in ([], ["roll_rad", "pitch_rad", "yaw_rad"]):
        raise ArmtoolError("waypoint header must be x_m,y_m,z_m[,roll_rad,pitch_rad,yaw_rad]", f"{path}:{rows[0][0]}")
    poses = [np.asarray(T0)]
    for line_no, row in rows[1:]:
        where = f"{path}:{line_no}"
        if len(row) != len(header):
            raise ArmtoolError(f"row has {len(row)} fields, the header has {len(header)}", where)
        try:
            v = [float(c) for c in row]
        except ValueError:
            raise ArmtoolError("not a number in the row", where) from None
        if not all(math.isfinite(x) for x in v):
            raise ArmtoolError("the row holds a NaN or infinity", where)
        T = poses[-1].copy()
        T[:3, 3] = v[:3]
        if len(v) == 6:
            T[:3, :3] = rpy_matrix(*v[3:])
        poses.append(T)
    segs = [cart.line_segment(a, b) for a, b in zip(poses, poses[1:]) if np.abs(a - b).max() > 1e-12]
    if not segs:
        raise ArmtoolError("the waypoints do not move the tool", str(path))
    return segs


# ---- time / retime / thin / join ---------------------------------------------------------------
@app.command(
    "time",
    help="Time a joint path time-optimally (TOPP-RA), rest to rest, within velocity and acceleration limits.\n\n"
    + FORMATS_HELP,
)
def time_cmd(
    path: Path = typer.Argument(..., help="Joint path or trajectory (its times, if any, are ignored); - for stdin."),
    urdf: Path = typer.Option(..., "--urdf", help="URDF or xacro: joint names, position and velocity limits."),
    joint_limits: Path | None = typer.Option(
        None, "--joint-limits", help="MoveIt joint_limits.yaml (acceleration limits, scaling factors)."
    ),
    vel: list[str] = LIMIT_OPTS["vel"],
    acc: list[str] = LIMIT_OPTS["acc"],
    vscale: float | None = typer.Option(
        None,
        "--velocity-scaling",
        callback=finite_float(0.0, 1.0, lo_open=True),
        help="Fraction of the velocity limits to use (default: joint_limits.yaml's, else 1).",
    ),
    ascale: float | None = typer.Option(
        None,
        "--acceleration-scaling",
        callback=finite_float(0.0, 1.0, lo_open=True),
        help="Fraction of the acceleration limits to use (default: joint_limits.yaml's, else 1).",
    ),
    output: Path | None = OUTPUT_OPTS["output"],
    to: OutFormat | None = OUTPUT_OPTS["to"],
) -> None:
    require("traj")  # exit 2 with the install command when the extra is missing
    from armtool.console import stderr
    from armtool.traj.timing import time_optimal

    _check_outputs({"-o": output}, [path, urdf, joint_limits])
    traj, in_fmt = _read(path)
    limits = _limits(urdf, joint_limits, vel, acc, (), vscale, ascale)
    timed = time_optimal(traj, limits)
    if any(math.isfinite(j) for j in limits.jerk):
        stderr().print(
            "note: jerk limits are checked by `traj check`, not planned for: a time-optimal profile switches "
            "acceleration abruptly"
        )
    stderr().print(
        f"time-optimal: {timed.duration_s:.4f} s over {timed.n_points} samples "
        f"(velocity scaling {limits.velocity_scaling:g}, acceleration scaling {limits.acceleration_scaling:g})"
    )
    _write(timed, output, _out_format(output, to, in_fmt), limits)


@app.command(
    "retime",
    help="Scale a trajectory's speed exactly: time × 1/S, velocity × S, acceleration × S² (the lecture's scale_trajectory_speed).",
)
def retime_cmd(
    path: Path = typer.Argument(..., help="Timed trajectory; - for stdin."),
    scale: float = typer.Option(
        ..., "--scale", callback=positive_float(), help="Speed factor S > 0 (0.25: four times slower)."
    ),
    urdf: Path | None = typer.Option(
        None, "--urdf", help="Check the result against this URDF's limits before writing."
    ),
    joint_limits: Path | None = typer.Option(None, "--joint-limits", help="MoveIt joint_limits.yaml for that check."),
    acc: list[str] = LIMIT_OPTS["acc"],
    output: Path | None = OUTPUT_OPTS["output"],
    to: OutFormat | None = OUTPUT_OPTS["to"],
) -> None:
    require("traj")  # exit 2 with the install command when the extra is missing
    from armtool.traj.edit import retime

    _check_outputs({"-o": output}, [path, urdf, joint_limits])
    traj, in_fmt = _read(path)
    out = retime(traj, scale)
    limits = _limits(urdf, joint_limits, [], acc) if urdf is not None else None
    _write(
        out,
        output,
        _out_format(output, to, in_fmt),
        limits,
        "a smaller --scale, or leave out --urdf to write it unchecked",
    )


@app.command(
    "thin",
    help="Drop every K-th point (first and last kept; the lecture: 20 points -> 16 with --every 4), or points within a tolerance; re-time with --urdf.",
)
def thin_cmd(
    path: Path = typer.Argument(..., help="Trajectory or path; - for stdin."),
    every: int | None = typer.Option(None, "--every", help="Drop points K, 2K, 3K, ... (1-based)."),
    tolerance: float | None = typer.Option(
        None,
        "--tolerance",
        callback=positive_float(),
        help="Drop points within this joint-space distance (rad/m) of the path through the kept ones.",
    ),
    urdf: Path | None = typer.Option(
        None, "--urdf", help="Re-time the thinned path time-optimally within this URDF's limits."
    ),
    joint_limits: Path | None = typer.Option(
        None, "--joint-limits", help="MoveIt joint_limits.yaml (acceleration limits)."
    ),
    vel: list[str] = LIMIT_OPTS["vel"],
    acc: list[str] = LIMIT_OPTS["acc"],
    output: Path | None = OUTPUT_OPTS["output"],
    to: OutFormat | None = OUTPUT_OPTS["to"],
) -> None:
    require("traj")  # exit 2 with the install command when the extra is missing
    from armtool.console import stderr
    from armtool.traj.edit import thin

    _check_outputs({"-o": output}, [path, urdf, joint_limits])
    traj, in_fmt = _read(path)
    out = thin(traj, every, tolerance)
    stderr().print(f"thinned {traj.n_points} -> {out.n_points} points")
    out, limits = _retime_within(out, urdf, joint_limits, vel, acc)
    _write(out, output, _out_format(output, to, in_fmt), limits)


@app.command(
    "join",
    help="Join trajectories end to start (each start must meet the previous end) and re-time the whole with --urdf.",
)
def join_cmd(
    paths: list[Path] = typer.Argument(..., help="Two or more trajectories, in order."),
    tolerance: float = typer.Option(
        1e-3,
        "--tolerance",
        callback=finite_float(0.0),
        help="Largest gap per joint between an end and the next start (rad/m).",
    ),
    urdf: Path | None = typer.Option(
        None, "--urdf", help="Re-time the joined path time-optimally within this URDF's limits."
    ),
    joint_limits: Path | None = typer.Option(
        None, "--joint-limits", help="MoveIt joint_limits.yaml (acceleration limits)."
    ),
    vel: list[str] = LIMIT_OPTS["vel"],
    acc: list[str] = LIMIT_OPTS["acc"],
    output: Path | None = typer.Option(None, "--output", "-o", help="Write here (default: stdout)."),
    to: OutFormat | None = typer.Option(
        None, "--to", help="Output format (default: from -o's extension, else the first input's)."
    ),
) -> None:
    require("traj")  # exit 2 with the install command when the extra is missing
    from armtool.console import stderr
    from armtool.traj.edit import join

    _check_outputs({"-o": output}, [*paths, urdf, joint_limits])
    loaded = [_read(p) for p in paths]
    parts = [lt.trajectory for lt in loaded]
    out = join(parts, tolerance)
    stderr().print(f"joined {len(parts)} trajectories: {out.n_points} points")
    out, limits = _retime_within(out, urdf, joint_limits, vel, acc)
    _write(out, output, _out_format(output, to, loaded[0].format), limits)


# ---- check -------------------------------------------------------------------------------------
@app.command(
    "check",
    help="Check a trajectory against a URDF's limits: time, positions, velocity, acceleration, jerk, jumps, joints, rest. Exit 1 on findings.",
)
def check_cmd(
    path: Path = typer.Argument(..., help="Trajectory file; - for stdin."),
    urdf: Path = typer.Option(..., "--urdf", help="URDF or xacro with the joints' limits."),
    joint_limits: Path | None = typer.Option(
        None, "--joint-limits", help="MoveIt joint_limits.yaml (acceleration and jerk limits)."
    ),
    vel: list[str] = LIMIT_OPTS["vel"],
    acc: list[str] = LIMIT_OPTS["acc"],
    jerk: list[str] = typer.Option([], "--jerk-limit", help="Jerk limit: VALUE or JOINT=VALUE[,..]."),
    jump_factor: float = typer.Option(
        10.0,
        "--jump-factor",
        callback=finite_float(0.0),
        help="Relative jump rule for untimed paths: a step over FACTOR × the mean (0: off).",
    ),
    max_step: float | None = typer.Option(
        None,
        "--max-step",
        callback=finite_float(0.0),
        help="Absolute jump rule: largest step of any joint between points.",
    ),
    output_format: CheckFormat | None = typer.Option(
        None, "--format", help="text (default; github inside GitHub Actions), json, sarif, github."
    ),
    exit_zero: bool = typer.Option(False, "--exit-zero", help="Exit 0 even when problems are found."),
) -> None:
    require("traj")  # exit 2 with the install command when the extra is missing
    from armtool.console import stderr, write_stdout
    from armtool.traj.check import CheckOptions, check

    traj = _read(path).trajectory
    limits = _limits(urdf, joint_limits, vel, acc, jerk)
    no_acc = [
        n for n in traj.joint_names if n in limits.names and not math.isfinite(limits.acceleration[limits.index(n)])
    ]
    if no_acc and traj.times is not None:
        stderr().print(
            f"note: no acceleration limit for {', '.join(no_acc)}: accelerations not checked "
            "(give --joint-limits or --acc-limit)"
        )
    findings = check(traj, limits, CheckOptions(jump_factor=jump_factor, max_step=max_step))
    fmt = output_format or (CheckFormat.GITHUB if os.environ.get("GITHUB_ACTIONS") == "true" else CheckFormat.TEXT)
    write_stdout(_render(findings, fmt))
    failing = any(f.severity.value == "error" for f in findings)
    raise typer.Exit(ExitCode.FINDINGS if failing and not exit_zero else ExitCode.OK)


def _render(findings: list[Finding], fmt: CheckFormat) -> str:
    from armtool.output.base import LintReport
    from armtool.output.registry import OutputFormat, formatter

    report = LintReport(findings, 1)
    if fmt is CheckFormat.SARIF:
        from armtool.output.sarif import SarifFormatter
        from armtool.traj.check import sarif_tool

        return SarifFormatter(sarif_tool()).render(report, color=False)
    return formatter(OutputFormat(fmt.value)).render(report, color=sys.stdout.isatty() and "NO_COLOR" not in os.environ)


# ---- plot --------------------------------------------------------------------------------------
@app.command(
    "plot",
    help="Draw positions, velocities and accelerations per joint with their limits (PNG); with --tip also the tool path.",
)
def plot_cmd(
    path: Path = typer.Argument(..., help="Trajectory file; - for stdin."),
    urdf: Path = typer.Option(..., "--urdf", help="URDF or xacro with the joints' limits."),
    output: Path = typer.Option(..., "--output", "-o", help="PNG to write."),
    joint_limits: Path | None = typer.Option(
        None, "--joint-limits", help="MoveIt joint_limits.yaml (acceleration limits)."
    ),
    acc: list[str] = LIMIT_OPTS["acc"],
    base: str | None = typer.Option(None, "--base", help="Base link, for the tool path panel."),
    tip: str | None = typer.Option(None, "--tip", help="Tool link: also draw the tool path (x-y, x-z, y-z)."),
) -> None:
    require("traj")  # exit 2 with the install command when the extra is missing
    from armtool.console import stderr
    from armtool.traj.plot import write_plot

    _check_outputs({"-o": output}, [path, urdf, joint_limits])
    traj = _read(path).trajectory
    limits = _limits(urdf, joint_limits, [], acc)
    chain = None
    if tip is not None:
        from armtool.model.chain import load_chain

        chain = load_chain(urdf, base, tip)
    write_plot(output, traj, limits, chain)
    stderr().print(f"wrote {output}")
