"""CameraModel projection and its inverse; intrinsics files in OpenCV FileStorage and ROS camera_info form."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from armtool.calib.model.camera import CameraModel, load_intrinsics, save_intrinsics
from armtool.errors import ArmtoolError

K = np.array([[910.0, 0.0, 641.3], [0.0, 905.0, 358.7], [0.0, 0.0, 1.0]])
DIST = np.array([0.1, -0.25, 5e-4, -3e-4, 0.1])
CAM = CameraModel(K, DIST, 1280, 720)

ROS_YAML = """\
image_width: 1280
image_height: 720
camera_name: head_camera
camera_matrix:
  rows: 3
  cols: 3
  data: [910.0, 0.0, 641.3, 0.0, 905.0, 358.7, 0.0, 0.0, 1.0]
distortion_model: {model}
distortion_coefficients:
  rows: 1
  cols: {n}
  data: [{coeffs}]
rectification_matrix:
  rows: 3
  cols: 3
  data: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
projection_matrix:
  rows: 3
  cols: 4
  data: [910.0, 0.0, 641.3, 0.0, 0.0, 905.0, 358.7, 0.0, 0.0, 0.0, 1.0, 0.0]
"""

# What OpenCV 4's calibration sample writes (the header OpenCV 5 no longer emits).
OPENCV4_YAML = """\
%YAML:1.0
---
calibration_time: "Mon 01 Jan 2024"
image_width: 1280
image_height: 720
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 910., 0., 641.29999999999995, 0., 905., 358.69999999999999, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 5
   cols: 1
   dt: d
   data: [ 0.1, -0.25, 5.0000000000000001e-04, -2.9999999999999997e-04, 0.1 ]
