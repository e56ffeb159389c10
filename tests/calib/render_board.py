"""Board images for the tests: `armtool.calib.simulation.render.render_board` (the exact inverse mapping of the
tag renderer, for chessboards, ChArUco boards and AprilTag grids) with the photometry the tests
want, and the poses a user takes (`random_board_pose`, `spread_board_poses`).

`render_board` here adds what real photos have and the renderer's defaults leave out: an
illumination gradient and a motion blur along a direction (a board that moved during the
exposure); perspective comes from the pose (tilts up to 60° are drawn exactly).
"""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import NDArray

from armtool.calib.model.camera import Array, CameraModel
from armtool.calib.simulation.render import _rotvec, board_in_view, board_outline_m
from armtool.calib.simulation.render import render_board as _render
from armtool.calib.targets.boards import BoardSpec


def render_board(
    camera: CameraModel,
    cMb: Array,
    spec: BoardSpec,
    *,
    noise_sigma: float = 2 / 255,
    motion_px: float = 0.0,
    motion_deg: float = 0.0,
    rng: np.random.Generator | None = None,
    **look: float,
) -> NDArray[np.uint8]:
    """8-bit grey image (H, W) of the board at pose `cMb` (`look`: the renderer's blur, reflectances,
    gradient, margin); `motion_px` smears it over that many pixels along the direction
    `motion_deg` (0 = +x) before the noise is added."""
    import cv2

    rng = np.random.default_rng(0) if rng is None else rng
    if motion_px <= 0:
        return _render(camera, cMb, spec, noise_sigma=noise_sigma, rng=rng, **look)  # type: ignore[arg-type]
    clean = _render(camera, cMb, spec, noise_sigma=0.0, rng=rng, **look).astype(np.float32)  # type: ignore[arg-type]
    size = int(np.ceil(motion_px)) | 1
    kernel = np.zeros((size, size), np.float32)
    c = size // 2
    d = np.array([np.cos(np.radians(motion_deg)), np.sin(np.radians(motion_deg))])
    for s in np.linspace(-motion_px / 2, motion_px / 2, 4 * size):
        x, y = np.clip(np.round(c + s * d).astype(int), 0, size - 1)
        kernel[y, x] += 1.0
    smeared = cast("NDArray[np.float32]", cv2.filter2D(clean, -1, kernel / kernel.sum(), borderType=cv2.BORDER_REFLECT))
    noisy = smeared + rng.normal(0.0, noise_sigma * 255.0, smeared.shape).astype(np.float32)
    return cast("NDArray[np.uint8]", np.clip(np.round(noisy), 0, 255).astype(np.uint8))


def random_board_pose(
    camera: CameraModel,
    spec: BoardSpec,
    rng: np.random.Generator,
    *,
    distance_m: tuple[float, float] = (0.3, 0.6),
    max_tilt_deg: float = 45.0,
    margin_m: float | None = None,
    attempts: int = 500,
) -> Array:
    """A random cMb with the whole board in view: its centre on the ray through a random pixel,
    tilted up to `max_tilt_deg` about a random in-plane axis, spun by up to ±30°."""
    margin = spec.square_m if margin_m is None else margin_m
    outline = board_outline_m(spec, margin)
    centre_b = outline.mean(axis=0)
    for _ in range(attempts):
        spin = rng.uniform(-np.pi / 6, np.pi / 6)
        tilt = np.deg2rad(rng.uniform(0.0, max_tilt_deg))
        a = rng.uniform(0.0, 2 * np.pi)
        R = _rotvec(np.array([np.cos(a), np.sin(a), 0.0]) * tilt) @ _rotvec(np.array([0.0, 0.0, spin]))
        u, v = rng.uniform(0.15, 0.85) * (camera.width - 1), rng.uniform(0.15, 0.85) * (camera.height - 1)
        ray = np.append(camera.normalized(np.array([[u, v]]))[0], 1.0)
        cMb = np.eye(4)
        cMb[:3, :3] = R
        cMb[:3, 3] = ray / np.linalg.norm(ray) * rng.uniform(*distance_m) - R @ centre_b
        if board_in_view(camera, cMb, spec, margin):
            return cMb
    raise RuntimeError("no pose with the whole board in view: the board is too large for these distances")


def spread_board_poses(
    camera: CameraModel,
    spec: BoardSpec,
    n: int,
    rng: np.random.Generator,
    *,
    distance_m: tuple[float, float] = (0.3, 0.45),
    tilt_deg: tuple[float, float] = (25.0, 45.0),
    margin_m: float | None = None,
) -> list[Array]:
    """`n` poses as a careful user takes them: the board's centre cycles over a 3×3 grid of image
    positions (jittered) and is tilted 25-45° towards a direction that turns by 135° each image;
    a pose whose board leaves the image is pulled towards the centre (then moved back) until it fits."""
    margin = spec.square_m if margin_m is None else margin_m
    centre_b = board_outline_m(spec, margin).mean(axis=0)
    spots = [(fx, fy) for fy in (0.2, 0.5, 0.8) for fx in (0.2, 0.5, 0.8)]
    poses: list[Array] = []
    for k in range(n):
        a = np.deg2rad(135.0 * k) + rng.uniform(-0.2, 0.2)
        tilt = np.deg2rad(rng.uniform(*tilt_deg))
        R = _rotvec(np.array([np.cos(a), np.sin(a), 0.0]) * tilt) @ _rotvec(
            np.array([0.0, 0.0, rng.uniform(-0.3, 0.3)])
        )
        fx, fy = spots[k % len(spots)]
        dist = rng.uniform(*distance_m)
        pose = None
        while pose is None and dist < 10 * distance_m[1]:
            for pull in np.linspace(0.0, 1.0, 21):
                u = (0.5 + (1 - pull) * (fx - 0.5) + rng.uniform(-0.03, 0.03)) * (camera.width - 1)
                v = (0.5 + (1 - pull) * (fy - 0.5) + rng.uniform(-0.03, 0.03)) * (camera.height - 1)
                ray = np.append(camera.normalized(np.array([[u, v]]))[0], 1.0)
                cMb = np.eye(4)
                cMb[:3, :3] = R
                cMb[:3, 3] = ray / np.linalg.norm(ray) * dist - R @ centre_b
                if board_in_view(camera, cMb, spec, margin):
                    pose = cMb
                    break
            dist *= 1.1  # the board does not fit at this distance: step back
        if pose is None:
            raise RuntimeError("the board does not fit in the image")
        poses.append(pose)
    return poses
