"""The joint refinement: its Jacobians against finite differences, the noises it estimates, the
truth it recovers, and the outlier images it names."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.choices import Setup
from armtool.calib.fit.handeye import AxXbMethod
from armtool.calib.handeye.closed_forms import closed_form
from armtool.calib.handeye.refine import Noise, Reprojection, fit_noise, refine, reprojection_residuals
from armtool.calib.handeye.simulate import SMALL_CAMERA as CAMERA
from armtool.calib.handeye.simulate import corner_observations
from armtool.calib.handeye.views import Observations
from armtool.calib.model import se3


def _numeric(f, x: np.ndarray, steps: np.ndarray) -> np.ndarray:  # type: ignore[no-untyped-def]
    cols = []
    for k, h in enumerate(steps):
        e = np.zeros_like(x)
        e[k] = h
        cols.append((f(x + e) - f(x - e)) / (2 * h))
    return np.stack(cols, axis=-1)


@pytest.mark.parametrize("intrinsics", [False, True])
def test_the_jacobian_is_the_residuals_derivative(intrinsics: bool) -> None:
    obs, X, Z = corner_observations(n=6, seed=1)
    problem = Reprojection(obs, X, Z, CAMERA, intrinsics)
    problem.whiten(problem.x0, Noise(0.1, 3e-4, 5e-4))  # whitened rows are checked too
    rng = np.random.default_rng(2)
    x = problem.x0.copy()
    x[:12] += rng.normal(scale=0.05, size=12)  # away from 0, where the right Jacobian of SO(3) matters
    steps = np.full(len(x), 1e-7)
    steps[12:] = 1e-6 * np.maximum(np.abs(x[12:]), 1.0)
    numeric = _numeric(problem.residuals, x, steps)
    assert np.allclose(problem.jacobian(x), numeric, rtol=1e-5, atol=1e-4 * np.abs(numeric).max())


@pytest.mark.parametrize("setup", list(Setup))
def test_the_flange_jacobian_is_the_derivative_by_the_flange_pose_error(setup: Setup) -> None:
    """Moving one image's reported flange pose F by F · SE3(exp(ω), v) moves its corners as
    `flange_jacobian` says (up to its sign, which a covariance does not see)."""
    obs, X, Z = corner_observations(n=3, seed=3, setup=setup)
    problem = Reprojection(obs, X, Z, CAMERA, False)
    J = problem.flange_jacobian(problem.x0)
    mine = obs.image == 1

    def corners(d: np.ndarray) -> np.ndarray:
        G = obs.G.copy()
        F = G[1] if setup is Setup.EYE_IN_HAND else se3.inv(G[1])
        F = F @ se3.delta(d)
        G[1] = F if setup is Setup.EYE_IN_HAND else se3.inv(F)
        moved = Observations(setup, G, obs.C, obs.start, obs.pnp_rms_px, obs.image, obs.points, obs.pixels)
        return reprojection_residuals(moved, X, Z, CAMERA)[mine]

    numeric = _numeric(corners, np.zeros(6), np.full(6, 1e-7))
    assert np.allclose(np.abs(J[mine]), np.abs(numeric), rtol=1e-4, atol=1e-3)
    assert np.allclose(J[mine], numeric, atol=1e-3) or np.allclose(J[mine], -numeric, atol=1e-3)


def test_the_noises_are_estimated_from_the_residuals() -> None:
    """The likelihood's σ_px, σ_t and σ_r come out near the simulated ones (pixel noise 0.1 px, the
    flange 0.5 mm and 0.05°), although IPPE's own depth error alone would suggest a larger σ_t."""
    obs, X, Z = corner_observations(n=40, seed=4, flange_mm=0.5, flange_deg=0.05, pixel_px=0.1)
    problem = Reprojection(obs, X, Z, CAMERA, False)
    noise = fit_noise(problem, problem.x0, Noise(0.05, 1e-3, 1e-3))
    assert 0.08 < noise.pixel_px < 0.12
    assert 0.35e-3 < noise.position_m < 0.65e-3
    assert np.radians(0.035) < noise.rotation_rad < np.radians(0.065)


@pytest.mark.parametrize("setup", list(Setup))
def test_refinement_recovers_both_frames(setup: Setup) -> None:
    obs, X, Z = corner_observations(n=30, seed=5, setup=setup)
    start = closed_form(AxXbMethod.PARK, obs.G, obs.C)
    fit = refine(obs, *start, CAMERA)
    for est, true, sigma in ((fit.X, X, fit.sigma_X), (fit.Z, Z, fit.sigma_Z)):
        dt, angle = se3.pose_difference(est, true)
        assert dt < max(4 * float(np.linalg.norm(sigma[0])), 1e-4)
        assert angle < max(4 * float(np.linalg.norm(sigma[1])), 1e-5)
    assert len(fit.outliers) == 0


def test_a_pose_row_of_another_image_is_named_and_left_out() -> None:
    obs, X, _Z = corner_observations(n=25, seed=6)
    G = obs.G.copy()
    G[7] = G[7] @ se3.delta(np.array([0.02, -0.01, 0.01, 0.03, 0.0, -0.02]))
    bad = Observations(obs.setup, G, obs.C, obs.start, obs.pnp_rms_px, obs.image, obs.points, obs.pixels)
    fit = refine(bad, *closed_form(AxXbMethod.PARK, bad.G, bad.C), CAMERA)
    assert list(fit.outliers) == [7]
    dt, angle = se3.pose_difference(fit.X, X)
    assert dt < 1e-3 and angle < np.radians(0.05)
    assert fit.image_rms_px[7] > 10 * np.median(fit.image_rms_px)
