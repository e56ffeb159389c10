"""Rendered board images with known intrinsics, shared by the intrinsics tests (cached per run).

640x480, f = 600 px, principal point off-centre, k1..k3 = (-0.12, 0.08, 0), p = (4e-4, -3e-4):
a typical webcam-like lens. Boards at 0.25-0.4 m, tilted 25-45°, spread over the image.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from armtool.calib.boards import parse_board
from armtool.calib.camera import CameraModel
from armtool.calib.render_board import render_board, spread_board_poses

TRUE_CAMERA = CameraModel(np.array([[600.0, 0, 322.4], [0, 600.0, 236.8], [0, 0, 1]]), np.array([-0.12, 0.08, 4e-4, -3e-4, 0.0]), 640, 480)
CHARUCO = "charuco:11x8:0.015:0.011:4X4_50"
APRILGRID = "aprilgrid:6x5:0.02:0.006"


@lru_cache(maxsize=None)
def board_images(board: str, n: int, seed: int = 0) -> tuple[NDArray[np.uint8], ...]:
    spec = parse_board(board)
    rng = np.random.default_rng(seed)
    poses = spread_board_poses(TRUE_CAMERA, spec, n, rng, distance_m=(0.25, 0.4))
    return tuple(render_board(TRUE_CAMERA, p, spec, rng=rng) for p in poses)
