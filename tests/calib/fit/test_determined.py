"""Only what the data determine is fitted: a nearly redundant combination is held at nominal and
named with its σ, an imprecise one far from nominal is still fitted, and one tracked point leaves
the flange's orientation where the nominal robot has it."""

from __future__ import annotations

import math

import numpy as np

from armtool.calib.choices import Setup
from armtool.calib.fit.calibration import FitOptions, calibrate
from armtool.calib.fit.determined import Precision, determined
from armtool.calib.model import se3
from armtool.calib.model.calib_model import CalibModel
from armtool.model.chain import Chain, load_chain
from tests.calib.synthetic import make_measured
from tests.ik.robots import erd


def _frames_and_two_joints(model: CalibModel) -> list[int]:
    """Three frame parameters and two origin translations (metres), as `free`."""
    layout = model.layout
    return layout.frames[:3] + layout.origin(1)[:1] + layout.origin(2)[:1]


def test_a_nearly_redundant_combination_is_held_and_named(clean_chain: Chain) -> None:
    model = CalibModel(clean_chain, Setup.EYE_TO_HAND, np.eye(4), np.eye(4))
    free = _frames_and_two_joints(model)
    rng = np.random.default_rng(0)
    frames = rng.normal(size=(300, 3))
    a = rng.normal(size=300)
    # noise-weighted columns per metre: the two translations move the measurements almost alike
    J = np.column_stack([frames, 1e4 * a, 1e4 * (a + 1e-4 * rng.normal(size=300))])
    subspace = determined(model, J, free, Precision())
    assert subspace.dimension == 4  # three frames and one combination of the two
    (held,) = subspace.held
    assert held.sigma > 10
    assert {i for i, _w in held.weights} == set(free[3:])
    assert "× the precision" in held.describe(model, Precision())


def test_projection_keeps_the_frames_and_moves_only_fitted_combinations(clean_chain: Chain) -> None:
    model = CalibModel(clean_chain, Setup.EYE_TO_HAND, np.eye(4), np.eye(4))
    free = _frames_and_two_joints(model)
    rng = np.random.default_rng(0)
    a = rng.normal(size=300)
    J = np.column_stack([rng.normal(size=(300, 3)), 1e4 * a, 1e4 * (a + 1e-4 * rng.normal(size=300))])
    subspace = determined(model, J, free, Precision())
    x = np.zeros(model.size)
    x[free] = [0.1, 0.2, 0.3, 0.004, -0.004]  # a move along the held combination (equal and opposite)
    projected = subspace.project(x, np.zeros(model.size))
    assert np.allclose(projected[free[:3]], [0.1, 0.2, 0.3])
    assert np.abs(projected[free[3:]]).max() < 1e-4
    assert subspace.basis.shape == (5, subspace.dimension)


def _base_registered_angle(model: CalibModel, x_fit: np.ndarray, x_true: np.ndarray, Q: np.ndarray) -> float:  # type: ignore[type-arg]
    """The largest angle (°) between the fitted and the true flange orientation, after the one base
    rotation that best aligns them (the tracker's frame carries the base's own errors)."""
    R_fit, R_true = model.flange(x_fit, Q)[:, :3, :3], model.flange(x_true, Q)[:, :3, :3]
    U, _s, Vt = np.linalg.svd(np.einsum("nij,nkj->ik", R_true, R_fit))
    base = U @ np.diag([1, 1, np.linalg.det(U @ Vt)]) @ Vt
    turned = np.einsum("ij,njk->nik", base, R_fit)
    return math.degrees(float(np.linalg.norm(se3.log3_batch(np.swapaxes(R_true, -1, -2) @ turned), axis=-1).max()))


def test_one_tracked_point_on_the_last_axis_leaves_the_flange_orientation_nominal() -> None:
    # A laser tracker's reflector 31 mm out along a UR5's wrist_3 axis, as on the real data: the
    # flange's turn about the reflector changes no measurement, so only nominal is right for it.
    chain = load_chain(erd("ur_description/urdf/ur5_robot.urdf"), "base_link", "tool0")
    m = make_measured(
        chain, "point", n=200, setup=Setup.EYE_TO_HAND, noise_mm=0.03, seed=4, point=np.array([1e-4, 2e-4, 0.031])
    )
    result = calibrate(m.model, m.measurements, m.samples, FitOptions(folds=0))
    assert result.subspace is not None and result.subspace.held
    Q = m.truth.validation
    assert _base_registered_angle(result.model, result.x, m.truth.x, Q) < 0.5  # the injected errors: up to 0.3°
