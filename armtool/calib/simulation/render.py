"""Synthetic camera images of a planar target (an AprilTag or a calibration board): what
`calibrate simulate` and the detector tests see.

The renderer is exact where it matters for corner accuracy: every sample is an exact inverse
mapping (pixel → lens undistortion → ray → target plane), in OpenCV's pixel-centre convention
(pixel i covers [i − 0.5, i + 0.5], so an edge at x = 560.0 makes pixel 560 exactly half grey).
Pixels whose four corners fall in the same region of the target (a tag cell, a board square, a
marker cell, the margin, the background) are uniform and take one value; the others get n×n
supersamples, box-filtered. The n² samples lie on an "n-rooks" pattern (every sample has its own
x and its own y offset), so a nearly axis-aligned edge is resolved in steps of 1/n² px instead of
1/n. Then, as in research/calibration.md §2: reflectance × a linear illumination gradient,
Gaussian blur (the lens), Gaussian noise (the sensor), 8-bit.

Lens distortion costs nothing extra per supersample: the undistorted coordinates are computed
exactly (to 1e-9 px) at every pixel corner and interpolated bilinearly inside the pixel, where
the lens map is linear to ~1e-6 px.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, cast

import numpy as np
from numpy.typing import NDArray

from armtool.calib.model.camera import Array, CameraModel
from armtool.calib.targets.apriltag import tag_bits
from armtool.calib.targets.boards import board_size_m
from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    from armtool.calib.targets.boards import BoardSpec

_MIN_DEPTH_M = 1e-3
_EDGE_SAMPLES = 64  # points per plate edge for the in-view test and the bounding box
_ROUNDTRIP_TOL = 1e-6  # normalized units: a larger mismatch means the lens model folded over

Regions = Callable[[Array, Array, NDArray[np.bool_]], NDArray[np.intp]]  # plane x, y (m), ray hits → region ids


def plate_corners(size_m: float, family: str, margin_cells: int) -> Array:
    """Corners (4,3) of the white plate in the tag frame (TL, TR, BR, BL), `margin_cells` around the black square."""
    n_black = tag_bits(family, 0).shape[0]
    half = size_m / 2.0 + margin_cells * size_m / n_black
    return np.array([[-half, half, 0.0], [half, half, 0.0], [half, -half, 0.0], [-half, -half, 0.0]])


def _outline_px(camera: CameraModel, cMt: Array, corners: Array) -> Array | None:
    """Pixels (4·64, 2) along the outline through `corners` (4,3, target frame), or None if any of
    it is behind or within 1 mm of the camera plane, outside the image (pixel centres 0..W−1,
    0..H−1), or so far off-axis that the distortion polynomial folds back (the projected point
    does not undistort to its own ray)."""
    s = (np.arange(_EDGE_SAMPLES) / _EDGE_SAMPLES)[:, None]
    outline_t = np.concatenate([corners[i] + s * (corners[(i + 1) % 4] - corners[i]) for i in range(4)])
    outline_c = outline_t @ cMt[:3, :3].T + cMt[:3, 3]
    if np.any(outline_c[:, 2] < _MIN_DEPTH_M):
        return None
    px = camera.project(outline_c)
    if np.any(px < 0.0) or np.any(px[:, 0] > camera.width - 1) or np.any(px[:, 1] > camera.height - 1):
        return None
    if camera.has_distortion:
        back = camera.normalized(px)
        if np.max(np.abs(back - outline_c[:, :2] / outline_c[:, 2:])) > _ROUNDTRIP_TOL:
            return None
    return px


def plate_outline_px(camera: CameraModel, cMt: Array, size_m: float, family: str, margin_cells: int) -> Array | None:
    """Pixels (4·64, 2) along the plate's outline, or None if any of it is not properly in view
    (`_outline_px`) or the tag is seen from the back (the camera must be on the +z side of its face)."""
    if float(-cMt[:3, 2] @ cMt[:3, 3]) <= 0.0:  # z of the camera centre in the tag frame
        return None
    return _outline_px(camera, cMt, plate_corners(size_m, family, margin_cells))


def tag_in_view(
    camera: CameraModel, cMt: Array, size_m: float, family: str = "tag36h11", margin_cells: int = 2
) -> bool:
    """True when `render_tag` would draw this pose (the whole plate in the image, in front of the camera)."""
    return plate_outline_px(camera, np.asarray(cMt, dtype=np.float64), size_m, family, margin_cells) is not None


def _subsample_offsets(n: int) -> Array:
    """(n², 2) offsets in [0, 1) from a pixel's top-left corner: the n-rooks pattern of the module docstring."""
    ga, gb = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a, b = ga.reshape(-1), gb.reshape(-1)
    return np.stack([(n * a + b + 0.5) / n**2, (n * b + a + 0.5) / n**2], axis=1)


