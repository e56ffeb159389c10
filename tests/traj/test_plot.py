"""`traj plot` and `traj cartesian --plot`'s figures, read from the matplotlib Figure: a panel per
joint and quantity with the limits drawn as lines, the tool path's projections with a chain, and
the Cartesian path's deviation against its bounds."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.model.chain import load_chain
from armtool.traj.plot import cartesian_figure, trajectory_figure
from armtool.traj.trajectory import Trajectory

from .helpers import CLEAN_URDF, JOINTS, clean_limits, random_path


def _limit_lines(ax: object) -> list[float]:
    return sorted(float(line.get_ydata()[0]) for line in ax.get_lines() if line.get_linestyle() == "--")  # type: ignore[attr-defined]


def test_a_timed_trajectory_has_position_velocity_and_acceleration_per_joint_with_their_limits() -> None:
    path = random_path(1, points=30)
    t = np.linspace(0.0, 2.0, path.n_points)
    traj = Trajectory(path.joint_names, path.positions, times=t, source="timed.csv")
    limits = clean_limits()
    fig = trajectory_figure(traj, limits)
    axes = {ax.get_title(loc="left"): ax for ax in fig.get_axes()}
    assert len(axes) == 3 * len(JOINTS)
    k = limits.names.index("joint2")
    assert _limit_lines(axes["joint2 position (rad)"]) == pytest.approx([limits.lower[k], limits.upper[k]])
    v, a = float(limits.velocity[k]), float(limits.acceleration[k])
    assert _limit_lines(axes["joint2 velocity (rad/s)"]) == pytest.approx([-v, v])
    assert _limit_lines(axes["joint2 acceleration (rad/s²)"]) == pytest.approx([-a, a])
    assert axes["joint6 acceleration (rad/s²)"].get_xlabel() == "time (s)"
    (curve,) = [line for line in axes["joint3 position (rad)"].get_lines() if line.get_linestyle() == "-"]
    assert np.allclose(curve.get_xdata(), t) and np.allclose(curve.get_ydata(), traj.positions[:, 2])
    assert fig.get_suptitle() == "timed.csv: 30 points; red dashed: the limits"


def test_an_untimed_path_over_the_point_index_and_the_tool_path_with_a_chain() -> None:
    chain = load_chain(CLEAN_URDF, "base_link", "tool0")
    fig = trajectory_figure(random_path(2, points=8), clean_limits(), chain)
    titles = [ax.get_title(loc="left") for ax in fig.get_axes()]
    assert titles[: len(JOINTS)] == [f"{j} position (rad)" for j in JOINTS]  # no velocity without times
    assert titles[len(JOINTS) :] == ["tool path x-y", "tool path x-z", "tool path y-z"]
    assert fig.get_axes()[len(JOINTS) - 1].get_xlabel() == "point"
    xy = fig.get_axes()[len(JOINTS)]
    assert xy.get_xlabel() == "x (m)" and xy.get_ylabel() == "y (m)" and xy.get_aspect() == 1.0


def test_a_chain_joint_missing_from_the_trajectory_is_named() -> None:
    chain = load_chain(CLEAN_URDF, "base_link", "tool0")
    path = random_path(3)
    short = Trajectory(path.joint_names[:5], path.positions[:, :5], source="short.csv")
    with pytest.raises(ArmtoolError, match="lacks joint\\(s\\) joint6"):
        trajectory_figure(short, clean_limits(), chain)


def test_the_cartesian_figure_draws_the_deviation_against_the_precision_bounds() -> None:
    chain = load_chain(CLEAN_URDF, "base_link", "tool0")
    q = random_path(4, points=6).positions
    dev_m, dev_rad = np.array([1e-4, 3e-4, 2e-4, 5e-4, 1e-4]), np.array([1e-3, 2e-3, 1e-3, 4e-3, 2e-3])
    fig = cartesian_figure(chain, q, dev_m, dev_rad, 1e-3, 0.01)
    axes = {ax.get_title(loc="left"): ax for ax in fig.get_axes()}
    mm, rad = axes["midpoint deviation per step (mm)"], axes["midpoint deviation per step (rad)"]
    assert _limit_lines(mm) == pytest.approx([1.0]) and _limit_lines(rad) == pytest.approx([0.01])
    (curve,) = [line for line in mm.get_lines() if line.get_linestyle() == "-"]
    assert np.allclose(curve.get_ydata(), dev_m * 1000)
    assert {"tool path x-y", "tool path x-z", "tool path y-z"} <= set(axes)
    assert fig.get_suptitle().startswith("base_link → tool0: 6 points")
