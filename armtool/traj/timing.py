"""`traj time`: the time-optimal rest-to-rest timing of a joint path, sampled on the TOPP-RA grid
(with jerk limits: smoothed, `armtool.traj.smooth`).

The path through the waypoints is a natural cubic spline per joint, except for a joint whose
spline would leave its position limits between waypoints: that joint follows a shape-preserving
cubic (PCHIP), which stays between its waypoints (`armtool.traj.path`). A path is refused only
when a waypoint itself lies outside the limits. The timing is time-optimal for the path so made,
and `TimedPath.interpolation` says which interpolation each joint follows.

The written samples (t, q, q̇, q̈) are checked with `armtool.traj.check` itself (cubic Hermite
between samples, exactly); if rounding between grid points puts a segment over a limit, the
affected limits are tightened by the excess and the path is timed again. A result is never
returned over a limit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armtool.errors import ArmtoolError
from armtool.traj.check import ACC_TOL, VEL_TOL, hermite_extremes
from armtool.traj.limits import JointLimits
from armtool.traj.path import joint_path
from armtool.traj.topp import parameterize
from armtool.traj.trajectory import Trajectory

_MARGIN = 1e-4  # plan this far inside the limits: the grid is exact only at its points


@dataclass(frozen=True)
class TimedPath:
    trajectory: Trajectory
    interpolation: str  # which interpolation the path follows between its waypoints, per joint


def time_optimal(traj: Trajectory, limits: JointLimits, min_stages: int = 400) -> Trajectory:
    """`traj`'s positions as a path, timed time-optimally under `limits` (joints matched by name).
    With a jerk limit on any joint, the jerk-limited timing of `armtool.traj.smooth` instead."""
    return time_path(traj, limits, min_stages).trajectory


def time_path(traj: Trajectory, limits: JointLimits, min_stages: int = 400) -> TimedPath:
    """time_optimal, saying which interpolation the path follows between its waypoints."""
    from armtool.traj.topp import grid

    missing = [n for n in traj.joint_names if n not in limits.names]
    if missing:
        raise ArmtoolError(
            f"joint(s) {', '.join(missing)} are not moving joints of the URDF",
            traj.source,
            hint="URDF joints: " + ", ".join(limits.names),
        )
    lim = limits.subset(traj.joint_names)
    lim.require_acceleration()
    vel, acc = lim.scaled()
    _waypoints_within_limits(traj, lim)
    path = joint_path(traj.positions, traj.source, lim.lower, lim.upper)
    how = path.interpolation(lim.names)
    s_grid = grid(path, min_stages)
    if lim.has_jerk_limits():
        from armtool.traj.smooth import jerk_limited

        return TimedPath(jerk_limited(traj, lim, path, s_grid, vel, acc), how)
    v_plan, a_plan = vel * (1 - _MARGIN), acc * (1 - _MARGIN)
    for _ in range(8):
        profile = parameterize(path, v_plan, a_plan, s_grid)
        q, dq, ddq = path.eval(profile.s)
        sdot = np.sqrt(profile.x)[:, None]
        u = np.concatenate([profile.u, profile.u[-1:]])[:, None]
        qd = dq * sdot
        qdd = dq * u + ddq * profile.x[:, None]
        qdd[-1] = dq[-1] * profile.u[-1] + ddq[-1] * profile.x[-1]
        vmax, amax, _ = hermite_extremes(profile.t, q, qd)
        v_ratio = np.max(np.concatenate([vmax, np.abs(qd)]), axis=0) / vel
        a_ratio = np.max(np.concatenate([amax, np.abs(qdd)]), axis=0) / acc
        if np.all(v_ratio <= 1 + VEL_TOL) and np.all(a_ratio <= 1 + ACC_TOL):
            return TimedPath(Trajectory(traj.joint_names, q, profile.t, qd, qdd, traj.source, (), lim.prismatic), how)
        v_plan = np.where(v_ratio > 1, v_plan / np.maximum(v_ratio, 1.0) * (1 - _MARGIN), v_plan)
        a_plan = np.where(a_ratio > 1 + ACC_TOL / 2, a_plan / np.maximum(a_ratio, 1.0) * (1 - _MARGIN), a_plan)
    raise ArmtoolError(
        "could not time the path within the limits between its samples",
        traj.source,
        hint="the path may have a corner or a very tight curve; give it more waypoints",
    )


def _waypoints_within_limits(traj: Trajectory, lim: JointLimits) -> None:
    """Every waypoint within the joints' position limits: the interpolation between them then is too."""
    q = traj.positions
    over = (q < lim.lower - 1e-9) | (q > lim.upper + 1e-9)
    if over.any():
        k, j = (int(v) for v in np.argwhere(over)[0])
        raise ArmtoolError(
            f"waypoint {k}: joint '{lim.names[j]}' is at {q[k, j]:.6g}, outside its limits "
            f"[{lim.lower[j]:.6g}, {lim.upper[j]:.6g}]",
            traj.where(k),
            hint="move the waypoint within the limits (`armtool traj check` lists every such point)",
        )