def _reflectance(
    camera: CameraModel,
    cMt: Array,
    regions: Regions,
    table: NDArray[np.float32],
    box: tuple[int, int, int, int],
    background: float,
    supersample: int,
) -> NDArray[np.float32]:
    """Reflectance (H, W) of the scene: the target's regions (`table[regions(...)]`) inside `box`
    = (x0, y0, x1, y1), pixels inclusive, `background` elsewhere."""
    R, t = cMt[:3, :3], cMt[:3, 3]
    origin_t = -R.T @ t  # camera centre in the target frame

    def region_ids(xy_norm: Array) -> NDArray[np.intp]:
        """Region id of the target-plane point hit by each ray (…, 2) of normalized camera coordinates."""
        x, y = xy_norm[..., 0], xy_norm[..., 1]
        dx = x * R[0, 0] + y * R[1, 0] + R[2, 0]  # Rᵀ (x, y, 1): the ray in the target frame
        dy = x * R[0, 1] + y * R[1, 1] + R[2, 1]
        dz = x * R[0, 2] + y * R[1, 2] + R[2, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = -origin_t[2] / dz
            px_t = origin_t[0] + lam * dx
            py_t = origin_t[1] + lam * dy
        hit = np.isfinite(lam) & (lam > 0)
        return regions(np.where(hit, px_t, 0.0), np.where(hit, py_t, 0.0), hit)

    x0, y0, x1, y1 = box
    bw, bh = x1 - x0 + 1, y1 - y0 + 1
    # Pixel corners of the box: pixel (r, c) spans lattice points (r..r+1, c..c+1).
    gx, gy = np.meshgrid(np.arange(x0, x1 + 2) - 0.5, np.arange(y0, y1 + 2) - 0.5)
    lattice = camera.normalized(np.stack([gx.reshape(-1), gy.reshape(-1)], axis=1)).reshape(bh + 1, bw + 1, 2)
    ids = region_ids(lattice)
    corner_id = ids[:-1, :-1]
    uniform = (corner_id == ids[:-1, 1:]) & (corner_id == ids[1:, :-1]) & (corner_id == ids[1:, 1:])
    patch = table[corner_id]

    rows, cols = np.nonzero(~uniform)
    if len(rows):
        fx, fy = _subsample_offsets(supersample).T
        weights = np.stack([(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy], axis=1)  # (S, 4)
        quad = np.stack(
            [lattice[rows, cols], lattice[rows, cols + 1], lattice[rows + 1, cols], lattice[rows + 1, cols + 1]], axis=1
        )
        xy = weights @ quad  # (M, S, 2): bilinear inside each pixel
        patch[rows, cols] = table[region_ids(xy)].mean(axis=1)

    reflect = np.full((camera.height, camera.width), background, dtype=np.float32)
    reflect[y0 : y1 + 1, x0 : x1 + 1] = patch
    return reflect


def _box(camera: CameraModel, outline: Array | None, blur_sigma_px: float) -> tuple[int, int, int, int]:
    """Pixels (x0, y0, x1, y1) to draw: around the target's outline, or the whole image when its
    outline is not wholly in view (a board partly outside the image)."""
    if outline is None:
        return 0, 0, camera.width - 1, camera.height - 1
    pad = int(np.ceil(4.0 * blur_sigma_px)) + 2
    x0 = max(int(np.floor(outline[:, 0].min())) - pad, 0)
    y0 = max(int(np.floor(outline[:, 1].min())) - pad, 0)
    x1 = min(int(np.ceil(outline[:, 0].max())) + pad, camera.width - 1)
    y1 = min(int(np.ceil(outline[:, 1].max())) + pad, camera.height - 1)
    return x0, y0, x1, y1


def _expose(
    reflect: NDArray[np.float32],
    *,
    blur_sigma_px: float,
    noise_sigma: float,
    gradient: float,
    rng: np.random.Generator,
) -> NDArray[np.uint8]:
    """The 8-bit image of a reflectance: × a linear illumination gradient (`gradient` peak to peak,
    in a random direction), Gaussian blur, Gaussian noise, rounded and saturated to 0..255."""
    import cv2

    height, width = reflect.shape
    theta = rng.uniform(0.0, 2.0 * np.pi)
    c, s = np.cos(theta), np.sin(theta)
    extent = abs(width * c) + abs(height * s)
    u = (np.arange(width, dtype=np.float32) - width / 2) * np.float32(gradient * c / extent)
    v = (np.arange(height, dtype=np.float32) - height / 2) * np.float32(gradient * s / extent)
    illumination = np.empty((height, width), dtype=np.float32)
    illumination[:] = u + np.float32(1.0)
    illumination += v[:, None]
    image = reflect * illumination
    if blur_sigma_px > 0:
        image = cast(
            "NDArray[np.float32]", cv2.GaussianBlur(image, (0, 0), blur_sigma_px, borderType=cv2.BORDER_REFLECT)
        )
    if noise_sigma > 0:
        # OpenCV's generator, seeded from rng: 3 ms per frame against numpy's 10 ms.
        cv2.setRNGSeed(int(rng.integers(2**31 - 1)))
        noise = np.empty_like(image)
        cv2.randn(noise, 0.0, float(noise_sigma))  # type: ignore[call-overload]  # scalars work; OpenCV's stubs want arrays
        image += noise
    np.maximum(image, 0.0, out=image)  # OpenCV's stubs type cv2.max's scalar operand differently by version
    return cast("NDArray[np.uint8]", cv2.convertScaleAbs(image, alpha=255.0))  # rounds and saturates to 0..255


def _check_render_args(cMt: Array, supersample: int) -> Array:
    if supersample < 1:
        raise ArmtoolError(f"supersample must be at least 1, got {supersample}")
    pose = np.asarray(cMt, dtype=np.float64)
    if pose.shape != (4, 4):
        raise ArmtoolError(f"the pose must be a 4x4 homogeneous matrix, got shape {pose.shape}")
    return pose


def render_tag(
    camera: CameraModel,
    cMt: Array,
    size_m: float,
    family: str,
    tag_id: int,
    *,
    blur_sigma_px: float = 1.0,
    noise_sigma: float = 3 / 255,
    black: float = 0.12,
    white: float = 0.8,
    gradient: float = 0.1,
    margin_cells: int = 2,
    rng: np.random.Generator | None = None,
    background: float = 0.35,
    supersample: int = 4,
) -> NDArray[np.uint8] | None:
    """8-bit grey image (H, W) of the tag seen by `camera` at pose `cMt` (tag in camera), or None.

    Returns None when the tag cannot be drawn whole: seen from the back, or any part of the white
    plate (the black square of edge `size_m` plus `margin_cells` cells of white around it)
    behind the camera or outside the image. Callers drawing random poses just draw again; `tag_in_view` asks first.

    Reflectances `black`, `white` and `background` (the scene behind the plate) are in [0, 1];
    the illumination varies linearly by `gradient` (fraction, peak to peak) across the image in a
    random direction; `blur_sigma_px` is a Gaussian blur, `noise_sigma` Gaussian noise in units
    of full scale. `rng` draws the gradient direction and the noise (default: seed 0).
    """
    if size_m <= 0:
        raise ArmtoolError(f"tag size must be positive, got {size_m} m")
    cMt = _check_render_args(cMt, supersample)
    rng = np.random.default_rng(0) if rng is None else rng
    bits = tag_bits(family, tag_id)
    outline = plate_outline_px(camera, cMt, size_m, family, margin_cells)
    if outline is None:
        return None

    # Reflectance per region id: the plate's cell grid, extended by one ring of "outside" cells
    # (8 convex regions of background), plus one id for rays that miss the plane.
    n_black = bits.shape[0]
    n_plate = n_black + 2 * margin_cells
    cell = size_m / n_black
    half_plate = n_plate * cell / 2.0
    side = n_plate + 2
    table = np.full(side * side + 1, background, dtype=np.float32)
    grid = np.full((n_plate, n_plate), white, dtype=np.float32)
    grid[margin_cells : margin_cells + n_black, margin_cells : margin_cells + n_black] = np.where(bits, white, black)
    table[: side * side].reshape(side, side)[1:-1, 1:-1] = grid
    miss_id = side * side

    def regions(x: Array, y: Array, hit: NDArray[np.bool_]) -> NDArray[np.intp]:
        ix = np.clip(np.floor((x + half_plate) / cell), -1, n_plate).astype(np.intp)
        iy = np.clip(np.floor((half_plate - y) / cell), -1, n_plate).astype(np.intp)
        return cast("NDArray[np.intp]", np.where(hit, (iy + 1) * side + (ix + 1), miss_id))

    reflect = _reflectance(camera, cMt, regions, table, _box(camera, outline, blur_sigma_px), background, supersample)
    return _expose(reflect, blur_sigma_px=blur_sigma_px, noise_sigma=noise_sigma, gradient=gradient, rng=rng)


class BoardTexture:
    """A board as regions of its plane: a grid of cells of pitch `pitch` (a chessboard square, or a
    tag and its gap), each with a base value and optionally a marker (its top-left corner and its
    (n+2)² cells), a white margin around the pattern, and the background (id 0) beyond."""

    def __init__(self, spec: BoardSpec, margin_m: float, black: float, white: float, background: float) -> None:
        import cv2

        from armtool.calib.targets.boards import BoardKind, cv_board

        squares = spec.kind is not BoardKind.APRILGRID  # chessboard and ChArUco: alternate squares
        self.pitch = spec.square_m if squares else spec.square_m + spec.marker_m
        self.cols, self.rows = spec.cols, spec.rows
        self.width_m, self.height_m = board_size_m(spec)
        self.margin = margin_m
        cells = self.cols * self.rows
        board = None if spec.kind is BoardKind.CHESSBOARD else cv_board(spec)
        self.n = int(board.getDictionary().markerSize) + 2 if board is not None else 1
        self.marker_m = spec.marker_m if spec.kind is BoardKind.CHARUCO else spec.square_m
        self.per_cell = 1 + self.n * self.n
        self.origin = np.full((cells, 2), np.nan)  # marker top-left per cell
        table = np.full(2 + cells * self.per_cell, white, dtype=np.float32)
        table[0] = background
        for i in range(cells):
            r, c = divmod(i, self.cols)
            table[2 + i * self.per_cell] = black if squares and (r + c) % 2 == 0 else white
        if board is not None:
            dictionary = board.getDictionary()
            for obj, marker_id in zip(board.getObjPoints(), np.asarray(board.getIds()).reshape(-1)):
                tl = np.asarray(obj, dtype=np.float64).reshape(4, 3)[0, :2]
                c, r = (int(np.floor((v + self.marker_m / 2) / self.pitch)) for v in tl)  # the cell holding its centre
                i = r * self.cols + c
                self.origin[i] = tl
                bits = cv2.aruco.generateImageMarker(dictionary, int(marker_id), self.n, borderBits=1) > 127
                table[2 + i * self.per_cell + 1 : 2 + (i + 1) * self.per_cell] = np.where(
                    bits.reshape(-1), white, black
                )
        self.table = table
        self.has_markers = board is not None

    def region(self, x: Array, y: Array, hit: NDArray[np.bool_]) -> NDArray[np.intp]:
        """Region id of board-plane points (metres, board frame); 0 (background) where the ray missed."""
        m = self.margin
        inside_board = hit & (x >= -m) & (x < self.width_m + m) & (y >= -m) & (y < self.height_m + m)
        inside_pattern = inside_board & (x >= 0) & (x < self.width_m) & (y >= 0) & (y < self.height_m)
        c = np.clip(np.floor(x / self.pitch), 0, self.cols - 1).astype(np.intp)
        r = np.clip(np.floor(y / self.pitch), 0, self.rows - 1).astype(np.intp)
        cell = r * self.cols + c
        ids = 2 + cell * self.per_cell
        if self.has_markers:
            origin = self.origin[cell]
            with np.errstate(invalid="ignore"):
                u = np.floor((x - origin[..., 0]) / self.marker_m * self.n)
                v = np.floor((y - origin[..., 1]) / self.marker_m * self.n)
                in_marker = (u >= 0) & (u < self.n) & (v >= 0) & (v < self.n)
            ids = ids + np.where(in_marker, 1 + np.nan_to_num(v) * self.n + np.nan_to_num(u), 0).astype(np.intp)
        # Outside the grid's cells but inside the pattern (AprilTag grid: the gaps) is white.
        in_cell = (x < (c + 1) * self.pitch) & (y < (r + 1) * self.pitch)
        ids = np.where(in_cell, ids, 1)
        return cast("NDArray[np.intp]", np.where(inside_pattern, ids, np.where(inside_board, 1, 0)))


def board_outline_m(spec: BoardSpec, margin_m: float) -> Array:
    """Corners (4,3) of the printed board including its margin, in the board frame."""
    w, h = board_size_m(spec)
    m = margin_m
    return np.array([[-m, -m, 0.0], [w + m, -m, 0.0], [w + m, h + m, 0.0], [-m, h + m, 0.0]])


def board_in_view(camera: CameraModel, cMb: Array, spec: BoardSpec, margin_m: float | None = None) -> bool:
    """True when the whole printed board (pattern and margin; default margin one square) is in the
    image and faces the camera (the board's z points into it: the camera is on its −z side)."""
    cMb = np.asarray(cMb, dtype=np.float64)
    if float(cMb[:3, 2] @ cMb[:3, 3]) <= 0.0:
        return False
    margin = spec.square_m if margin_m is None else margin_m
    return _outline_px(camera, cMb, board_outline_m(spec, margin)) is not None


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
    gradient: float = 0.0,
    supersample: int = 4,
    rng: np.random.Generator | None = None,
) -> NDArray[np.uint8]:
    """8-bit grey image (H, W) of the board at pose `cMb` (board frame in camera frame), with a
    white margin of `margin_m` (default one square) around its pattern. Unlike `render_tag` a board
    may be partly out of view (a partial ChArUco view); a board seen from the back shows its
    pattern as if printed on glass. Photometry as in `render_tag`."""
    cMb = _check_render_args(cMb, supersample)
    rng = np.random.default_rng(0) if rng is None else rng
    margin = spec.square_m if margin_m is None else margin_m
    texture = BoardTexture(spec, margin, black, white, background)
    outline = _outline_px(camera, cMb, board_outline_m(spec, margin))
    reflect = _reflectance(
        camera, cMb, texture.region, texture.table, _box(camera, outline, blur_sigma_px), background, supersample
    )
    return _expose(reflect, blur_sigma_px=blur_sigma_px, noise_sigma=noise_sigma, gradient=gradient, rng=rng)


def random_view_pose(
    camera: CameraModel,
    rng: np.random.Generator,
    *,
    distance_m: tuple[float, float] = (0.3, 1.0),
    max_tilt_deg: float = 60.0,
    central_fraction: float = 0.76,
) -> Array:
    """A random cMt as in research/calibration.md §2: the tag faces the camera, tilted 0..max_tilt
    about a random in-plane axis, spun at random about its normal, its centre at a random
    distance on the ray through a random pixel of the central part of the image.

    The whole plate is not guaranteed to be in view: check with `tag_in_view` and draw again.
    """
    spin = rng.uniform(-np.pi, np.pi)
    tilt = np.deg2rad(rng.uniform(0.0, max_tilt_deg))
    axis_angle = rng.uniform(0.0, 2.0 * np.pi)
    axis = np.array([np.cos(axis_angle), np.sin(axis_angle), 0.0])
    face_camera = np.diag([1.0, -1.0, -1.0])  # tag x right, y up, z towards the camera
    R = face_camera @ _rotvec(axis * tilt) @ _rotvec(np.array([0.0, 0.0, spin]))
    lo = (1.0 - central_fraction) / 2.0
    u = rng.uniform(lo, 1.0 - lo) * (camera.width - 1)
    v = rng.uniform(lo, 1.0 - lo) * (camera.height - 1)
    ray = np.append(camera.normalized(np.array([[u, v]]))[0], 1.0)
    cMt = np.eye(4)
    cMt[:3, :3] = R
    cMt[:3, 3] = ray / np.linalg.norm(ray) * rng.uniform(*distance_m)
    return cMt


def _rotvec(r: Array) -> Array:
    angle = float(np.linalg.norm(r))
    if angle < 1e-12:
        return np.eye(3)
    k = r / angle
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    R: Array = np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)
    return R
