"""The figures of `traj plot` and `traj cartesian --plot` (PNG, SVG or PDF, by the extension).

- A trajectory: per joint its position, velocity and acceleration over time (over the point index
  for an untimed path), the limits as red dashed lines; with a chain, the tool path in three
  projections. Velocities and accelerations are the file's own if it has them, else finite
  differences.
- A Cartesian path: the tool path in three projections and, per step, how far the tool at the
  joint midpoint lies from the ideal path (the precision check's measure), against the bounds.

Drawn with matplotlib in armtool's one style (`armtool.plotting`), as `calibrate fit --plot` and
`ik-bench --plot` are.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from armtool import plotting
from armtool.errors import ArmtoolError
from armtool.model.chain import Chain
from armtool.traj.limits import JointLimits
from armtool.traj.trajectory import Array, Trajectory

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure

_PROJECTIONS = ((0, 1, "x", "y"), (0, 2, "x", "z"), (1, 2, "y", "z"))


def _series(traj: Trajectory) -> tuple[Array, Array, Array | None, Array | None, str]:
    q = traj.positions
    if traj.times is None:
        return np.arange(traj.n_points, dtype=np.float64), q, None, None, "point"
    t = traj.times
    v = traj.velocities if traj.velocities is not None else np.gradient(q, t, axis=0)
    a = traj.accelerations if traj.accelerations is not None else np.gradient(v, t, axis=0)
    return t, q, v, a, "time (s)"


def _curve(ax: Axes, x: Array, y: Array, bounds: tuple[float, ...], title: str) -> None:
    """A quantity over x with its bounds (red dashed; a non-finite bound is not drawn)."""
    ax.plot(x, y, color=plotting.CALIBRATED, linewidth=1.2, marker="." if len(x) < 50 else None)
    for bound in bounds:
        if math.isfinite(bound):
            ax.axhline(bound, color=plotting.LIMIT, linestyle="--", linewidth=1.0)
    ax.set_title(title, loc="left")


def _tool_path(sub: Figure | SubFigure, P: Array) -> None:
    """The tool path's three projections, equal aspect, in metres."""
    for ax, (i, k, a, b) in zip(sub.subplots(1, 3), _PROJECTIONS):
        ax.plot(P[:, i], P[:, k], color=plotting.CALIBRATED, linewidth=1.2)
        ax.plot(P[0, i], P[0, k], "o", color=plotting.NOMINAL, markersize=4, label="start")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(f"tool path {a}-{b}", loc="left")
        ax.set_xlabel(f"{a} (m)")
        ax.set_ylabel(f"{b} (m)")
    sub.axes[0].legend(loc="best")


def trajectory_figure(traj: Trajectory, limits: JointLimits, chain: Chain | None = None) -> Figure:
    """Per joint its position (velocity, acceleration) with the limits; the tool path with a chain."""
    x, q, v, a, xlabel = _series(traj)
    P = None
    if chain is not None:
        missing = [nm for nm in chain.joint_names if nm not in traj.joint_names]
        if missing:
            raise ArmtoolError(
                f"the trajectory lacks joint(s) {', '.join(missing)} of the chain {chain.base} -> {chain.tip}",
                traj.source,
            )
        P = np.array([chain.fk(qi)[:3, 3] for qi in traj.reorder(chain.joint_names).positions])
    n = len(traj.joint_names)
    cols = 1 if v is None else 3
    joints_height = 1.7 * n
    path_height = 3.2 if P is not None else 0.0
    with plotting.style():
        fig = plotting.figure(4.4 * cols if cols == 3 else 7.0, joints_height + path_height + 0.6)
        joints_fig: Figure | SubFigure = fig
        path_fig: SubFigure | None = None
        if P is not None:
            joints_fig, path_fig = fig.subfigures(2, 1, squeeze=False, height_ratios=[joints_height, path_height])[:, 0]
        axes = joints_fig.subplots(n, cols, sharex=True, squeeze=False)
        for j, name in enumerate(traj.joint_names):
            k = limits.names.index(name) if name in limits.names else None
            unit = "m" if (k is not None and limits.prismatic[k]) else "rad"
            lower = float(limits.lower[k]) if k is not None else math.nan
            upper = float(limits.upper[k]) if k is not None else math.nan
            _curve(axes[j, 0], x, q[:, j], (lower, upper), f"{name} position ({unit})")
            if v is not None and a is not None:
                vl = float(limits.velocity[k]) if k is not None else math.nan
                al = float(limits.acceleration[k]) if k is not None else math.nan
                _curve(axes[j, 1], x, v[:, j], (-vl, vl), f"{name} velocity ({unit}/s)")
                _curve(axes[j, 2], x, a[:, j], (-al, al), f"{name} acceleration ({unit}/s²)")
        for ax in axes[-1]:
            ax.set_xlabel(xlabel)
        if P is not None and path_fig is not None:
            _tool_path(path_fig, P)
        fig.suptitle(
            f"{traj.source}: {traj.n_points} points; red dashed: the limits",
            horizontalalignment="left",
            x=0.01,
        )
    return fig


def cartesian_figure(
    chain: Chain, q: Array, dev_m: Array, dev_rad: Array, precision_m: float, precision_rad: float
) -> Figure:
    """The tool path of a Cartesian joint path (three projections) and, per step, how far the tool at
    the joint midpoint lies from the ideal path, with the --precision bounds."""
    P = np.array([chain.fk(qi)[:3, 3] for qi in q])
    steps = np.arange(len(dev_m), dtype=np.float64)
    with plotting.style():
        fig = plotting.figure(12.0, 7.0)
        top, bottom = fig.subfigures(2, 1, squeeze=False, height_ratios=[1.1, 1.0])[:, 0]
        _tool_path(top, P)
        left, right = bottom.subplots(1, 2)
        _curve(left, steps, dev_m * 1000, (precision_m * 1000,), "midpoint deviation per step (mm)")
        _curve(right, steps, dev_rad, (precision_rad,), "midpoint deviation per step (rad)")
        for ax in (left, right):
            ax.set_xlabel("step")
            ax.set_ylim(bottom=0)
        fig.suptitle(
            f"{chain.base} → {chain.tip}: {len(q)} points; red dashed: the --precision bounds",
            horizontalalignment="left",
            x=0.01,
        )
    return fig


def write_plot(path: Path, traj: Trajectory, limits: JointLimits, chain: Chain | None = None) -> None:
    plotting.save(trajectory_figure(traj, limits, chain), path, "-o")


def write_cartesian_plot(
    path: Path, chain: Chain, q: Array, dev_m: Array, dev_rad: Array, precision_m: float, precision_rad: float
) -> None:
    plotting.save(cartesian_figure(chain, q, dev_m, dev_rad, precision_m, precision_rad), path)
