"""Rendered hand-eye datasets with known truth for the tests: a 640x480 camera (f = 600 px,
webcam-like distortion) and a 10x7 chessboard of 25 mm squares at 0.5-1.0 m, so that images render
fast; `copied` for a test that changes a dataset; `synthetic_observations` for the fits alone, without images.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from armtool.calib.choices import Setup
from armtool.calib.handeye.simulate import Rendered
from armtool.calib.handeye.views import Observations
from armtool.calib.model import se3
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array

CAMERA = CameraModel(
    np.array([[600.0, 0, 322.4], [0, 600.0, 236.8], [0, 0, 1]]), np.array([-0.12, 0.08, 4e-4, -3e-4, 0.0]), 640, 480
)
DEFAULTS: dict[str, Any] = {"images": 25, "camera": CAMERA, "distance_m": (0.5, 1.0)}
Make = Callable[..., tuple[Path, Rendered]]  # the `rendered` fixture: (dataset directory, truth) of a spec


def copied(dataset: Path, tmp_path: Path) -> Path:
    """A copy of a dataset that a test may change."""
    out = tmp_path / "dataset"
    shutil.copytree(dataset, out)
    return out


def synthetic_observations(
    n: int = 25,
    seed: int = 0,
    flange_mm: float = 0.2,
    flange_deg: float = 0.02,
    pixel_px: float = 0.05,
    setup: Setup = Setup.EYE_IN_HAND,
    board: str = "chessboard:10x7:0.025",
) -> tuple[Observations, Array, Array]:
    """(observations, X, Z) without images: the corners where CAMERA sees the board, plus Gaussian
    pixel noise, and each flange pose off by the controller's error (1σ per axis, on its right)."""
    from armtool.calib.handeye.simulate import HandEyeSimulation, board_pose, true_frames
    from armtool.calib.targets.boards import board_points, parse_board
    from armtool.calib.targets.pose import planar_pose

    rng = np.random.default_rng(seed)
    spec = HandEyeSimulation(board=parse_board(board), setup=setup, **DEFAULTS)
    X, Z = true_frames(setup, spec.board, rng)
    points = board_points(spec.board)
    G, C, rms, pixels = [], [], [], []
    for _ in range(n):
        cMb = board_pose(CAMERA, spec.board, spec, rng)
        F = Z @ se3.inv(cMb) @ se3.inv(X)
        F = F if setup is Setup.EYE_IN_HAND else se3.inv(F)  # the flange in the base, exact
        e = np.concatenate(
            [rng.normal(scale=flange_mm * 1e-3, size=3), rng.normal(scale=np.radians(flange_deg), size=3)]
        )
        F = F @ se3.delta(e)
        u = CAMERA.project(points @ cMb[:3, :3].T + cMb[:3, 3]) + rng.normal(scale=pixel_px, size=(len(points), 2))
        pose, r, _ambiguous = planar_pose(points, u, CAMERA)
        G.append(F if setup is Setup.EYE_IN_HAND else se3.inv(F))
        C.append(pose)
        rms.append(r)
        pixels.append(u)
    obs = Observations(
        setup,
        np.array(G),
        np.array(C),
        np.ones(n, dtype=bool),
        np.array(rms),
        np.repeat(np.arange(n), len(points)),
        np.tile(points, (n, 1)),
        np.concatenate(pixels),
    )
    return obs, X, Z
