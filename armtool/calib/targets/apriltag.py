"""AprilTag detection for calibration: OpenCV's aruco AprilTag dictionaries, corners to ~0.07 px.

Why this detector (research/calibration.md §2, measured on rendered images with known truth):
`CORNER_REFINE_APRILTAG` fits lines to the tag's edges and gives 0.07–0.19 px median corner
error, where `NONE` (0.7 px) and `SUBPIX` (0.2–0.7 px) are biased inwards by blur, so the tag
looks smaller and further away (mm of depth error). On the whole image it is slow (242 ms CPU
per 1280×720 frame in research, 500 ms here), so the marker is found with `CORNER_REFINE_NONE`
and the AprilTag refinement runs on a crop around it only (15–29 ms CPU per frame in all, 0.064 px
median corner error on 90 typical images). AprilTag puts pixel centres at 0.5: its corners are
shifted by +0.5 px in x and y, which is subtracted here (AprilRobotics/apriltag #121).
pupil-apriltags is as accurate but segfaulted in long runs, so it is not used.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from armtool.calib.model.camera import Array, CameraModel
from armtool.errors import ArmtoolError

# AprilTag family name → cv2.aruco predefined dictionary constant.
FAMILIES = {
    "tag36h11": "DICT_APRILTAG_36h11",
    "tag25h9": "DICT_APRILTAG_25h9",
    "tag16h5": "DICT_APRILTAG_16h5",
    "tag36h10": "DICT_APRILTAG_36h10",
}


def tag_object_points(size_m: float) -> Array:
    """Corners (4,3) of the black square of edge `size_m` in the tag frame, in cv2.aruco's order.

    Tag frame (OpenCV aruco): origin at the centre, x right, y up, z out of the face. Order
    TL, TR, BR, BL as `detectMarkers` returns them (what SOLVEPNP_IPPE_SQUARE expects).
    """
    h = size_m / 2.0
    return np.array([[-h, h, 0.0], [h, h, 0.0], [h, -h, 0.0], [-h, -h, 0.0]])


@cache
def family_dictionary(family: str) -> Any:
    """The cv2.aruco.Dictionary of an AprilTag family (tag36h11, tag25h9, tag16h5, tag36h10)."""
    import cv2

    if family not in FAMILIES:
        raise ArmtoolError(
            f"unknown AprilTag family '{family}'",
            hint=f"valid families: {', '.join(FAMILIES)}",
        )
    return cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, FAMILIES[family]))


def family_size(family: str) -> int:
    """Number of ids in a family (valid ids are 0 .. size−1)."""
    return int(family_dictionary(family).bytesList.shape[0])


def tag_bits(family: str, tag_id: int) -> NDArray[np.bool_]:
    """Cells of the black square, (n+2, n+2) booleans, True = white; row 0 at the top (tag +y), column 0 at the left (tag −x)."""
    import cv2

    n_ids = family_size(family)
    if not 0 <= int(tag_id) < n_ids:
        raise ArmtoolError(f"tag id {tag_id} is not in {family}", hint=f"valid ids: 0..{n_ids - 1}")
    dictionary = family_dictionary(family)
    cells = dictionary.markerSize + 2
    image = cv2.aruco.generateImageMarker(dictionary, int(tag_id), cells, borderBits=1)
    return np.asarray(image > 127)


# Detection thresholds (keyword arguments of detect_tag); see docs/calibrate.md for how they were chosen.
MIN_SIDE_PX = 20.0
MIN_SHARPNESS = 0.12
_ROI_PAD_FRACTION = 0.25  # of the tag side, around the rough corners
_ROI_PAD_MIN_PX = 12
_MAX_REFINE_SHIFT_FRACTION = 0.1  # refined corners may move this much of the side from the rough ones
_MIN_CONTRAST = 8.0  # grey levels between the black border and the white around it


@dataclass(frozen=True, eq=False)
class TagDetection:
    """One tag in one image. `corners_px` (4,2): TL, TR, BR, BL in OpenCV pixel convention
    (pixel centres at integers), corrected for AprilTag's +0.5 px; NaN when not found.

    `ok` False means: do not use these corners; `reason` says why. `side_px` is the mean edge
    length; `sharpness` the steepest slope across the tag's outer edges divided by the
    black-to-white step, in 1/px (min over the four edges): 1/(σ·√(2π)) for an edge blurred
    by a Gaussian of σ px, ≈ 0.4 for σ = 1.
    """

    tag_id: int
    corners_px: Array
    ok: bool
    reason: str
    side_px: float
    sharpness: float

    @property
    def blur_px(self) -> float:
        """The Gaussian σ (px) that would give this sharpness."""
        return float(1.0 / (self.sharpness * np.sqrt(2.0 * np.pi))) if self.sharpness > 0 else float("inf")


def _not_found(tag_id: int, reason: str) -> TagDetection:
    return TagDetection(tag_id, np.full((4, 2), np.nan), False, reason, float("nan"), float("nan"))


@cache
def _detector(family: str, refine: str) -> Any:
    import cv2

    params = cv2.aruco.DetectorParameters()
    params.cornerRefinementMethod = {
        "none": cv2.aruco.CORNER_REFINE_NONE,
        "apriltag": cv2.aruco.CORNER_REFINE_APRILTAG,
    }[refine]
    return cv2.aruco.ArucoDetector(family_dictionary(family), params)


def _detect(gray: NDArray[np.uint8], family: str, refine: str) -> tuple[list[Array], list[int]]:
    corners, ids, _ = _detector(family, refine).detectMarkers(gray)
    if ids is None:
        return [], []
    return [np.asarray(c, dtype=np.float64).reshape(4, 2) for c in corners], [int(i) for i in ids.reshape(-1)]


def _as_gray(image: NDArray[Any]) -> NDArray[np.uint8]:
    import cv2

    img = np.asarray(image)
    if img.ndim == 3 and img.shape[2] in (3, 4):
        img = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY if img.shape[2] == 3 else cv2.COLOR_BGRA2GRAY)
    if img.ndim != 2:
        raise ArmtoolError(f"expected a grey or BGR image, got an array of shape {img.shape}")
    if img.dtype != np.uint8:
        if img.dtype == np.uint16:
            img = (img / 257.0 + 0.5).astype(np.uint8)
        else:
            raise ArmtoolError(f"expected an 8-bit image, got {img.dtype}")
    return np.ascontiguousarray(img)


def _find_rough(gray: NDArray[np.uint8], family: str, tag_id: int) -> tuple[list[Array], set[int]]:
    """Rough corners of every detection of tag_id, and all ids seen.

    Passes, cheapest first, stopping at the first that sees tag_id: CORNER_REFINE_NONE on the
    image (~8 ms), then on the image at half size (large low-contrast tags escape the adaptive
    threshold's window at full size), then the AprilTag quad detector at half size (~30 ms; it
    finds strongly tilted or blurred tags the others miss). On 300 rendered images (typical and
    poor quality, 50 and 80 mm tags at 0.25-1.2 m) the passes found 291, 1 and 4; the AprilTag
    detector on the full image (~500 ms) found no more than at half size.
    """
    import cv2

    seen: set[int] = set()
    small: NDArray[np.uint8] | None = None
    for scale, refine in ((1, "none"), (2, "none"), (2, "apriltag")):
        if scale == 2 and small is None:
            small = cast("NDArray[np.uint8]", cv2.pyrDown(gray))
        image = gray if small is None or scale == 1 else small
        corners, ids = _detect(image, family, refine)
        seen.update(ids)
        hits = [c * scale for c, i in zip(corners, ids) if i == tag_id]
        if hits:
            return hits, seen
    return [], seen


def _side_px(corners: Array) -> float:
    return float(np.mean(np.linalg.norm(corners - np.roll(corners, 1, axis=0), axis=1)))


def _crop_box(corners: Array, pad_fraction: float, limit: tuple[int, int] | None) -> tuple[int, int, int, int]:
    """Integer box [x0, x1) × [y0, y1) around `corners`, padded, clipped to `limit` = (w, h) if given."""
    pad = max(_ROI_PAD_MIN_PX, pad_fraction * _side_px(corners))
    x0, y0 = np.floor(corners.min(axis=0) - pad).astype(int)
    x1, y1 = np.ceil(corners.max(axis=0) + pad).astype(int) + 1
    if limit is not None:
        x0, y0 = max(0, x0), max(0, y0)
        x1, y1 = min(limit[0], x1), min(limit[1], y1)
    return int(x0), int(y0), int(x1), int(y1)


def _refine(
    gray: NDArray[np.uint8], family: str, tag_id: int, rough: Array, camera: CameraModel | None
) -> tuple[Array | None, int]:
    """AprilTag corners (OpenCV convention, raw pixels) from a crop around `rough`; None if not found there.

    With a distorting lens the crop is first undistorted (resampled through the lens model with
    the same K), so the AprilTag line fits see straight edges; the corners are then distorted
    back. Measured on 60 rendered images with k1..k3 = (0.1, −0.25, 0.1): median corner error
    0.066 px instead of 0.079, p90 0.13 instead of 0.18, for +12 ms.
    """
    import cv2

    h, w = gray.shape
    undistort = camera is not None and camera.has_distortion
    for pad_fraction in (_ROI_PAD_FRACTION, 2 * _ROI_PAD_FRACTION):
        if undistort:
            assert camera is not None
            K = camera.K
            ideal = camera.normalized(rough) @ K[:2, :2].T + K[:2, 2]
            x0, y0, x1, y1 = _crop_box(ideal, pad_fraction, None)
            gx, gy = np.meshgrid(np.arange(x0, x1, dtype=np.float64), np.arange(y0, y1, dtype=np.float64))
            yn = (gy - K[1, 2]) / K[1, 1]
            xn = (gx - K[0, 2] - K[0, 1] * yn) / K[0, 0]
            rays = np.stack([xn.reshape(-1), yn.reshape(-1), np.ones(xn.size)], axis=1)
            source = camera.project(rays).reshape(gx.shape + (2,)).astype(np.float32)
            crop = cast(
                "NDArray[np.uint8]",
                cv2.remap(gray, source[..., 0], source[..., 1], cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE),
            )
        else:
            x0, y0, x1, y1 = _crop_box(rough, pad_fraction, (w, h))
            crop = np.ascontiguousarray(gray[y0:y1, x0:x1])
        corners, ids = _detect(crop, family, "apriltag")
        hits = [c for c, i in zip(corners, ids) if i == tag_id]
        if hits:
            # AprilTag's pixel centres are at +0.5: back to OpenCV's integer centres.
            found = hits[0] + np.array([x0 - 0.5, y0 - 0.5])
            if undistort:
                assert camera is not None
                yn = (found[:, 1] - camera.K[1, 2]) / camera.K[1, 1]
                xn = (found[:, 0] - camera.K[0, 2] - camera.K[0, 1] * yn) / camera.K[0, 0]
                found = camera.project(np.stack([xn, yn, np.ones(4)], axis=1))
            return found, len(hits)
    return None, 0


def edge_sharpness(gray: NDArray[np.uint8], corners: Array, cells: int) -> tuple[float, float]:
    """(sharpness, contrast) of the tag's outer edges: the min over the four edges of each.

    Sharpness: the steepest slope across an edge over its black-to-white step, in 1/px. For each
    edge, intensity profiles along the outward normal are sampled (bilinear) at points from 20 %
    to 80 % of its length and averaged; the profile spans ±0.9 cell measured across that edge
    (the black border band on one side, the white quiet zone on the other). A step blurred by a
    Gaussian of σ px gives 1/(σ·√(2π)). Contrast: the step in grey levels.
    """
    import cv2

    offsets_unit = np.arange(-1.0, 1.0 + 1e-9, 1.0 / 32.0)
    centre = corners.mean(axis=0)
    sharpness, contrast_min = np.inf, np.inf
    for i in range(4):
        p0, p1 = corners[i], corners[(i + 1) % 4]
        length = float(np.linalg.norm(p1 - p0))
        along = (p1 - p0) / length
        normal = np.array([-along[1], along[0]])
        if normal @ ((p0 + p1) / 2 - centre) < 0:
            normal = -normal
        # The tag's extent across this edge: distance of the two other corners from its line.
        across = float(np.min(np.abs((corners[[(i + 2) % 4, (i + 3) % 4]] - p0) @ normal)))
        half_width = max(1.5, 0.9 * across / cells)
        offsets = offsets_unit * half_width
        s = np.linspace(0.2, 0.8, int(np.clip(length / 2, 8, 64)))
        points = p0 + s[:, None] * (p1 - p0)
        samples = points[:, None, :] + offsets[None, :, None] * normal
        values = cv2.remap(
            gray,
            samples[..., 0].astype(np.float32),
            samples[..., 1].astype(np.float32),
            cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_REPLICATE,
        )
        profile = values.astype(np.float64).mean(axis=0)
        n_plateau = len(offsets) // 8
        contrast = float(profile[-n_plateau:].mean() - profile[:n_plateau].mean())
        step = max(1, int(round(1.0 / (offsets[1] - offsets[0]))))  # samples per px
        slope = (profile[step:] - profile[:-step]) / (offsets[step] - offsets[0])
        contrast_min = min(contrast_min, contrast)
        sharpness = min(sharpness, float(slope.max() / contrast) if contrast > 0 else 0.0)
    return sharpness, contrast_min


def detect_tag(
    gray: NDArray[Any],
    family: str,
    tag_id: int,
    camera: CameraModel | None = None,
    *,
    min_side_px: float = MIN_SIDE_PX,
    min_sharpness: float = MIN_SHARPNESS,
) -> TagDetection:
    """Find tag `tag_id` of `family` in an 8-bit image and return its corners to ~0.07 px.

    Rejected (ok False, corners still filled when known): not found, found twice, smaller than
    `min_side_px`, or blurred (sharpness below `min_sharpness`, see TagDetection), or an image
    whose size differs from the camera's. With a `camera` that has lens distortion the
    refinement runs on an undistorted crop (see `_refine`); corners are always raw pixels of
    the given image.
    """
    family_dictionary(family)
    image = _as_gray(gray)
    if camera is not None and image.shape != (camera.height, camera.width):
        return _not_found(
            tag_id,
            f"image is {image.shape[1]}x{image.shape[0]} but the intrinsics are for {camera.width}x{camera.height}",
        )
    rough_hits, seen = _find_rough(image, family, tag_id)
    if not rough_hits:
        found = ", ".join(str(i) for i in sorted(seen)) if seen else "none"
        return _not_found(tag_id, f"tag {tag_id} not found (found ids: {found})")
    if len(rough_hits) > 1:
        return _not_found(tag_id, f"ambiguous: {len(rough_hits)} detections of id {tag_id}")
    rough = rough_hits[0]
    corners, count = _refine(image, family, tag_id, rough, camera)
    cells = int(family_dictionary(family).markerSize) + 2
    if corners is None:
        # Say why if we can: blur and low contrast are the usual causes, measured on the rough corners.
        side = _side_px(rough)
        sharpness, contrast = edge_sharpness(image, rough, cells)
        reason = _quality_reason(side, sharpness, contrast, min_side_px, min_sharpness) or (
            f"corner refinement failed: the AprilTag edge fit does not find the tag ({side:.0f} px side; "
            "usually too small or too tilted)"
        )
        return TagDetection(tag_id, rough, False, reason, side, sharpness)
    if count > 1:
        return _not_found(tag_id, f"ambiguous: {count} detections of id {tag_id}")
    side = _side_px(corners)
    shift = float(np.max(np.linalg.norm(corners - rough, axis=1)))
    sharpness, contrast = edge_sharpness(image, corners, cells)
    reason = _quality_reason(side, sharpness, contrast, min_side_px, min_sharpness)
    if shift > max(3.0, _MAX_REFINE_SHIFT_FRACTION * side):
        reason = f"corner refinement moved a corner by {shift:.1f} px from the detection"
    return TagDetection(tag_id, corners, not reason, reason, side, sharpness)


def _quality_reason(side: float, sharpness: float, contrast: float, min_side_px: float, min_sharpness: float) -> str:
    """Why a found tag's corners should not be trusted, or "" if they can."""
    if side < min_side_px:
        return f"too small: {side:.0f} px side (minimum {min_side_px:.0f})"
    if contrast < _MIN_CONTRAST:
        return (
            f"low contrast: the tag's black-to-white step is {contrast:.0f} grey levels (minimum {_MIN_CONTRAST:.0f})"
        )
    if sharpness < min_sharpness:
        blur = 1.0 / sharpness / np.sqrt(2 * np.pi) if sharpness > 0 else float("inf")
        return (
            f"blurred: edge sharpness {sharpness:.3f} below {min_sharpness:.3f} (an edge blur of about {blur:.1f} px)"
        )
    return ""


def pnp_pose(corners_px: Array, size_m: float, camera: CameraModel) -> tuple[Array, float, bool]:
    """Pose cMt of a square tag from its 4 corners (TL, TR, BR, BL, raw pixels): SOLVEPNP_IPPE_SQUARE.

    Returns (cMt, reprojection RMS in px over the 4 corners, ambiguous). IPPE gives two poses
    for a planar square (a tilt one way or the other); `ambiguous` is True when the second
    reprojects almost as well as the first (`targets.pose`'s AMBIGUITY_RATIO and AMBIGUITY_MIN_PX), i.e.
    the corners cannot tell them apart: near-fronto-parallel views of small tags. Such a pose
    should not initialise anything on its own (research §2: the 2–9° p99 rotation tail).
    """
    from armtool.calib.targets.pose import planar_pose

    corners = np.asarray(corners_px, dtype=np.float64).reshape(4, 2)
    if not np.all(np.isfinite(corners)):
        raise ArmtoolError("tag corners contain NaN (tag not detected)")
    cMt, rms, ambiguous = planar_pose(tag_object_points(size_m), corners, camera, square=True)
    if not np.isfinite(rms):
        raise ArmtoolError("solvePnP found no pose for these tag corners")
    return cMt, rms, ambiguous
