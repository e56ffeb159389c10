"""Closed-form AX = XB recovers known frames from exact and noisy motions."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.choices import Setup
from armtool.calib.fit.handeye import initial_frames, solve_ax_xb
from armtool.calib.model import se3
from armtool.errors import ArmtoolError


def _random_poses(rng: np.random.Generator, n: int) -> list[np.ndarray]:
    return [se3.delta(np.concatenate([rng.normal(scale=0.3, size=3), rng.normal(scale=0.8, size=3)])) for _ in range(n)]


def test_ax_xb_exact() -> None:
    rng = np.random.default_rng(1)
    X = se3.delta(np.array([0.1, -0.05, 0.2, 0.3, -0.2, 1.0]))
    Bs = _random_poses(rng, 10)
    As = [X @ B @ se3.inv(X) for B in Bs]
    assert np.allclose(solve_ax_xb(As, Bs), X, atol=1e-9)


@pytest.mark.parametrize("setup", list(Setup))
def test_initial_frames_from_noisy_pnp(setup: Setup) -> None:
    rng = np.random.default_rng(2)
    L = se3.delta(np.array([0.2, 0.1, 1.0, 2.0, 0.1, -0.5]))
    R = se3.delta(np.array([0.0, 0.01, 0.02, 0.0, 0.0, 1.5]))
    flanges = _random_poses(rng, 30)
    C = []
    for F in flanges:
        G = F if setup is Setup.EYE_TO_HAND else se3.inv(F)
        noise = se3.delta(np.concatenate([rng.normal(scale=5e-4, size=3), rng.normal(scale=2e-3, size=3)]))
        C.append(L @ G @ R @ noise)
    L_est, R_est = initial_frames(setup, flanges, C)
    for est, true in ((L_est, L), (R_est, R)):
        dt, angle = se3.pose_difference(est, true)
        assert dt < 0.01 and angle < np.radians(1.0)


def test_too_little_rotation_is_a_clear_error() -> None:
    T = [se3.delta(np.array([0.1 * k, 0, 0, 0, 0, 0])) for k in range(5)]
    with pytest.raises(ArmtoolError, match="rotate the flange too little"):
        solve_ax_xb(T, T)
