"""The lecture's trajectory edits: uniform re-timing by a speed factor, thinning, joining.

`retime` is exact uniform time scaling (t × 1/S, q̇ × S, q̈ × S²): the same path, S times as fast;
MoveIt's velocity/acceleration "scaling factors" instead scale the limits and re-solve, which is a
different trajectory. `thin` drops points; `join` appends trajectories end to start. Thinning and
joining change the path's points, so their result is a path to be timed again (`time_optimal`).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from armtool.errors import ArmtoolError
from armtool.traj.trajectory import Trajectory


def retime(traj: Trajectory, scale: float) -> Trajectory:
    if not (math.isfinite(scale) and scale > 0):
        raise ArmtoolError(
            f"--scale must be a positive number, got {scale}", hint="e.g. --scale 0.25 for a quarter of the speed"
        )
    if traj.times is None:
        raise ArmtoolError("the trajectory has no times to scale", traj.source, hint="time it first: armtool traj time")
    t = traj.times[0] + (traj.times - traj.times[0]) / scale
    return replace(
        traj,
        times=t,
        velocities=None if traj.velocities is None else traj.velocities * scale,
        accelerations=None if traj.accelerations is None else traj.accelerations * scale**2,
    )


def thin(traj: Trajectory, every: int | None = None, tolerance: float | None = None) -> Trajectory:
    """Drop every `every`-th point (the lecture: 20 points, every 4th dropped, 16 left), or every
    point that lies within `tolerance` (rad/m, each joint) of the straight joint-space segment between
    its kept neighbours. First and last are always kept. The result is an untimed path."""
    n = traj.n_points
    if n < 2:
        raise ArmtoolError("a path needs at least two points", traj.source)
    if (every is None) == (tolerance is None):
        raise ArmtoolError(
            "give exactly one of --every K or --tolerance TOL", hint="--every 4 drops every fourth point"
        )
    if every is not None:
        if every < 2:
            raise ArmtoolError(
                f"--every must be 2 or more, got {every}", hint="--every 4 drops points 4, 8, 12, ... (1-based)"
            )
        keep = np.array([(i + 1) % every != 0 for i in range(n)])
    else:
        assert tolerance is not None
        if not (math.isfinite(tolerance) and tolerance > 0):
            raise ArmtoolError(f"--tolerance must be a positive number, got {tolerance}")
        keep = _simplify(traj.positions, tolerance)
    keep[0] = keep[-1] = True
    idx = np.flatnonzero(keep)
    return replace(
        traj,
        positions=traj.positions[idx],
        times=None,
        velocities=None,
        accelerations=None,
        lines=tuple(traj.lines[i] for i in idx) if traj.lines else (),
    )


def _simplify(q: np.ndarray, tol: float) -> np.ndarray:
    """Ramer–Douglas–Peucker in joint space with the max-norm of the deviation from the chord."""
    keep = np.zeros(len(q), dtype=bool)
    keep[0] = keep[-1] = True
    stack = [(0, len(q) - 1)]
    while stack:
        a, b = stack.pop()
        if b - a < 2:
            continue
        seg = q[b] - q[a]
        denom = float(seg @ seg)
        inner = q[a + 1 : b]
        lam = np.clip(((inner - q[a]) @ seg) / denom, 0, 1) if denom > 0 else np.zeros(len(inner))
        dev = np.abs(inner - (q[a] + lam[:, None] * seg)).max(axis=1)
        k = int(np.argmax(dev))
        if dev[k] > tol:
            m = a + 1 + k
            keep[m] = True
            stack += [(a, m), (m, b)]
    return keep


def join(parts: list[Trajectory], tolerance: float) -> Trajectory:
    """One path through every part's points in order (each next start, equal to the previous end
    within `tolerance` per joint, is dropped). Joints are matched by name to the first part's."""
    if len(parts) < 2:
        raise ArmtoolError("join needs at least two trajectories")
    names = parts[0].joint_names
    rows = [parts[0].positions]
    for prev, part in zip(parts, parts[1:]):
        if set(part.joint_names) != set(names):
            raise ArmtoolError(
                f"{part.source} has joints {', '.join(part.joint_names)}, {parts[0].source} has {', '.join(names)}",
                part.source,
                hint="join trajectories of the same joints",
            )
        part = part.reorder(names)
        prev_end = rows[-1][-1]
        gap = np.abs(part.positions[0] - prev_end)
        if gap.max() > tolerance:
            j = int(np.argmax(gap))
            raise ArmtoolError(
                f"{part.source} starts {gap[j]:.6g} {part.unit(j)} away from where {prev.source} ends (joint '{names[j]}': "
                f"{part.positions[0, j]:.6g} vs {prev_end[j]:.6g}), more than the tolerance {tolerance:g}",
                part.where(0),
                hint="plan the second trajectory from the first one's end state, or raise --tolerance",
            )
        rows.append(part.positions[1:])
    q = np.concatenate(rows)
    return Trajectory(names, q, None, None, None, f"join({', '.join(p.source for p in parts)})", (), parts[0].prismatic)
