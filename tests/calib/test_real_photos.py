"""Real photos: OpenCV's own chessboard samples (fixtures/calib/opencv_chessboard, Apache-2.0)
through `calibrate camera`, against the calibration OpenCV's sample computed from them."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
from typer.testing import CliRunner

from armtool.calib.targets.boards import find_board, parse_board
from armtool.cli import app

PHOTOS = Path(__file__).resolve().parents[2] / "fixtures" / "calib" / "opencv_chessboard"
BOARD = "chessboard:10x7:0.025"  # OpenCV's board_width 9, board_height 6 inner corners, square_size 0.025


def _reference() -> tuple[np.ndarray, float]:
    fs = cv2.FileStorage(str(PHOTOS / "left_intrinsics.yml"), cv2.FILE_STORAGE_READ)
    try:
        return np.asarray(fs.getNode("camera_matrix").mat()), float(fs.getNode("avg_reprojection_error").real())
    finally:
        fs.release()


def _grey_at(gray: np.ndarray, xy: np.ndarray) -> float:
    x, y = np.round(xy).astype(int)
    return float(gray[y - 1 : y + 2, x - 1 : x + 2].mean())


def test_every_photo_shows_the_whole_board_with_its_first_square_black() -> None:
    spec = parse_board(BOARD)
    photos = sorted(PHOTOS.glob("left*.jpg"))
    assert len(photos) == 13
    for photo in photos:
        gray = cv2.imread(str(photo), cv2.IMREAD_GRAYSCALE)
        assert gray is not None
        view = find_board(gray, spec)
        assert not view.reason and len(view.ids) == 54, photo.name
        grid = view.pixels.reshape(6, 9, 2)
        # The square between the first two rows' first corners is the board's square (1, 1): black
        # like the first square; its neighbour along the row is white.
        first = _grey_at(gray, grid[:2, :2].reshape(-1, 2).mean(axis=0))
        second = _grey_at(gray, grid[:2, 1:3].reshape(-1, 2).mean(axis=0))
        assert first + 50 < second, f"{photo.name}: the board frame does not start at its black corner square"


def test_calibrate_camera_agrees_with_opencvs_own_calibration_of_these_photos(tmp_path: Path) -> None:
    out = tmp_path / "left.yaml"
    result = CliRunner().invoke(
        app, ["calibrate", "camera", str(PHOTOS), "--board", BOARD, "-o", str(out), "--format", "json"]
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    K_ref, rms_ref = _reference()
    assert sum(image["used"] for image in summary["images"]) == 13
    assert abs(summary["fx_px"] / K_ref[0, 0] - 1) < 0.01 and abs(summary["fy_px"] / K_ref[1, 1] - 1) < 0.01
    assert abs(summary["cx_px"] - K_ref[0, 2]) < 3 and abs(summary["cy_px"] - K_ref[1, 2]) < 3
    assert summary["rms_px"] < rms_ref  # OpenCV's sample: 0.39 px with its older corner detector
