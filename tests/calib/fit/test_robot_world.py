"""Closed-form AX = ZB (Shah, Li): both frames from exact and noisy poses, and too few poses refused."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.fit.robot_world import AxZbMethod, solve_ax_zb
from armtool.calib.model import se3
from armtool.errors import ArmtoolError

X = se3.delta(np.array([0.1, -0.05, 0.2, 0.3, -0.2, 1.0]))
Z = se3.delta(np.array([0.6, 0.2, -0.1, 2.0, 0.3, -1.0]))


def _poses(n: int, seed: int, noise: tuple[float, float] = (0.0, 0.0)) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """(A_i, B_i) with A_i X = Z B_i, B_i perturbed by `noise` (m, rad) on its right."""
    rng = np.random.default_rng(seed)
    A = [se3.delta(np.concatenate([rng.normal(scale=0.3, size=3), rng.normal(scale=0.8, size=3)])) for _ in range(n)]
    B = []
    for a in A:
        e = se3.delta(np.concatenate([rng.normal(scale=noise[0], size=3), rng.normal(scale=noise[1], size=3)]))
        B.append(se3.inv(Z) @ a @ X @ e)
    return A, B


@pytest.mark.parametrize("method", list(AxZbMethod))
def test_exact_poses_give_both_frames(method: AxZbMethod) -> None:
    Xe, Ze = solve_ax_zb(*_poses(12, 1), method)
    assert np.allclose(Xe, X, atol=1e-9) and np.allclose(Ze, Z, atol=1e-9)


@pytest.mark.parametrize("method", list(AxZbMethod))
def test_noisy_poses_give_both_frames_within_the_noise(method: AxZbMethod) -> None:
    Xe, Ze = solve_ax_zb(*_poses(30, 2, (1e-3, 2e-3)), method)
    for est, true in ((Xe, X), (Ze, Z)):
        dt, angle = se3.pose_difference(est, true)
        assert dt < 3e-3 and angle < np.radians(0.3)


def test_two_poses_are_refused() -> None:
    with pytest.raises(ArmtoolError, match="cannot determine two frames"):
        solve_ax_zb(*_poses(2, 3))
