"""Synthetic camera images of a calibration board (ChArUco or AprilTag grid) with known intrinsics.

The same exact inverse mapping as `armtool.calib.render` (pixel → lens undistortion → ray →
board plane, OpenCV's pixel-centre convention): every pixel whose four corners fall in one
region of the board (a square, a marker cell, the margin, the background) takes that region's
value; the others are supersampled on an n-rooks pattern and box-filtered. Then Gaussian blur,
Gaussian noise and 8-bit rounding. Used by the intrinsics tests: what `calibrate camera`
recovers is compared with the camera that drew the images.
"""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import NDArray

from armtool.calib.boards import BoardKind, BoardSpec, cv_board
from armtool.calib.camera import Array, CameraModel
from armtool.calib.render import _rotvec, _subsample_offsets


class _Layout:
    """The board as regions: a grid of cells of pitch `pitch`, each with a base value and
    optionally a marker (its top-left corner and its (n+2)² cells), a white margin, background."""

    def __init__(self, spec: BoardSpec, margin_m: float, black: float, white: float, background: float) -> None:
        import cv2

        board = cv_board(spec)
        dictionary = board.getDictionary()
        n = int(dictionary.markerSize) + 2
        charuco = spec.kind is BoardKind.CHARUCO
        self.pitch = spec.square_m if charuco else spec.square_m + spec.marker_m
        self.cols, self.rows = spec.cols, spec.rows
        self.width_m = spec.cols * spec.square_m if charuco else spec.cols * self.pitch - spec.marker_m
        self.height_m = spec.rows * spec.square_m if charuco else spec.rows * self.pitch - spec.marker_m
        self.margin = margin_m
        self.n = n
        self.marker_m = spec.marker_m if charuco else spec.square_m
        cells = self.cols * self.rows
        self.per_cell = 1 + n * n
        self.origin = np.full((cells, 2), np.nan)  # marker top-left per cell
        table = np.full(2 + cells * self.per_cell, white, dtype=np.float32)
        table[0] = background
        for i in range(cells):
            r, c = divmod(i, self.cols)
            table[2 + i * self.per_cell] = black if charuco and (r + c) % 2 == 0 else white
        for obj, marker_id in zip(board.getObjPoints(), np.asarray(board.getIds()).reshape(-1)):
            tl = np.asarray(obj, dtype=np.float64).reshape(4, 3)[0, :2]
            c, r = (int(np.floor((v + self.marker_m / 2) / self.pitch)) for v in tl)  # the cell holding its centre
            i = r * self.cols + c
            self.origin[i] = tl
            bits = cv2.aruco.generateImageMarker(dictionary, int(marker_id), n, borderBits=1) > 127
            table[2 + i * self.per_cell + 1 : 2 + (i + 1) * self.per_cell] = np.where(bits.reshape(-1), white, black)
        self.table = table

    def region(self, x: Array, y: Array) -> NDArray[np.intp]:
        """Region id of board-plane points (metres, board frame)."""
        m = self.margin
        inside_board = (x >= -m) & (x < self.width_m + m) & (y >= -m) & (y < self.height_m + m)
        inside_pattern = (x >= 0) & (x < self.width_m) & (y >= 0) & (y < self.height_m)
        c = np.clip(np.floor(x / self.pitch), 0, self.cols - 1).astype(np.intp)
        r = np.clip(np.floor(y / self.pitch), 0, self.rows - 1).astype(np.intp)
        cell = r * self.cols + c
        origin = self.origin[cell]
        u = np.floor((x - origin[..., 0]) / self.marker_m * self.n)
        v = np.floor((y - origin[..., 1]) / self.marker_m * self.n)
        with np.errstate(invalid="ignore"):
            in_marker = (u >= 0) & (u < self.n) & (v >= 0) & (v < self.n)
        sub = np.where(in_marker, 1 + np.nan_to_num(v) * self.n + np.nan_to_num(u), 0).astype(np.intp)
        ids = 2 + cell * self.per_cell + sub
        # Outside the grid's cells but inside the pattern (AprilTag grid: the gaps) is white.
        in_cell = (x < (c + 1) * self.pitch) & (y < (r + 1) * self.pitch)
        ids = np.where(in_cell, ids, 1)
        return cast("NDArray[np.intp]", np.where(inside_pattern, ids, np.where(inside_board, 1, 0)))


