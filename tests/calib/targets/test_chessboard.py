"""The chessboard detector: every corner where the camera projects it, in the board's own order
however the board is turned (blur, noise, a lighting gradient, motion blur and perspective)."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.model.camera import CameraModel
from armtool.calib.simulation.render import _rotvec, board_in_view
from armtool.calib.targets.boards import BoardKind, board_points, find_board, parse_board
from armtool.calib.targets.chessboard import _handedness, find_chessboard, symmetric
from armtool.errors import ArmtoolError
from tests.calib.render_board import random_board_pose, render_board

CAM = CameraModel(
    np.array([[910.0, 0, 641.3], [0, 910.0, 358.7], [0, 0, 1]]), np.array([-0.1, 0.08, 3e-4, -2e-4, 0.0]), 1280, 720
)


def _spun_poses(spec_text: str, n: int, seed: int) -> list[np.ndarray]:
    """Poses with the board turned by any angle about its normal (OpenCV's order then starts at
    either end), tilted up to 55°, all of it in view."""
    spec = parse_board(spec_text)
    centre = board_points(spec).mean(axis=0)
    rng = np.random.default_rng(seed)
    poses: list[np.ndarray] = []
    while len(poses) < n:
        pose = random_board_pose(CAM, spec, rng, distance_m=(0.45, 0.9), max_tilt_deg=55.0)
        spun = pose.copy()
        spun[:3, :3] = pose[:3, :3] @ _rotvec(np.array([0.0, 0.0, rng.uniform(-np.pi, np.pi)]))
        spun[:3, 3] = pose[:3, 3] + pose[:3, :3] @ centre - spun[:3, :3] @ centre
        if board_in_view(CAM, spun, spec):
            poses.append(spun)
    return poses


@pytest.mark.parametrize("board", ["chessboard:10x7:0.03", "chessboard:7x10:0.03", "chessboard:9x6:0.025"])
def test_corners_are_found_in_board_order_however_the_board_is_turned(board: str) -> None:
    spec = parse_board(board)
    rng = np.random.default_rng(3)
    errors = []
    for k, pose in enumerate(_spun_poses(board, 8, seed=k_seed(board))):
        image = render_board(
            CAM,
            pose,
            spec,
            blur_sigma_px=rng.uniform(0.5, 2.0),
            noise_sigma=4 / 255,
            gradient=0.4,
            motion_px=3.0 if k % 2 else 0.0,
            motion_deg=rng.uniform(0, 180),
            rng=rng,
        )
        view = find_board(image, spec)
        assert not view.reason, view.reason
        truth = CAM.project(board_points(spec)[view.ids] @ pose[:3, :3].T + pose[:3, 3])
        err = np.linalg.norm(view.pixels - truth, axis=1)
        assert err.max() < 0.6, f"image {k}: corners off by up to {err.max():.1f} px (turned the wrong way?)"
        errors.append(err)
    assert float(np.median(np.concatenate(errors))) < 0.1


def k_seed(board: str) -> int:
    return sum(map(ord, board)) % 97


def test_a_missing_board_and_an_unreadable_orientation_are_explained() -> None:
    spec = parse_board("chessboard:10x7:0.03")
    blank = np.full((CAM.height, CAM.width), 90, np.uint8)
    assert "chessboard not found: no 9x6 grid of inner corners (a 10x7-square board" in find_board(blank, spec).reason
    pose = _spun_poses("chessboard:10x7:0.03", 1, seed=1)[0]
    image = render_board(CAM, pose, spec, black=0.45, white=0.47, background=0.46, noise_sigma=0.0, blur_sigma_px=0.5)
    found = find_chessboard(image, 10, 7)
    assert found.pixels is None and (
        "cannot tell the board's orientation" in found.reason or "chessboard not found" in found.reason
    )


def test_symmetric_boards_are_known_and_kept_for_intrinsics() -> None:
    assert symmetric(8, 8) and symmetric(9, 7) and not symmetric(10, 7)
    spec = parse_board("chessboard:8x6:0.03")
    assert spec.kind is BoardKind.CHESSBOARD and spec.symmetric and spec.min_points_per_view == 35
    pose = _spun_poses("chessboard:8x6:0.03", 1, seed=2)[0]
    view = find_board(render_board(CAM, pose, spec), spec)
    assert not view.reason and len(view.ids) == 35  # found: its order is OpenCV's, fine for `calibrate camera`


def test_a_mirrored_order_is_turned_back() -> None:
    grid = np.stack(np.meshgrid(np.arange(4.0), np.arange(3.0)), axis=-1) * 20 + 100  # x right, y down
    assert _handedness(grid) > 0 and _handedness(grid[:, ::-1]) < 0


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("chessboard:10x7", "3 fields"),
        ("chessboard:10x7:0.025:0.01", "3 fields"),
        ("chessboard:2x7:0.025", "at least 3x3 squares"),
        ("chessboard:10x7:25", "metres"),
    ],
)
def test_chessboard_specs_are_checked(text: str, message: str) -> None:
    with pytest.raises(ArmtoolError, match=message):
        parse_board(text)


def test_the_spec_reads_back_and_numbers_inner_corners_like_charuco() -> None:
    spec = parse_board("chessboard:10x7:0.025")
    assert parse_board(spec.text()) == spec
    assert spec.describe() == "chessboard 10x7 squares (9x6 inner corners), squares 25 mm"
    charuco = parse_board("charuco:10x7:0.025:0.018:4X4_50")
    np.testing.assert_allclose(board_points(spec), board_points(charuco))
    assert parse_board(charuco.text()) == charuco
