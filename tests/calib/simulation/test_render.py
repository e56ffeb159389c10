"""The tag renderer: OpenCV's pixel-centre convention, the right texture in the right place, views it refuses."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.model.camera import CameraModel
from armtool.calib.simulation.render import random_view_pose, render_tag, tag_in_view
from armtool.calib.targets.apriltag import tag_bits, tag_object_points
from armtool.errors import ArmtoolError

K = np.array([[910.0, 0.0, 641.3], [0.0, 910.0, 358.7], [0.0, 0.0, 1.0]])
CAM = CameraModel(K, np.zeros(5), 1280, 720)
CAM_DIST = CameraModel(K, np.array([0.1, -0.25, 5e-4, -3e-4, 0.1]), 1280, 720)
FACING = np.diag([1.0, -1.0, -1.0])  # tag x right, y up, z towards the camera
CLEAN = {"blur_sigma_px": 0.0, "noise_sigma": 0.0, "gradient": 0.0}


def pose(R: np.ndarray, t: list[float]) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = t
    return T


def test_an_edge_at_x_560_makes_pixel_560_exactly_half_grey() -> None:
    size, z = 0.08, 0.5
    x_left = (560.0 - K[0, 2]) * z / K[0, 0]  # camera x of the black square's left edge
    cMt = pose(FACING, [x_left + size / 2, 0.0, z])
    img = render_tag(CAM, cMt, size, "tag36h11", 0, black=0.2, white=1.0, **CLEAN)
    assert img is not None
    row = int(round(K[1, 2] + 0.3 * size / 2 * K[1, 1] / z))  # inside the left border band
    assert list(img[row, 558:563]) == [255, 255, 153, 51, 51]  # 0.6 = (0.2 + 1.0) / 2 at pixel 560


def test_cells_are_where_the_bits_say_with_the_tag_facing_the_camera() -> None:
    size, z, tag_id = 0.08, 0.4, 5
    cMt = pose(FACING, [0.01, -0.02, z])
    img = render_tag(CAM, cMt, size, "tag36h11", tag_id, **CLEAN)
    assert img is not None
    bits = tag_bits("tag36h11", tag_id)
    n = bits.shape[0]
    cell = size / n
    centres = np.array(
        [[-size / 2 + (c + 0.5) * cell, size / 2 - (r + 0.5) * cell, 0.0] for r in range(n) for c in range(n)]
    )
    px = CAM.project(centres @ cMt[:3, :3].T + cMt[:3, 3])
    values = img[np.round(px[:, 1]).astype(int), np.round(px[:, 0]).astype(int)]
    expected = np.where(bits.reshape(-1), round(0.8 * 255), round(0.12 * 255))
    np.testing.assert_array_equal(values, expected)
    # The white margin (2 cells) and the background outside it.
    corners = CAM.project(tag_object_points(size) @ cMt[:3, :3].T + cMt[:3, 3])
    tl = corners[0]
    assert img[int(tl[1] - 1.0 * cell * K[1, 1] / z), int(tl[0])] == round(0.8 * 255)
    assert img[int(tl[1] - 2.5 * cell * K[1, 1] / z), int(tl[0])] == round(0.35 * 255)


def test_views_that_cannot_be_drawn_whole_return_none() -> None:
    size = 0.08
    assert render_tag(CAM, pose(FACING, [0.0, 0.0, -0.5]), size, "tag36h11", 0) is None  # behind
    assert render_tag(CAM, pose(np.eye(3), [0.0, 0.0, 0.5]), size, "tag36h11", 0) is None  # its back
    assert render_tag(CAM, pose(FACING, [0.33, 0.0, 0.5]), size, "tag36h11", 0) is None  # off the right edge
    assert not tag_in_view(CAM, pose(FACING, [0.33, 0.0, 0.5]), size)
    assert tag_in_view(CAM, pose(FACING, [0.25, 0.0, 0.5]), size)
    with pytest.raises(ArmtoolError, match="not in tag36h11"):
        render_tag(CAM, pose(FACING, [0.0, 0.0, 0.5]), size, "tag36h11", 587)


def test_same_seed_same_image_and_noise_has_the_requested_sigma() -> None:
    cMt = pose(FACING, [0.0, 0.0, 0.5])
    a = render_tag(CAM, cMt, 0.08, "tag36h11", 1, rng=np.random.default_rng(7))
    b = render_tag(CAM, cMt, 0.08, "tag36h11", 1, rng=np.random.default_rng(7))
    c = render_tag(CAM, cMt, 0.08, "tag36h11", 1, rng=np.random.default_rng(8))
    assert a is not None and b is not None and c is not None
    np.testing.assert_array_equal(a, b)
    assert np.any(a != c)
    flat = render_tag(CAM, cMt, 0.08, "tag36h11", 1, noise_sigma=6 / 255, gradient=0.0, rng=np.random.default_rng(1))
    assert flat is not None
    patch = flat[20:120, 20:220].astype(float)  # background only
    assert abs(patch.std() - 6.0) < 0.5
    assert abs(patch.mean() - 0.35 * 255) < 0.5


def test_gradient_spans_the_requested_fraction_of_the_image() -> None:
    img = render_tag(
        CAM, pose(FACING, [0.0, 0.0, 0.6]), 0.05, "tag36h11", 0, blur_sigma_px=0.0, noise_sigma=0.0, gradient=0.2
    )
    assert img is not None
    corners = img[[0, 0, -1, -1], [0, -1, 0, -1]].astype(float) / (0.35 * 255)
    assert 0.17 < corners.max() - corners.min() < 0.21


def test_distorted_render_puts_the_plate_where_the_lens_model_projects_it() -> None:
    # A fronto-parallel tag near the image corner, where k1..k3 move it by several pixels.
    cMt = pose(FACING, [-0.3, -0.17, 0.6])
    img = render_tag(CAM_DIST, cMt, 0.08, "tag36h11", 0, black=0.0, white=1.0, **CLEAN)
    assert img is not None
    corners = CAM_DIST.project(tag_object_points(0.08) @ cMt[:3, :3].T + cMt[:3, 3])
    ideal = CAM.project(tag_object_points(0.08) @ cMt[:3, :3].T + cMt[:3, 3])
    assert np.max(np.linalg.norm(corners - ideal, axis=1)) > 4.0
    # Sample just inside / outside the black square along the diagonal of each corner.
    centre = corners.mean(axis=0)
    for corner in corners:
        direction = (centre - corner) / np.linalg.norm(centre - corner)
        inside, outside = corner + 1.5 * direction, corner - 1.5 * direction
        assert img[int(round(inside[1])), int(round(inside[0]))] == 0
        assert img[int(round(outside[1])), int(round(outside[0]))] == 255


def test_random_view_pose_faces_the_camera_within_the_tilt() -> None:
    rng = np.random.default_rng(3)
    for _ in range(50):
        cMt = random_view_pose(CAM, rng, distance_m=(0.3, 1.0), max_tilt_deg=60.0)
        normal_towards_camera = -cMt[:3, 3] / np.linalg.norm(cMt[:3, 3])
        assert 0.3 - 1e-9 <= np.linalg.norm(cMt[:3, 3]) <= 1.0 + 1e-9
        # The tag's z axis points back at the camera, within 60° of the optical axis.
        assert cMt[2, 2] <= -np.cos(np.radians(60.0)) + 1e-9
        assert normal_towards_camera @ cMt[:3, 2] > 0
