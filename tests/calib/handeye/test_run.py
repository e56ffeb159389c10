"""Hand-eye end to end on rendered images with known truth: the frames recovered within the noise,
the refinement ahead of every closed form on held-out images, eye-to-hand, outliers, 180° turns."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from armtool.calib.choices import Setup
from armtool.calib.handeye.run import HandEyeRequest, HandEyeResult, document, run_handeye
from armtool.calib.handeye.scores import REFINED, REFINED_INTRINSICS
from armtool.calib.handeye.simulate import Rendered
from armtool.calib.model import se3
from tests.calib.handeye_data import Make


def _errors(result: HandEyeResult, truth: Rendered) -> tuple[float, float, float, float]:
    """(X mm, X °, Z mm, Z °) of the chosen refinement against the truth."""
    fit = result.scores.refined
    (xt, xr), (zt, zr) = se3.pose_difference(fit.X, truth.X), se3.pose_difference(fit.Z, truth.Z)
    return xt * 1e3, math.degrees(xr), zt * 1e3, math.degrees(zr)


def _closed_forms(result: HandEyeResult) -> dict[str, float]:
    return {r.method: r.heldout_inlier_rms_px for r in result.scores.rows if not r.method.startswith("refined")}


@pytest.mark.parametrize("setup", list(Setup))
def test_both_frames_are_recovered_within_the_noise(rendered: Make, setup: Setup) -> None:
    dataset, truth = rendered(setup=setup, flange_noise_mm=0.3, flange_noise_deg=0.03)
    result = run_handeye(HandEyeRequest(dataset))
    x_mm, x_deg, z_mm, z_deg = _errors(result, truth)
    fit = result.scores.refined
    assert x_mm < max(4e3 * float(np.linalg.norm(fit.sigma_X[0])), 0.1), (x_mm, fit.sigma_X)
    assert z_mm < max(4e3 * float(np.linalg.norm(fit.sigma_Z[0])), 0.1), (z_mm, fit.sigma_Z)
    assert x_deg < 0.1 and z_deg < 0.1
    assert len(fit.outliers) == 0 and result.conventions is not None and result.conventions.better is None
    assert 0.2 < fit.noise.position_m * 1e3 < 0.45 and 0.02 < math.degrees(fit.noise.rotation_rad) < 0.045
    doc = document(result)
    names = (
        ("camera_in_flange", "board_in_base") if setup is Setup.EYE_IN_HAND else ("camera_in_base", "board_in_flange")
    )
    assert all(name in doc for name in names) and doc["heldout"]["folds"] == 5


def test_the_refinement_predicts_held_out_images_better_than_every_closed_form(rendered: Make) -> None:
    """Corner noise dominating (a well-calibrated robot, 0.02 mm and 0.002°): the closed forms,
    which fit motions, trail the fit of the corners themselves."""
    dataset, truth = rendered(flange_noise_mm=0.02, flange_noise_deg=0.002, seed=0)
    result = run_handeye(HandEyeRequest(dataset))
    chosen = result.scores.chosen
    assert chosen.method in (REFINED, REFINED_INTRINSICS)
    closed = _closed_forms(result)
    assert chosen.heldout_inlier_rms_px < 0.97 * min(closed.values()), closed
    x_mm, x_deg, _z_mm, _z_deg = _errors(result, truth)
    assert x_mm < 0.2 and x_deg < 0.02


def test_a_pose_row_of_another_image_is_named_and_does_not_bend_the_frames(rendered: Make) -> None:
    dataset, truth = rendered(bad_rows=1, flange_noise_mm=0.3, flange_noise_deg=0.03, seed=8)
    result = run_handeye(HandEyeRequest(dataset))
    doc = document(result)
    assert doc["outliers"] == [f"images/{i:04d}.png" for i in truth.bad_rows]
    x_mm, x_deg, _z_mm, _z_deg = _errors(result, truth)
    assert x_mm < 0.5 and x_deg < 0.05
    closed = _closed_forms(result)
    assert result.scores.chosen.heldout_inlier_rms_px < 0.8 * min(closed.values()), closed


def test_a_detection_turned_by_180_degrees_is_turned_back(rendered: Make, monkeypatch: pytest.MonkeyPatch) -> None:
    """OpenCV's detector returning the grid from its other end (5 of 29 real photos of one set):
    the order is fixed from the image, and the frames come out as without it."""
    dataset, _truth = rendered(images=20, seed=9)
    plain = run_handeye(HandEyeRequest(dataset, folds=0))
    find = cv2.findChessboardCorners
    calls = {"n": 0}

    def turned(image, size, *args, **kwargs):  # type: ignore[no-untyped-def]
        found, corners = find(image, size, *args, **kwargs)
        calls["n"] += 1
        if found and calls["n"] % 4 == 0:
            corners = corners[::-1].copy()
        return found, corners

    monkeypatch.setattr(cv2, "findChessboardCorners", turned)
    result = run_handeye(HandEyeRequest(dataset, folds=0))
    assert calls["n"] >= 20
    for a, b in ((plain.scores.refined.X, result.scores.refined.X), (plain.scores.refined.Z, result.scores.refined.Z)):
        dt, angle = se3.pose_difference(a, b)
        assert dt < 1e-6 and angle < 1e-6
    assert len(result.scores.refined.outliers) == 0
