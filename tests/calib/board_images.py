"""Rendered board images with known intrinsics, shared by the intrinsics tests (cached per run).

640x480, f = 600 px, principal point off-centre, k1..k3 = (-0.12, 0.08, 0), p = (4e-4, -3e-4):
a typical webcam-like lens. Boards spread over the image and tilted (`spread_board_poses`).
How many images each board needs for 0.2 % / 1 px was measured over seeds 0-5 (README,
`calibrate camera`): the grid's 120 tag corners per image need 16 images, the ChArUco
board's 54 chessboard corners 30 (20 left the principal point up to 1.3 px off).
"""

from __future__ import annotations

from functools import cache

import numpy as np
from numpy.typing import NDArray

from armtool.calib.model.camera import CameraModel
from armtool.calib.targets.boards import parse_board
from tests.calib.render_board import render_board, spread_board_poses

TRUE_CAMERA = CameraModel(
    np.array([[600.0, 0, 322.4], [0, 600.0, 236.8], [0, 0, 1]]), np.array([-0.12, 0.08, 4e-4, -3e-4, 0.0]), 640, 480
)
CHARUCO = "charuco:10x7:0.02:0.015:4X4_50"
APRILGRID = "aprilgrid:6x5:0.02:0.006"
IMAGES = {CHARUCO: 30, APRILGRID: 16}
_POSES = {
    CHARUCO: {"distance_m": (0.28, 0.42), "tilt_deg": (30.0, 50.0)},
    APRILGRID: {"distance_m": (0.25, 0.4), "tilt_deg": (25.0, 45.0)},
}


@cache
def board_images(board: str, n: int | None = None, seed: int = 0) -> tuple[NDArray[np.uint8], ...]:
    spec = parse_board(board)
    rng = np.random.default_rng(seed)
    poses = spread_board_poses(TRUE_CAMERA, spec, IMAGES[board] if n is None else n, rng, **_POSES[board])  # type: ignore[arg-type]
    return tuple(render_board(TRUE_CAMERA, p, spec, rng=rng) for p in poses)