def board_outline_m(spec: BoardSpec, margin_m: float) -> Array:
    """Corners (4,3) of the printed board including its margin, in the board frame."""
    lay_w = (
        spec.cols * spec.square_m
        if spec.kind is BoardKind.CHARUCO
        else spec.cols * (spec.square_m + spec.marker_m) - spec.marker_m
    )
    lay_h = (
        spec.rows * spec.square_m
        if spec.kind is BoardKind.CHARUCO
        else spec.rows * (spec.square_m + spec.marker_m) - spec.marker_m
    )
    m = margin_m
    return np.array([[-m, -m, 0.0], [lay_w + m, -m, 0.0], [lay_w + m, lay_h + m, 0.0], [-m, lay_h + m, 0.0]])


def board_in_view(camera: CameraModel, cMb: Array, spec: BoardSpec, margin_m: float) -> bool:
    """True when the whole printed board is in the image and faces the camera."""
    if float(cMb[:3, 2] @ cMb[:3, 3]) <= 0.0:  # the board's z points into it: the camera must be on its −z side
        return False
    outline = board_outline_m(spec, margin_m)
    s = np.linspace(0.0, 1.0, 32, endpoint=False)[:, None]
    pts = np.concatenate([outline[i] + s * (outline[(i + 1) % 4] - outline[i]) for i in range(4)])
    pc = pts @ cMb[:3, :3].T + cMb[:3, 3]
    if np.any(pc[:, 2] < 0.01):
        return False
    px = camera.project(pc)
    inside = (px[:, 0] >= 0) & (px[:, 0] <= camera.width - 1) & (px[:, 1] >= 0) & (px[:, 1] <= camera.height - 1)
    if not bool(np.all(inside)):
        return False
    if camera.has_distortion:  # the distortion polynomial must not fold back here
        back = camera.normalized(px)
        return bool(np.max(np.abs(back - pc[:, :2] / pc[:, 2:])) < 1e-6)
    return True


def render_board(
    camera: CameraModel,
    cMb: Array,
    spec: BoardSpec,
    *,
    margin_m: float | None = None,
    blur_sigma_px: float = 0.7,
    noise_sigma: float = 2 / 255,
    black: float = 0.1,
    white: float = 0.85,
    background: float = 0.35,
    supersample: int = 4,
    rng: np.random.Generator | None = None,
) -> NDArray[np.uint8]:
    """8-bit grey image (H, W) of the board at pose `cMb` (board frame in camera frame)."""
    import cv2

    rng = np.random.default_rng(0) if rng is None else rng
    margin = spec.square_m if margin_m is None else margin_m
    layout = _Layout(spec, margin, black, white, background)
    R, t = np.asarray(cMb, dtype=np.float64)[:3, :3], np.asarray(cMb, dtype=np.float64)[:3, 3]
    origin_b = -R.T @ t  # camera centre in the board frame

    def regions(xy: Array) -> NDArray[np.intp]:
        x, y = xy[..., 0], xy[..., 1]
        dx = x * R[0, 0] + y * R[1, 0] + R[2, 0]
        dy = x * R[0, 1] + y * R[1, 1] + R[2, 1]
        dz = x * R[0, 2] + y * R[1, 2] + R[2, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = -origin_b[2] / dz
            bx, by = origin_b[0] + lam * dx, origin_b[1] + lam * dy
        ok = np.isfinite(lam) & (lam > 0)
        ids = layout.region(np.where(ok, bx, -1e9), np.where(ok, by, -1e9))
        return cast("NDArray[np.intp]", np.where(ok, ids, 0))

    W, H = camera.width, camera.height
    gx, gy = np.meshgrid(np.arange(W + 1) - 0.5, np.arange(H + 1) - 0.5)
    lattice = camera.normalized(np.stack([gx.reshape(-1), gy.reshape(-1)], axis=1)).reshape(H + 1, W + 1, 2)
    ids = regions(lattice)
    corner = ids[:-1, :-1]
    uniform = (corner == ids[:-1, 1:]) & (corner == ids[1:, :-1]) & (corner == ids[1:, 1:])
    image = layout.table[corner]
    rows, cols = np.nonzero(~uniform)
    if len(rows):
        fx, fy = _subsample_offsets(supersample).T
        weights = np.stack([(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy], axis=1)
        quad = np.stack(
            [lattice[rows, cols], lattice[rows, cols + 1], lattice[rows + 1, cols], lattice[rows + 1, cols + 1]], axis=1
        )
        image[rows, cols] = layout.table[regions(weights @ quad)].mean(axis=1)
    if blur_sigma_px > 0:
        image = cast(
            "NDArray[np.float32]", cv2.GaussianBlur(image, (0, 0), blur_sigma_px, borderType=cv2.BORDER_REFLECT)
        )
    if noise_sigma > 0:
        image = image + rng.normal(0.0, noise_sigma, image.shape).astype(np.float32)
    return cast("NDArray[np.uint8]", np.clip(np.round(image * 255.0), 0, 255).astype(np.uint8))


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
