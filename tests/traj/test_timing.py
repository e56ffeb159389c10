"""Time-optimal timing: the bang-bang optimum on a straight path, no limit exceeded between samples on
random paths, an acceleration limit demanded (effort is not one), and the path's shape kept."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.traj.check import check, hermite_extremes
from armtool.traj.limits import load_limits
from armtool.traj.path import joint_path
from armtool.traj.timing import time_optimal
from armtool.traj.trajectory import Trajectory

from .helpers import CLEAN_URDF, JOINTS, clean_limits, random_path


@pytest.mark.parametrize("distance, expected", [(2.0, 2.0 / 2.0 + 2.0 / 4.0), (0.5, 2 * np.sqrt(0.5 / 4.0))])
def test_straight_single_joint_move_is_the_trapezoid_optimum(distance: float, expected: float) -> None:
    # joint1: v 2 rad/s, a 4 rad/s² (fixture). Cruise: D/v + v/a; triangle: 2√(D/a).
    q = np.zeros((2, 6))
    q[1, 0] = distance
    timed = time_optimal(Trajectory(JOINTS, q), clean_limits())
    assert timed.duration_s == pytest.approx(expected, rel=5e-3)
    assert timed.duration_s >= expected * (1 - 1e-6)  # never faster than physics allows


@pytest.mark.parametrize("seed", range(6))
def test_random_paths_stay_within_limits_between_samples(seed: int) -> None:
    limits = clean_limits()
    timed = time_optimal(random_path(seed, points=6), limits)
    assert [f.code for f in check(timed, limits)] == []
    lim = limits.subset(JOINTS)
    vmax, amax, _ = hermite_extremes(timed.times, timed.positions, timed.velocities)
    assert np.all(vmax <= lim.velocity * (1 + 1e-6)) and np.all(amax <= lim.acceleration * (1 + 1e-3))
    assert np.all(np.abs(timed.velocities[[0, -1]]) < 1e-9)  # rest to rest


def test_timed_path_passes_through_the_waypoints() -> None:
    path = random_path(3)
    timed = time_optimal(path, clean_limits())
    spline = joint_path(path.positions)
    dense = spline.spline(np.linspace(0, spline.length, 400))
    for wp in path.positions:
        assert np.min(np.abs(timed.positions - wp).max(axis=1)) < 1e-9
    assert np.abs(timed.positions[:, None, :] - dense[None]).max(axis=2).min(axis=1).max() < 0.05


def test_missing_acceleration_limit_is_an_error_saying_where_to_give_it() -> None:
    limits = load_limits(CLEAN_URDF)  # URDF only: velocity and effort, no acceleration
    with pytest.raises(ArmtoolError) as err:
        time_optimal(random_path(0), limits)
    assert "acceleration" in err.value.what and "joint_limits.yaml" in (err.value.hint or "")
    assert "effort" in (err.value.hint or "")


def test_scaling_factors_scale_the_limits() -> None:
    full = time_optimal(random_path(2), clean_limits())
    half = time_optimal(
        random_path(2), load_limits(CLEAN_URDF, acc_limits=["4"], velocity_scaling=0.5, acceleration_scaling=0.25)
    )
    assert half.duration_s > full.duration_s * 1.5


def test_one_point_path_is_refused() -> None:
    with pytest.raises(ArmtoolError, match="at least two points"):
        time_optimal(Trajectory(JOINTS, np.zeros((1, 6))), clean_limits())


def test_spline_leaving_the_position_limits_is_refused() -> None:
    q = np.zeros((4, 6))
    q[:, 1] = [0, 1.9, 1.999, 1.0]  # joint2 (limit 2.0) turns back just below its limit: the spline overshoots
    q[:, 0] = [0, 0.05, 0.3, 1.5]
    with pytest.raises(ArmtoolError, match="leaves joint 'joint2' limits"):
        time_optimal(Trajectory(JOINTS, q), clean_limits())


def test_within_one_percent_of_toppra() -> None:
    ta = pytest.importorskip("toppra")
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    limits = clean_limits()
    lim = limits.subset(JOINTS)
    for seed in range(3):
        path = random_path(seed, points=5)
        ours = time_optimal(path, limits)
        spline = joint_path(path.positions)
        tp = ta.SplineInterpolator(spline.s, spline.waypoints, bc_type="natural")
        vlim = np.stack([-lim.velocity, lim.velocity], axis=1)
        alim = np.stack([-lim.acceleration, lim.acceleration], axis=1)
        inst = algo.TOPPRA(
            [constraint.JointVelocityConstraint(vlim), constraint.JointAccelerationConstraint(alim)],
            tp,
            parametrizer="ParametrizeConstAccel",
            gridpoints=np.linspace(0, spline.length, 401),
        )
        ref = inst.compute_trajectory()
        assert ours.duration_s <= ref.duration * 1.01
