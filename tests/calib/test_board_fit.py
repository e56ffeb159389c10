"""`calibrate fit` with a board target: partial views reproject only the corners they show, and a
simulated dataset of chessboard or ChArUco images recovers the true robot end to end."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from armtool.calib.choices import Setup
from armtool.calib.fit.calibration import FitOptions, calibrate
from armtool.calib.fit.measurements import CornerMeasurements
from armtool.calib.inputs.dataset import Sample
from armtool.calib.inputs.observations import Observation
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.simulation.simulate import SimulationSpec, _place, _visible, default_camera, true_errors
from armtool.calib.simulation.truth import Truth, score
from armtool.calib.targets.boards import board_points, parse_board
from armtool.cli import app
from armtool.model.chain import Chain
from tests.ik.robots import erd


def test_partial_views_fit_the_true_robot_from_the_corners_they_show(clean_chain: Chain) -> None:
    """A ChArUco board whose views each miss a random 40 % of the corners (NaN): the fit uses the
    others and recovers the robot as well as from whole views."""
    board = parse_board("charuco:6x5:0.03:0.022:4X4_50")
    points = board_points(board)
    spec = SimulationSpec(samples=30, seed=4, board=board)
    rng = np.random.default_rng(4)
    nominal = CalibModel(clean_chain, Setup.EYE_TO_HAND, np.eye(4), np.eye(4))
    camera = default_camera()
    L, R, pool = _place(nominal, spec, rng, camera)
    x_true = true_errors(nominal, spec, rng)
    truth_model = nominal.with_frames(L, R)
    visible = _visible(truth_model, x_true, camera, pool[:6000], spec)
    chosen = rng.choice(visible, size=50, replace=False)
    Q, Q_val = pool[chosen[:30]], pool[chosen[30:]]
    uv = camera.project(truth_model.corners_in_camera(x_true, Q, points).reshape(-1, 3)).reshape(30, len(points), 2)
    uv += rng.normal(scale=0.05, size=uv.shape)
    hidden = rng.random(uv.shape[:2]) < 0.4
    uv[hidden] = np.nan
    samples = [Sample(str(i), i + 2, Q[i].copy(), None) for i in range(30)]
    observations = {s.id: Observation(s.id, uv[i]) for i, s in enumerate(samples)}
    measurements = CornerMeasurements(camera, observations, points)
    result = calibrate(nominal, measurements, samples, FitOptions(holdout=0.0, folds=0))
    truth = Truth(x_true, Q_val, {})
    before, after = score(result.model, result.x_handeye, truth), score(result.model, result.x, truth)
    assert before.position_rms_mm > 2.0 and after.position_rms_mm < 0.1
    assert not result.outliers
    # The residual RMS is over the corners each view showed: the 0.05 px noise per coordinate. A
    # hidden corner counted as a zero residual would pull it down to √0.6 of that, 0.039 px.
    after_px = result.fit.rms["corner"][1]
    assert 0.045 < after_px < 0.055, result.fit.rms


@pytest.mark.parametrize(
    ("target", "setup"),
    [("chessboard:7x6:0.03", Setup.EYE_TO_HAND), ("charuco:5x4:0.05:0.037:4X4_50", Setup.EYE_IN_HAND)],
)
def test_simulated_board_images_calibrate_end_to_end(tmp_path: Path, target: str, setup: Setup) -> None:
    robot = erd("ur_description/urdf/ur5_robot.urdf")
    data, out = tmp_path / "data", tmp_path / "out"
    runner = CliRunner()
    made = runner.invoke(
        app,
        ["calibrate", "simulate", str(robot), "--flange", "tool0", "--target", target, "--setup", setup.value]
        + ["--samples", "30", "--validation", "15", "--seed", "1", "-o", str(data)],
    )
    assert made.exit_code == 0, made.output
    manifest = yaml.safe_load((data / "dataset.yaml").read_text())
    assert manifest["target"]["board"] == parse_board(target).text() and "family" not in manifest["target"]
    fitted = runner.invoke(app, ["calibrate", "fit", str(data), "--out", str(out), "--format", "json"])
    assert fitted.exit_code == 0, fitted.output
    summary = json.loads(fitted.stdout)
    document = yaml.safe_load((out / "calibration.yaml").read_text())
    truth = document["against_truth"]
    assert truth["hand_eye_only"]["position_rms_mm"] > 2.0
    assert truth["calibrated"]["position_rms_mm"] < 0.4 and truth["improvement"] > 10, truth
    assert summary["schema_version"] == 1 and summary["fitted"] == document["fitted"]
    assert summary["against_truth"] == truth and summary["frames"] == document["frames"]
