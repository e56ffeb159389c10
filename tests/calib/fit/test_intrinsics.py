"""Camera intrinsics from board images: recovered against the camera that rendered them."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from armtool.calib.choices import DistortionModel
from armtool.calib.fit.intrinsics import calibrate_views, find_boards, write_intrinsics
from armtool.calib.model.camera import CameraModel, load_intrinsics
from armtool.calib.targets.boards import BoardKind, BoardView, board_points, find_board, parse_board
from armtool.errors import ArmtoolError
from tests.calib.board_images import APRILGRID, CHARUCO, IMAGES, TRUE_CAMERA, board_images
from tests.calib.render_board import render_board, spread_board_poses


def _views(board: str) -> list[tuple[str, BoardView]]:
    spec = parse_board(board)
    return [(f"{k:02d}.png", find_board(img, spec)) for k, img in enumerate(board_images(board))]


def test_parse_board_reads_both_kinds_and_defaults() -> None:
    c = parse_board("charuco:9x7:0.03:0.022")
    assert (c.kind, c.cols, c.rows, c.square_m, c.marker_m, c.dictionary) == (
        BoardKind.CHARUCO,
        9,
        7,
        0.03,
        0.022,
        "DICT_6X6_250",
    )
    assert parse_board("charuco:9x7:0.03:0.022:5x5_100").dictionary == "DICT_5X5_100"
    g = parse_board("aprilgrid:6x4:0.04:0.01")
    assert (g.kind, g.dictionary, g.family) == (BoardKind.APRILGRID, "DICT_APRILTAG_36h11", "tag36h11")
    assert len(board_points(c)) == 8 * 6 and len(board_points(g)) == 4 * 24


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("checker:9x7:0.03", "unknown board type"),
        ("charuco:9x7:0.03", "4 or 5 fields"),
        ("charuco:9by7:0.03:0.02", "COLSxROWS"),
        ("charuco:9x7:30:22", "metres"),
        ("charuco:9x7:0.02:0.03", "smaller than the square"),
        ("charuco:9x7:0.03:0.02:DICT_NOPE", "unknown ArUco dictionary"),
        ("charuco:30x30:0.03:0.02:4X4_50", "has only 50"),
        ("aprilgrid:6x4:0.04:0.01:tag99h1", "unknown AprilTag family"),
    ],
)
def test_parse_board_rejects_bad_specs(text: str, message: str) -> None:
    with pytest.raises(ArmtoolError, match=message):
        parse_board(text)


@pytest.mark.parametrize("board", [CHARUCO, APRILGRID])
def test_rendered_corners_are_found_where_the_camera_projects_them(board: str) -> None:
    spec = parse_board(board)
    rng = np.random.default_rng(5)
    pose = spread_board_poses(TRUE_CAMERA, spec, 1, rng, distance_m=(0.28, 0.4))[0]
    view = find_board(render_board(TRUE_CAMERA, pose, spec, rng=rng), spec)
    truth = TRUE_CAMERA.project(board_points(spec)[view.ids] @ pose[:3, :3].T + pose[:3, 3])
    err = np.linalg.norm(view.pixels - truth, axis=1)
    assert not view.reason and len(view.ids) >= len(board_points(spec)) * 0.9
    assert np.median(err) < 0.25 and np.abs((view.pixels - truth).mean(axis=0)).max() < 0.1


@pytest.mark.parametrize("board", [CHARUCO, APRILGRID])
def test_recovers_focal_length_and_principal_point_of_the_rendering_camera(board: str) -> None:
    views = _views(board)
    result = calibrate_views(views, parse_board(board), (640, 480))
    K, K0 = result.camera.K, TRUE_CAMERA.K
    assert abs(K[0, 0] / K0[0, 0] - 1) < 0.002 and abs(K[1, 1] / K0[1, 1] - 1) < 0.002
    assert abs(K[0, 2] - K0[0, 2]) < 1.0 and abs(K[1, 2] - K0[1, 2]) < 1.0
    assert abs(result.camera.dist[0] - TRUE_CAMERA.dist[0]) < 0.01
    # The fitted lens distorts like the true one wherever the board was seen (elsewhere it is
    # extrapolated, and the coverage warning says so): displacements < 0.3 px apart.
    seen = np.concatenate([v.pixels for _, v in views])
    rays = np.column_stack([TRUE_CAMERA.normalized(seen), np.ones(len(seen))])

    def displacement(cam: CameraModel) -> np.ndarray:
        return cam.project(rays) - cam.without_distortion().project(rays)

    assert np.abs(displacement(result.camera) - displacement(TRUE_CAMERA)).max() < 0.3
    assert result.rms_px < 0.3 and len(result.used) == IMAGES[board] and all(v.tilt_deg > 15 for v in result.used)


def test_an_image_whose_corners_disagree_is_rejected_as_an_outlier() -> None:
    views = _views(CHARUCO)
    name, bad = views[3]
    shifted = bad.pixels.copy()
    shifted[::2] += 2.0  # every other corner 2 px off: no pose explains it
    views[3] = (name, BoardView(bad.ids, shifted))
    result = calibrate_views(views, parse_board(CHARUCO), (640, 480))
    rejected = [v for v in result.views if not v.used]
    assert (
        [v.name for v in rejected] == [name] and rejected[0].reason.startswith("outlier") and rejected[0].rms_px > 1.0
    )
    assert abs(result.camera.K[0, 0] / 600.0 - 1) < 0.002


def _projected_views(spec_text: str, poses: list[np.ndarray], camera: CameraModel) -> list[tuple[str, BoardView]]:
    spec = parse_board(spec_text)
    pts = board_points(spec)
    rng = np.random.default_rng(0)
    views = []
    for k, p in enumerate(poses):
        px = camera.project(pts @ p[:3, :3].T + p[:3, 3]) + rng.normal(0, 0.05, (len(pts), 2))
        views.append((f"{k}", BoardView(np.arange(len(pts)), px)))
    return views


def test_warns_when_the_board_never_reaches_the_corners_or_never_tilts() -> None:
    spec = parse_board(CHARUCO)
    rng = np.random.default_rng(1)
    poses = []
    for _k in range(12):  # small, near the centre, facing the camera within 10°
        R = cv2.Rodrigues(np.array([rng.uniform(-0.15, 0.15), rng.uniform(-0.15, 0.15), rng.uniform(-0.3, 0.3)]))[0]
        centre = np.array([spec.cols * spec.square_m / 2, spec.rows * spec.square_m / 2, 0])
        pose = np.eye(4)
        pose[:3, :3] = R
        pose[:3, 3] = np.array([rng.uniform(-0.02, 0.02), rng.uniform(-0.02, 0.02), 0.6]) - R @ centre
        poses.append(pose)
    result = calibrate_views(_projected_views(CHARUCO, poses, TRUE_CAMERA), spec, (640, 480), DistortionModel.K1K2)
    text = " ".join(result.warnings)
    assert "poor coverage" in text and "top-left" in text and "never tilted" in text
    assert result.coverage < 0.5


def test_too_few_images_is_an_error_naming_what_was_seen() -> None:
    views = _views(CHARUCO)[:5]
    blank = np.full((480, 640), 128, np.uint8)
    views.append(("blank.png", find_board(blank, parse_board(CHARUCO))))
    with pytest.raises(ArmtoolError, match=r"found in 5 of 6 images; at least 10") as info:
        calibrate_views(views, parse_board(CHARUCO), (640, 480))
    assert "blank.png: board not found: 0 ChArUco corners" in info.value.what


def test_written_file_is_what_dataset_yaml_reads(tmp_path: Path) -> None:
    spec = parse_board(APRILGRID)
    result = calibrate_views(_views(APRILGRID), spec, (640, 480), DistortionModel.RATIONAL)
    path = tmp_path / "camera.yaml"
    write_intrinsics(result, spec, path)
    back = load_intrinsics(path)
    assert np.allclose(back.K, result.camera.K) and np.allclose(back.dist, result.camera.dist) and back.dist.size == 8
    assert (back.width, back.height) == (640, 480)
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ)  # OpenCV reads it too
    assert np.allclose(fs.getNode("camera_matrix").mat(), result.camera.K)
    assert fs.getNode("distortion_model").string() == "rational_polynomial"


def test_images_of_different_sizes_are_refused(tmp_path: Path) -> None:
    cv2.imwrite(str(tmp_path / "a.png"), np.zeros((480, 640), np.uint8))
    cv2.imwrite(str(tmp_path / "b.png"), np.zeros((240, 320), np.uint8))
    (tmp_path / "c.png").write_bytes(b"not an image")
    with pytest.raises(ArmtoolError, match="image is 320x240 but a.png is 640x480"):
        find_boards([tmp_path / "a.png", tmp_path / "b.png"], parse_board(CHARUCO))
    with pytest.raises(ArmtoolError, match="cannot read image"):
        find_boards([tmp_path / "c.png"], parse_board(CHARUCO))
