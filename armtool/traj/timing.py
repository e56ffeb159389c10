"""`traj time`: the time-optimal rest-to-rest timing of a joint path, sampled on the TOPP-RA grid
(with jerk limits: smoothed, `armtool.traj.smooth`).

The written samples (t, q, q̇, q̈) are checked with `armtool.traj.check` itself (cubic Hermite
between samples, exactly); if rounding between grid points puts a segment over a limit, the
affected limits are tightened by the excess and the path is timed again. A result is never
returned over a limit.
"""

from __future__ import annotations

import numpy as np

from armtool.errors import ArmtoolError
from armtool.traj.check import ACC_TOL, VEL_TOL, hermite_extremes
from armtool.traj.limits import JointLimits
from armtool.traj.path import JointPath, joint_path
from armtool.traj.topp import parameterize
from armtool.traj.trajectory import Trajectory

_MARGIN = 1e-4  # plan this far inside the limits: the grid is exact only at its points


def time_optimal(traj: Trajectory, limits: JointLimits, min_stages: int = 400) -> Trajectory:
    """`traj`'s positions as a path, timed time-optimally under `limits` (joints matched by name).
    With a jerk limit on any joint, the jerk-limited timing of `armtool.traj.smooth` instead."""
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
    path = joint_path(traj.positions, traj.source)
    s_grid = grid(path, min_stages)
    _within_position_limits(path, lim, traj)
    if lim.has_jerk_limits():
        from armtool.traj.smooth import jerk_limited

        return jerk_limited(traj, lim, path, s_grid, vel, acc)
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
            return Trajectory(traj.joint_names, q, profile.t, qd, qdd, traj.source, (), lim.prismatic)
        v_plan = np.where(v_ratio > 1, v_plan / np.maximum(v_ratio, 1.0) * (1 - _MARGIN), v_plan)
        a_plan = np.where(a_ratio > 1 + ACC_TOL / 2, a_plan / np.maximum(a_ratio, 1.0) * (1 - _MARGIN), a_plan)
    raise ArmtoolError(
        "could not time the path within the limits between its samples",
        traj.source,
        hint="the path may have a corner or a very tight curve; give it more waypoints",
    )


def _within_position_limits(path: JointPath, lim: JointLimits, traj: Trajectory) -> None:
    """The spline between the waypoints must stay within the joints' position limits."""
    dense = np.linspace(0.0, path.length, 20 * len(path.s))
    q = path.spline(dense)
    over = (q < lim.lower - 1e-9) | (q > lim.upper + 1e-9)
    if over.any():
        k, j = np.argwhere(over)[0]
        seg = int(np.searchsorted(path.s, dense[k]) - 1)
        raise ArmtoolError(
            f"the smooth path through the waypoints leaves joint '{lim.names[j]}' limits "
            f"[{lim.lower[j]:.6g}, {lim.upper[j]:.6g}] between waypoints {seg} and {seg + 1} (reaches {q[k, j]:.6g})",
            traj.source,
            hint="add a waypoint there, or keep the waypoints further from the limit",
        )
