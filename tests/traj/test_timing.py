"""Time-optimal timing: the bang-bang optimum on a straight path, no limit exceeded between samples on
random paths, an acceleration limit demanded (effort is not one), and the path's shape kept."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.traj.check import check, hermite_extremes
from armtool.traj.limits import load_limits
from armtool.traj.path import joint_path
from armtool.traj.timing import time_optimal, time_path
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


def _turning_near_the_limit() -> Trajectory:
    q = np.zeros((4, 6))
    q[:, 1] = [0, 1.9, 1.999, 1.0]  # joint2 (limit 2.0) turns back just below its limit: the spline overshoots
    q[:, 0] = [0, 0.05, 0.3, 1.5]
    return Trajectory(JOINTS, q)


def test_a_joint_whose_spline_leaves_its_limits_follows_a_shape_preserving_cubic() -> None:
    limits = clean_limits()
    lim = limits.subset(JOINTS)
    path = _turning_near_the_limit()
    natural = joint_path(path.positions)
    assert natural.spline(np.linspace(0, natural.length, 400))[:, 1].max() > 2.0  # what used to be refused
    shaped = joint_path(path.positions, lower=lim.lower, upper=lim.upper)
    assert shaped.shape_preserving == (1,)  # joint2 only: the others keep the C2 natural spline
    timed = time_path(path, limits)
    assert "shape-preserving cubic (PCHIP) for 'joint2'" in timed.interpolation
    assert "natural cubic spline for the other joints" in timed.interpolation
    assert check(timed.trajectory, limits) == []  # within every limit, also between the samples
    assert timed.trajectory.positions[:, 1].max() <= 2.0
    for wp in path.positions:  # still through every waypoint
        assert np.min(np.abs(timed.trajectory.positions - wp).max(axis=1)) < 1e-9
    assert "natural cubic spline through the waypoints" == time_path(random_path(0), limits).interpolation


@pytest.mark.parametrize("make", [_turning_near_the_limit, lambda: random_path(4), lambda: random_path(1)])
def test_the_timing_is_time_optimal_for_the_path_it_follows(make: object) -> None:
    # Time-optimal (bang-bang): on every segment some joint reaches its velocity or acceleration
    # limit (as `traj check` measures it, between the samples); a slack stretch would be time given
    # away. Single segments where the profile switches from speeding up to slowing down fall short
    # on the grid. A path timed 5 % slower than this fails the test.
    limits = clean_limits()
    lim = limits.subset(JOINTS)
    timed = time_optimal(make(), limits)  # type: ignore[operator]
    for slower in (1.0, 1.05):
        vmax, amax, _ = hermite_extremes(timed.times * slower, timed.positions, timed.velocities / slower)
        reach = np.maximum(np.max(vmax / lim.velocity, axis=1), np.max(amax / lim.acceleration, axis=1))
        saturated = float(np.mean(reach > 0.97))
        assert (saturated > 0.99 and reach.min() > 0.75) if slower == 1.0 else saturated < 0.5


def test_a_waypoint_outside_the_limits_is_refused_with_its_line() -> None:
    q = _turning_near_the_limit().positions.copy()
    q[2, 1] = 2.1
    with pytest.raises(ArmtoolError) as err:
        time_optimal(Trajectory(JOINTS, q, source="p.csv", lines=(2, 3, 4, 5)), clean_limits())
    assert err.value.what == "waypoint 2: joint 'joint2' is at 2.1, outside its limits [-2, 2]"
    assert err.value.where == "p.csv:4"


def test_a_panda_path_turning_near_joint2s_limit_is_timed_within_it() -> None:
    # The case: Panda's joint 2 (±1.7628 rad) turning back near its limit.
    from tests.ik.robots import erd

    urdf = erd("panda_description/urdf/panda.urdf")
    limits = load_limits(urdf, acc_limits=["5"])
    names = tuple(f"panda_joint{i}" for i in range(1, 8))
    q = np.zeros((5, 7))
    q[:, 0] = [0.0, 0.05, 0.1, 0.6, 1.2]
    q[:, 1] = [0.0, 1.5, 1.76, 1.2, 0.4]  # the natural spline reaches 1.784 between waypoints 2 and 3
    q[:, 3] = -1.5
    path = Trajectory(names, q)
    assert joint_path(q).spline(np.linspace(0, joint_path(q).length, 500))[:, 1].max() > 1.7628
    timed = time_path(path, limits)
    assert "'panda_joint2'" in timed.interpolation and check(timed.trajectory, limits) == []


def test_path_slopes_match_scipy() -> None:
    interpolate = pytest.importorskip("scipy.interpolate")
    rng = np.random.default_rng(5)
    s = np.cumsum(rng.uniform(0.1, 1.0, 7))
    y = rng.normal(size=(7, 3))
    y[3:5, 0] = y[2, 0]  # a flat stretch
    from armtool.traj.path import natural_slopes, pchip_slopes

    assert np.allclose(pchip_slopes(s, y), interpolate.PchipInterpolator(s, y)(s, 1))
    assert np.allclose(natural_slopes(s, y), interpolate.CubicSpline(s, y, bc_type="natural")(s, 1))


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