avg_reprojection_error: 0.21
"""


def ros_yaml(model: str, coeffs: list[float]) -> str:
    return ROS_YAML.format(model=model, n=len(coeffs), coeffs=", ".join(repr(c) for c in coeffs))


def assert_same(cam: CameraModel, K_: np.ndarray = K, dist: np.ndarray = DIST) -> None:
    np.testing.assert_array_equal(cam.K, K_)
    np.testing.assert_array_equal(cam.dist, dist)
    assert (cam.width, cam.height) == (1280, 720)


def test_project_matches_opencv_and_is_nan_behind_the_camera() -> None:
    rng = np.random.default_rng(0)
    pts = rng.uniform([-0.4, -0.3, 0.4], [0.4, 0.3, 1.2], (50, 3))
    expected, _ = cv2.projectPoints(pts, np.zeros(3), np.zeros(3), K, DIST)
    np.testing.assert_allclose(CAM.project(pts), expected.reshape(-1, 2), atol=1e-9)
    behind = CAM.project(np.array([[0.1, 0.1, -1.0], [0.0, 0.0, 0.0]]))
    assert np.all(np.isnan(behind))


def test_normalized_inverts_project_to_a_nanopixel_across_the_image() -> None:
    wide = CameraModel(np.array([[600.0, 0, 640], [0, 600.0, 360], [0, 0, 1]]), DIST, 1280, 720)
    rng = np.random.default_rng(1)
    pts = rng.uniform([-1.2, -0.7, 1.0], [1.2, 0.7, 1.0], (4000, 3))
    px = wide.project(pts)
    inside = (px[:, 0] >= 0) & (px[:, 0] < 1280) & (px[:, 1] >= 0) & (px[:, 1] < 720)
    assert inside.sum() > 1000
    back = wide.normalized(px[inside])
    assert np.max(np.abs(back - pts[inside, :2])) * 600 < 1e-6
    # OpenCV's default (5 iterations) is visibly off near the corners: why we iterate longer.
    default = cv2.undistortPoints(px[inside].reshape(-1, 1, 2), wide.K, DIST).reshape(-1, 2)
    assert np.max(np.abs(default - pts[inside, :2])) * 600 > 0.05


def test_camera_model_is_validated_and_read_only() -> None:
    with pytest.raises(ArmtoolError, match="3x3"):
        CameraModel(np.eye(2), DIST, 1280, 720)
    with pytest.raises(ArmtoolError, match="0, 4, 5, 8, 12 or 14"):
        CameraModel(K, np.zeros(6), 1280, 720)
    with pytest.raises(ArmtoolError, match="fx, fy > 0"):
        CameraModel(np.diag([-1.0, 1.0, 1.0]), DIST, 1280, 720)
    with pytest.raises(ValueError):
        CAM.K[0, 0] = 1.0
    assert CameraModel(K, [], 10, 10).dist.shape == (0,)
    assert not CameraModel(K, np.zeros(5), 10, 10).has_distortion


def test_save_then_load_round_trips_exactly_and_atomically(tmp_path: Path) -> None:
    path = tmp_path / "camera.yaml"
    save_intrinsics(CAM, path)
    assert_same(load_intrinsics(path))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["camera.yaml"]
    # OpenCV itself reads what we wrote.
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ)
    np.testing.assert_array_equal(fs.getNode("camera_matrix").mat(), K)
    assert fs.getNode("image_width").real() == 1280
    fs.release()


def test_loads_opencv_filestorage_written_by_opencv(tmp_path: Path) -> None:
    yaml_path, xml_path = tmp_path / "cv.yaml", tmp_path / "cv.xml"
    for path, k_key, d_key in ((yaml_path, "camera_matrix", "distortion_coefficients"), (xml_path, "K", "D")):
        fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
        fs.write("image_width", 1280)
        fs.write("image_height", 720)
        fs.write(k_key, K)
        fs.write(d_key, DIST.reshape(5, 1))
        fs.release()
        assert_same(load_intrinsics(path))


def test_loads_opencv4_header_and_other_key_spellings(tmp_path: Path) -> None:
    path = tmp_path / "ost.yaml"
    path.write_text(OPENCV4_YAML)
    assert_same(load_intrinsics(path))
    plain = tmp_path / "plain.yaml"
    plain.write_text(f"K: {K.reshape(-1).tolist()}\nD: []\nimage_size: [1280, 720]\n")
    assert_same(load_intrinsics(plain), dist=np.zeros(0))


@pytest.mark.parametrize(
    ("model", "coeffs"),
    [
        ("plumb_bob", [0.1, -0.25, 5e-4, -3e-4, 0.1]),
        ("rational_polynomial", [0.1, -0.25, 5e-4, -3e-4, 0.1, 0.01, 0.02, 0.03]),
    ],
)
def test_loads_ros_camera_info(tmp_path: Path, model: str, coeffs: list[float]) -> None:
    path = tmp_path / "camera_info.yaml"
    path.write_text(ros_yaml(model, coeffs))
    assert_same(load_intrinsics(path), dist=np.array(coeffs))


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (ROS_YAML.replace("camera_matrix:", "camera_mat:"), "missing key 'camera_matrix'"),
        (
            ros_yaml("plumb_bob", [0.1, 0.2, 0.0, 0.0, 0.0]).replace(
                "0.0, 0.0, 1.0]\ndistortion_model", "0.0, 1.0]\ndistortion_model"
            ),
            "key 'camera_matrix' must have 9 values",
        ),
        (
            ros_yaml("plumb_bob", [0.1, 0.2, 0.0, 0.0, 0.0]).replace("distortion_coefficients:", "distortion:"),
            "missing key 'distortion_coefficients'",
        ),
        (ros_yaml("equidistant", [0.1, 0.2, 0.0, 0.0]), "unsupported distortion_model 'equidistant'"),
        (ros_yaml("plumb_bob", [0.1, 0.2, 0.0]), "needs 5 coefficients"),
        (
            ros_yaml("plumb_bob", [0.1, 0.2, 0.0, 0.0, 0.0]).replace("image_width: 1280\n", ""),
            "missing key 'image_width'",
        ),
        (
            ros_yaml("plumb_bob", [0.1, 0.2, 0.0, 0.0, 0.0]).replace("image_height: 720", "image_height: -5"),
            "key 'image_height' must be a positive",
        ),
        (
            ros_yaml("plumb_bob", [0.1, 0.2, 0.0, 0.0, 0.0]).replace("data: [910.0", "data: [fx"),
            "key 'camera_matrix' is not a list of numbers",
        ),
        ("image_width: 1280\ncamera_matrix: [1, 2\n", "cannot parse intrinsics file"),
        ("- just\n- a list\n", "not a mapping"),
        ("%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n   rows: [\n", "not a readable OpenCV FileStorage"),
    ],
)
def test_bad_files_name_the_file_and_the_key(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(ArmtoolError) as info:
        load_intrinsics(path)
    assert message in info.value.what
    assert info.value.where is not None and str(path) in info.value.where


def test_missing_file_and_yaml_syntax_error_line(tmp_path: Path) -> None:
    with pytest.raises(ArmtoolError, match="cannot read intrinsics file") as info:
        load_intrinsics(tmp_path / "nope.yaml")
    assert info.value.where == str(tmp_path / "nope.yaml")
    path = tmp_path / "syntax.yaml"
    path.write_text("image_width: 1280\nimage_height: 720\ncamera_matrix: {data: [1, 2}\n")
    with pytest.raises(ArmtoolError) as info:
        load_intrinsics(path)
    assert info.value.where == f"{path}:3"


def test_an_intrinsics_fifo_is_refused_without_waiting(tmp_path: Path) -> None:
    import os

    from armtool.calib.model.camera import load_intrinsics
    from armtool.errors import ArmtoolError

    fifo = tmp_path / "camera.yaml"
    os.mkfifo(fifo)  # nobody writes to it: reading would block forever
    with pytest.raises(ArmtoolError, match="not a regular file"):
        load_intrinsics(fifo)
