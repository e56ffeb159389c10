"""The lecture's edits: exact uniform re-timing, dropping every 4th point, joining at a shared end."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.traj.check import check
from armtool.traj.edit import join, retime, thin
from armtool.traj.timing import time_optimal
from armtool.traj.trajectory import Trajectory

from .helpers import JOINTS, clean_limits, random_path


def test_retime_is_exact_uniform_scaling() -> None:
    t = time_optimal(random_path(0), clean_limits())
    slow = retime(t, 0.25)
    np.testing.assert_allclose(slow.times, t.times * 4)
    np.testing.assert_allclose(slow.velocities, t.velocities * 0.25)
    np.testing.assert_allclose(slow.accelerations, t.accelerations * 0.0625)
    np.testing.assert_array_equal(slow.positions, t.positions)
    assert check(slow, clean_limits()) == []


@pytest.mark.parametrize("scale", [0.0, -1.0, float("nan")])
def test_retime_refuses_non_positive_scale(scale: float) -> None:
    with pytest.raises(ArmtoolError, match="positive"):
        retime(time_optimal(random_path(0), clean_limits()), scale)


def test_thin_every_fourth_of_twenty_leaves_sixteen_with_ends() -> None:
    q = np.arange(20, dtype=float)[:, None] * np.ones((1, 6)) * 0.01
    out = thin(Trajectory(JOINTS, q), every=4)
    assert out.n_points == 16
    np.testing.assert_array_equal(out.positions[0], q[0])
    np.testing.assert_array_equal(out.positions[-1], q[-1])
    assert not any(np.array_equal(row, q[3]) for row in out.positions)  # the 4th point (1-based) is gone


def test_thin_by_tolerance_keeps_the_corner() -> None:
    line1 = np.linspace([0] * 6, [1, 0, 0, 0, 0, 0], 10)
    line2 = np.linspace([1, 0, 0, 0, 0, 0], [1, 1, 0, 0, 0, 0], 10)[1:]
    out = thin(Trajectory(JOINTS, np.concatenate([line1, line2])), tolerance=1e-6)
    np.testing.assert_allclose(out.positions, [[0] * 6, [1, 0, 0, 0, 0, 0], [1, 1, 0, 0, 0, 0]])


def test_join_then_time_passes_check() -> None:
    a = random_path(0, points=3)
    b_q = random_path(1, points=3).positions.copy()
    b_q[0] = a.positions[-1]
    b = Trajectory(JOINTS[::-1], b_q[:, ::-1].copy(), source="b.csv")  # other joint order: matched by name
    joined = join([a, b], 1e-6)
    assert joined.n_points == 5 and joined.joint_names == JOINTS
    np.testing.assert_allclose(joined.positions[3:], b_q[1:])
    timed = time_optimal(joined, clean_limits())
    assert check(timed, clean_limits()) == []


def test_join_refuses_a_gap_and_says_where() -> None:
    a = random_path(0, points=3)
    b = replace(random_path(1, points=3), source="b.csv", lines=(2, 3, 4))
    with pytest.raises(ArmtoolError) as err:
        join([a, b], 1e-3)
    assert "starts" in err.value.what and err.value.where == "b.csv:2"
