"""Jerk-limited timing: within the jerk, velocity and acceleration limits by `traj check`'s own model,
rest to rest, every sample on the path, and slower than the time-optimal timing only by about the
smoothing window."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from armtool.traj.check import check
from armtool.traj.path import joint_path
from armtool.traj.timing import time_optimal
from armtool.traj.trajectory import Trajectory

from .helpers import JOINTS, clean_limits, random_path


def with_jerk(value: float) -> object:
    limits = clean_limits()
    return replace(limits, jerk=np.full(len(limits.names), value))


@pytest.mark.parametrize("seed, jerk", [(0, 5.0), (1, 50.0), (2, 500.0), (3, 50.0)])
def test_jerk_limited_paths_pass_check_with_the_jerk_limit(seed: int, jerk: float) -> None:
    limits = with_jerk(jerk)
    path = random_path(seed, points=6)
    timed = time_optimal(path, limits)  # type: ignore[arg-type]
    assert [f.code for f in check(timed, limits)] == []  # type: ignore[arg-type]
    assert np.all(np.abs(timed.velocities[[0, -1]]) < 1e-12) and np.all(np.abs(timed.accelerations[[0, -1]]) < 1e-12)
    # Without the jerk limit the time-optimal timing breaks it, and is faster.
    fast = time_optimal(path, clean_limits())
    assert "T303" in {f.code for f in check(fast, limits)}  # type: ignore[arg-type]
    assert fast.duration_s < timed.duration_s


def test_every_sample_lies_on_the_path_in_order() -> None:
    path = random_path(4, points=6)
    timed = time_optimal(path, with_jerk(20.0))  # type: ignore[arg-type]
    spline = joint_path(path.positions)
    s = np.linspace(0, spline.length, 200_001)
    dense = spline.spline(s)
    nearest = [int(np.argmin(np.abs(dense - q).max(axis=1))) for q in timed.positions]
    gap = max(float(np.abs(dense[k] - q).max()) for k, q in zip(nearest, timed.positions))
    assert gap < 1e-4  # on the spline, to the resolution of the dense sampling
    assert np.all(np.diff(nearest) >= 0)  # forward along it, never back
    # Between samples: the cubic Hermite a controller runs, at each segment's middle, stays on it too.
    T = np.diff(timed.times)[:, None]
    q, v = timed.positions, timed.velocities
    middles = (q[:-1] + q[1:]) / 2 + T * (v[:-1] - v[1:]) / 8
    assert max(float(np.abs(dense - m).max(axis=1).min()) for m in middles) < 1e-4
    assert np.allclose(timed.positions[[0, -1]], path.positions[[0, -1]], atol=1e-12)


def test_a_loose_jerk_limit_costs_little_time() -> None:
    path = random_path(5)
    fast = time_optimal(path, clean_limits())
    smooth = time_optimal(path, with_jerk(1e4))  # type: ignore[arg-type]
    assert smooth.duration_s < fast.duration_s * 1.05


def test_jerk_limit_on_one_joint_only() -> None:
    limits = clean_limits()
    jerk = np.full(len(limits.names), np.nan)
    jerk[limits.index("joint2")] = 10.0
    limited = replace(limits, jerk=jerk)
    timed = time_optimal(Trajectory(JOINTS, random_path(6).positions), limited)
    assert [f.code for f in check(timed, limited)] == []
