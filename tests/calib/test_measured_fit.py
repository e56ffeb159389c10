"""Measured poses and points with known truth: the fit recovers the robot within the noise,
estimates that noise, reports identifiability, and names bad samples."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from armtool.calib.choices import Setup
from armtool.calib.fit.calibration import FitOptions, calibrate
from armtool.calib.inputs.conventions import PoseFrame
from armtool.calib.model import se3
from armtool.calib.outputs.report import calibration_document
from armtool.calib.simulation.truth import score
from armtool.model.chain import Chain
from tests.calib.synthetic import make_measured

NO_CV = FitOptions(folds=0)


@pytest.mark.parametrize("setup", list(Setup))
@pytest.mark.parametrize("frame", list(PoseFrame))
def test_poses_give_the_true_robot_and_their_noise(clean_chain: Chain, setup: Setup, frame: PoseFrame) -> None:
    m = make_measured(clean_chain, "pose", n=80, setup=setup, frame=frame, noise_mm=0.1, noise_deg=0.02, seed=3)
    result = calibrate(m.model, m.measurements, m.samples, NO_CV)
    before, after = score(result.model, result.x_handeye, m.truth), score(result.model, result.x, m.truth)
    assert before.position_rms_mm > 1.5  # the injected errors matter
    assert after.position_rms_mm < 0.1 and after.rotation_rms_deg < 0.01  # within the measurement noise
    assert result.noise["position"] == pytest.approx(0.1, rel=0.2)
    assert result.noise["rotation"] == pytest.approx(0.02, rel=0.2)
    assert len(result.free) == 4 * clean_chain.n + 6  # Everett, Driels & Mooring, as for tag corners
    assert not result.outliers
    assert (result.coordinates_per_sample, result.fit_samples) == (6.0, 80)  # what the verdict's pose estimate uses


def test_the_fitted_placements_are_the_true_ones_within_their_sigma(clean_chain: Chain) -> None:
    m = make_measured(
        clean_chain, "pose", n=80, setup=Setup.EYE_IN_HAND, noise_mm=0.1, noise_deg=0.02, seed=4, errors=False
    )
    result = calibrate(m.model, m.measurements, m.samples, FitOptions(folds=0, families=()))
    L, _R = result.fitted_frames()
    dt, _angle = se3.pose_difference(se3.inv(L), se3.inv(m.L))
    sigma = dict(zip(result.free, result.sigma))
    translation_sigma = math.sqrt(sum(sigma[i] ** 2 for i in result.model.layout.frames[:3]))
    assert dt < 4 * translation_sigma
    frames = calibration_document(result, "ds", "robot.urdf")["frames"]
    assert set(frames) == {"camera_in_flange", "board_in_base"}
    assert len(frames["camera_in_flange"]["sigma_xyz_mm"]) == 3


@pytest.mark.parametrize("setup", list(Setup))
def test_points_give_the_true_robot(clean_chain: Chain, setup: Setup) -> None:
    m = make_measured(clean_chain, "point", n=80, setup=setup, noise_mm=0.05, seed=5)
    result = calibrate(m.model, m.measurements, m.samples, NO_CV)
    after = score(result.model, result.x, m.truth)
    assert after.position_rms_mm < 0.1
    assert result.noise["position"] == pytest.approx(0.05, rel=0.2)
    names = [result.model.params[i].name for i in result.identifiability.dropped]
    assert not any(name.startswith("point_in_") and ".r" in name for name in names)  # never candidates
    frames = calibration_document(result, "ds", "robot.urdf")["frames"]
    point = frames["point_in_flange" if setup is Setup.EYE_TO_HAND else "point_in_base"]
    assert set(point) == {"xyz", "sigma_xyz_mm"}


def test_a_bad_pose_sample_is_named_and_does_not_bend_the_robot(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "pose", n=60, noise_mm=0.1, noise_deg=0.02, seed=6)
    samples = list(m.samples)
    q = samples[7].q.copy()
    q[3] += math.radians(2.0)
    samples[7] = replace(samples[7], q=q)
    result = calibrate(m.model, m.measurements, samples, NO_CV)
    assert set(result.outliers) == {"7"}
    assert "row 9" in result.outliers["7"] and "mm" in result.outliers["7"]
    assert score(result.model, result.x, m.truth).position_rms_mm < 0.1


def test_a_sample_wrong_only_in_position_is_named(clean_chain: Chain) -> None:
    # One block bad, the other good: judged per block, so the good rotation does not hide it.
    m = make_measured(clean_chain, "pose", n=60, noise_mm=0.1, noise_deg=0.02, seed=7)
    poses = dict(m.measurements.poses)  # type: ignore[attr-defined]
    poses["11"] = se3.make(t=np.array([0.0, 0.0, 0.0015])) @ poses["11"]  # 1.5 mm, 15 σ
    measurements = type(m.measurements)(poses, PoseFrame.SENSOR_IN_TARGET, "camera", "board", "poses.csv")  # type: ignore[call-arg]
    result = calibrate(m.model, measurements, m.samples, NO_CV)
    assert set(result.outliers) == {"11"}


def test_a_measurement_missing_for_a_sample_rejects_it(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "point", n=40, seed=8)
    del m.measurements.points["4"]  # type: ignore[attr-defined]
    result = calibrate(m.model, m.measurements, m.samples, NO_CV)
    assert result.rejected == {"4": "no usable row in points.csv"}
