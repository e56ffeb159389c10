"""A dataset's target: a board declared as `calibrate camera --board` spells it, its corners (a
partial ChArUco view keeps the ones it shows), and a planar target's pose."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armtool.calib.inputs.dataset import load_dataset
from armtool.calib.model.camera import CameraModel
from armtool.calib.targets.boards import board_points, parse_board
from armtool.calib.targets.detect import detect_corners
from armtool.calib.targets.pose import planar_pose
from armtool.calib.targets.spec import Target
from tests.calib.inputs.test_dataset import JOINTS, _dataset
from tests.calib.render_board import render_board

CAM = CameraModel(np.array([[910.0, 0, 641.3], [0, 910.0, 358.7], [0, 0, 1]]), np.zeros(5), 1280, 720)
CHARUCO = "charuco:8x6:0.04:0.03:4X4_50"
ROW = ["0,images/0.png,0.1,0.2,0.3,0.4,0.5,0.6"]


def _with_target(tmp_path: Path, target: str, corners: bool = False) -> Path:
    root = _dataset(tmp_path, ROW)
    text = (root / "dataset.yaml").read_text()
    text = text.replace("target: {type: apriltag, family: tag36h11, id: 0, size_m: 0.08, mounted_on: tool0}", target)
    (root / "dataset.yaml").write_text(text)
    if corners:
        (root / "corners.csv").write_text("id,tag_id,u0,v0,u1,v1,u2,v2,u3,v3\n0,0,1,1,2,1,2,2,1,2\n")
    return root


@pytest.mark.parametrize(
    ("target", "kind"),
    [
        ("target: {board: 'chessboard:10x7:0.025', mounted_on: tool0}", "chessboard"),
        (f"target: {{type: charuco, board: '{CHARUCO}'}}", "charuco"),
        ("target: {board: 'aprilgrid:4x3:0.04:0.01'}", "aprilgrid"),
    ],
)
def test_a_board_target_is_read_without_tag_keys(tmp_path: Path, target: str, kind: str) -> None:
    ds = load_dataset(_with_target(tmp_path, target), JOINTS)
    assert not ds.errors, ds.errors
    assert ds.board is not None and ds.board.kind.value == kind
    assert Target.of(ds).points_m.shape == (len(board_points(ds.board)), 3)


@pytest.mark.parametrize(
    ("target", "message"),
    [
        ("target: {board: 'chessboard:8x6:0.025'}", "looks the same turned by 180°"),
        (
            f"target: {{type: chessboard, board: '{CHARUCO}'}}",
            "target.type is 'chessboard' but target.board is a charuco",
        ),
        ("target: {type: charuco}", "target.board is missing"),
        ("target: {board: 'charuco:8x6:0.04'}", "target.board: board 'charuco:8x6:0.04' needs 4 or 5 fields"),
        ("target: {board: [1, 2]}", "must be a board spec"),
    ],
)
def test_an_unusable_board_target_is_one_problem(tmp_path: Path, target: str, message: str) -> None:
    ds = load_dataset(_with_target(tmp_path, target), JOINTS)
    (problem,) = ds.errors
    assert message in problem.what and problem.where.endswith("dataset.yaml")


def test_corners_csv_is_refused_for_a_board(tmp_path: Path) -> None:
    ds = load_dataset(_with_target(tmp_path, "target: {board: 'chessboard:10x7:0.025'}", corners=True), JOINTS)
    (problem,) = ds.errors
    assert "corners.csv holds one AprilTag's corners, but the target is a board" in problem.what
    assert ds.corners_file is None and not ds.corners


def _pose(tilt_deg: float, t: list[float]) -> np.ndarray:
    from armtool.calib.simulation.render import _rotvec

    pose = np.eye(4)
    pose[:3, :3] = _rotvec(np.array([np.radians(tilt_deg), 0.0, 0.0])) @ _rotvec(np.array([0.0, 0.0, 0.3]))
    pose[:3, 3] = t
    return pose


def test_a_partial_charuco_view_keeps_the_corners_it_shows_with_their_ids() -> None:
    spec = parse_board(CHARUCO)
    target = Target(board=spec)
    pose = _pose(25.0, [0.05, -0.05, 0.45])  # the board's right part is out of the image
    image = render_board(CAM, pose, spec, blur_sigma_px=1.2, noise_sigma=3 / 255, gradient=0.3)
    corners, reason = detect_corners(image, target, CAM)
    assert corners is not None and not reason
    truth = CAM.project(target.points_m @ pose[:3, :3].T + pose[:3, 3])
    inside = (truth[:, 0] > 20) & (truth[:, 0] < CAM.width - 20) & (truth[:, 1] > 20) & (truth[:, 1] < CAM.height - 20)
    seen = np.all(np.isfinite(corners), axis=1)
    assert 8 <= seen.sum() < len(corners) and not np.any(seen & ~inside)  # a subset, none invented off-image
    err = np.linalg.norm(corners[seen] - truth[seen], axis=1)
    assert np.median(err) < 0.15 and err.max() < 0.6
    cMt, rms, ambiguous = planar_pose(target.points_m, corners, CAM)
    assert not ambiguous and rms < 0.3
    assert np.linalg.norm(cMt[:3, 3] - pose[:3, 3]) < 2e-3


def test_a_tag_target_goes_through_the_tag_detector() -> None:
    from armtool.calib.simulation.render import render_tag

    target = Target("tag36h11", 3, 0.08)
    cMt = _pose(180.0 + 20.0, [0.02, 0.01, 0.6])  # the tag faces the camera (z towards it)
    image = render_tag(CAM, cMt, 0.08, "tag36h11", 3)
    assert image is not None
    corners, reason = detect_corners(image, target, CAM)
    assert corners is not None and corners.shape == (4, 2) and not reason
    assert np.abs(corners - CAM.project(target.points_m @ cMt[:3, :3].T + cMt[:3, 3])).max() < 0.5
    missing, why = detect_corners(image, Target("tag36h11", 4, 0.08), CAM)
    assert missing is None and "tag 4 not found" in why


def test_planar_pose_is_exact_on_exact_corners_and_refuses_too_few() -> None:
    target = Target(board=parse_board("chessboard:10x7:0.025"))
    pose = _pose(30.0, [-0.03, 0.02, 0.5])
    pixels = CAM.project(target.points_m @ pose[:3, :3].T + pose[:3, 3])
    est, rms, ambiguous = planar_pose(target.points_m, pixels, CAM)
    assert not ambiguous and rms < 1e-6 and np.allclose(est, pose, atol=1e-8)
    few = np.full_like(pixels, np.nan)
    few[:3] = pixels[:3]
    assert planar_pose(target.points_m, few, CAM)[2]
    row = np.full_like(pixels, np.nan)
    row[:9] = pixels[:9]  # one row of corners: a line gives no pose
    assert planar_pose(target.points_m, row, CAM)[2]


def test_the_target_document_reads_back_and_the_face_frame_faces_out() -> None:
    spec = parse_board(CHARUCO)
    doc = Target(board=spec).document("tool0")
    assert doc["type"] == "charuco" and parse_board(str(doc["board"])) == spec and doc["mounted_on"] == "tool0"
    face = Target(board=spec).face_pose()
    assert np.allclose(face[:3, 3], [0.16, 0.12, 0.0]) and np.allclose(face[:3, 2], [0, 0, -1])
    assert np.allclose(Target().face_pose(), np.eye(4)) and Target().document("tool0")["type"] == "apriltag"


def test_an_unusable_board_target_rejects_every_sample_instead_of_looking_for_a_tag(tmp_path: Path) -> None:
    from armtool.calib.inputs.observations import observe

    ds = load_dataset(_with_target(tmp_path, "target: {board: 'chessboard:8x6:0.025'}"), JOINTS)
    assert not Target.of(ds).usable
    (only,) = observe(ds, CAM).values()
    assert only.corners_px is None and "target in dataset.yaml is not usable" in only.reason
    assert Target.of(ds).describe() == "the target"
