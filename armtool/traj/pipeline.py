"""The steps every `armtool traj` command shares: read a trajectory (or stdin), load the limits,
re-time, check what is about to be written, render `check`'s findings. The CLI calls these and
only prints; a step that fails raises ArmtoolError (exit 2) before anything is written."""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from armtool.errors import ArmtoolError
from armtool.lint.finding import Finding
from armtool.output.registry import OutputFormat
from armtool.traj.choices import TrajFormat
from armtool.traj.formats import LoadedTrajectory, format_trajectory, read_trajectory
from armtool.traj.limits import JointLimits, load_limits
from armtool.traj.trajectory import Trajectory

BUG_HINT = "this is a bug in armtool traj; please report it with the input"


@dataclass(frozen=True)
class LimitSources:
    """Where a command's limits come from: the URDF, MoveIt's joint_limits.yaml, and options
    (`--vel-limit` and the others: VALUE for every joint or JOINT=VALUE[,..])."""

    urdf: Path
    joint_limits: Path | None = None
    vel: Sequence[str] = ()
    acc: Sequence[str] = ()
    jerk: Sequence[str] = ()
    velocity_scaling: float | None = None
    acceleration_scaling: float | None = None
    xacro_args: tuple[tuple[str, str], ...] = ()  # for a xacro robot
    package_paths: tuple[Path, ...] = ()

    def load(self) -> JointLimits:
        for path, what in ((self.urdf, "URDF"), (self.joint_limits, "joint_limits.yaml")):
            if path is not None and path.exists() and not path.is_file():
                raise ArmtoolError(f"{what} is not a regular file (a FIFO, socket, device or directory)", str(path))
        if not self.urdf.is_file():
            raise ArmtoolError("URDF not found", str(self.urdf), "pass --urdf path/to/robot.urdf (or .xacro)")
        if self.joint_limits is not None and not self.joint_limits.is_file():
            raise ArmtoolError("joint_limits.yaml not found", str(self.joint_limits))
        return load_limits(
            self.urdf,
            self.joint_limits,
            vel_limits=self.vel,
            acc_limits=self.acc,
            jerk_limits=self.jerk,
            velocity_scaling=self.velocity_scaling,
            acceleration_scaling=self.acceleration_scaling,
            xacro_args=dict(self.xacro_args),
            package_paths=self.package_paths,
        )


def read_input(path: Path) -> LoadedTrajectory:
    """The trajectory and its detected format (the default output format); `-` reads stdin."""
    if str(path) == "-":
        return read_trajectory("<stdin>", sys.stdin.read())
    return read_trajectory(path)


def retime(traj: Trajectory, sources: LimitSources | None) -> tuple[Trajectory, JointLimits | None, str]:
    """thin's and join's optional --urdf: the edited path timed within the limits (time-optimal, or
    jerk-limited when a joint has a jerk limit) and the interpolation it follows; unchanged
    without --urdf."""
    if sources is None:
        return traj, None, ""
    from armtool.traj.timing import time_path

    limits = sources.load()
    done = time_path(traj, limits)
    return done.trajectory, limits, done.interpolation


def checked_text(traj: Trajectory, fmt: TrajFormat, limits: JointLimits | None, hint: str = BUG_HINT) -> str:
    """`traj` in `fmt`, after `traj check` found no error in it against `limits` (when given and
    the trajectory is timed): armtool never writes a trajectory over a limit."""
    if limits is not None and traj.times is not None:
        from armtool.traj.check import check

        errors = [f for f in check(traj, limits) if f.severity.value == "error"]
        if errors:
            raise ArmtoolError(
                f"the result fails `traj check`: {errors[0].code} {errors[0].message}; nothing written", hint=hint
            )
    return format_trajectory(traj, fmt)


def without_acceleration_limit(traj: Trajectory, limits: JointLimits) -> list[str]:
    """Joints of a timed trajectory whose accelerations `check` cannot judge (no limit given)."""
    if traj.times is None:
        return []
    return [
        n for n in traj.joint_names if n in limits.names and not math.isfinite(limits.acceleration[limits.index(n)])
    ]


def render_findings(findings: list[Finding], fmt: OutputFormat, color: bool) -> str:
    """`traj check`'s report in a lint output format (SARIF with the T codes as its rules)."""
    from armtool.output.base import LintReport
    from armtool.output.registry import formatter

    report = LintReport(findings, 1)
    if fmt is OutputFormat.SARIF:
        from armtool.output.sarif import SarifFormatter
        from armtool.traj.check import sarif_tool

        return SarifFormatter(sarif_tool()).render(report, color=False)
    return formatter(fmt).render(report, color=color)
