"""Camera intrinsics from images of a calibration board: `armtool calibrate camera`.

Why here: the kinematic calibration is only as good as the camera model (a 0.3 % focal error
costs about 1.3 mm, research/calibration.md §3), and `dataset.yaml` needs an intrinsics file.
The fit is OpenCV's `calibrateCamera` on the board corners (`armtool.calib.targets.boards`); around it:
per-image reprojection RMS, the worst image dropped while it stands out (above
max(OUTLIER_MIN_PX, OUTLIER_FACTOR × the median image RMS)), then checks that say what the
images cannot pin down (board never near the image corners: distortion extrapolated there;
board never tilted: focal length poorly constrained). The result is written as OpenCV
FileStorage YAML, the format `armtool.calib.model.camera.load_intrinsics` reads.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from armtool.calib.choices import DistortionModel
from armtool.calib.limits import MAX_IMAGES
from armtool.calib.model.camera import Array, CameraModel
from armtool.calib.targets.boards import BoardSpec, BoardView, board_points, find_board
from armtool.errors import ArmtoolError

log = logging.getLogger(__name__)

MIN_IMAGES = 10  # OpenCV's tutorials ask for at least 10 views of the board
OUTLIER_FACTOR = 3.0
OUTLIER_MIN_PX = 0.5
COVERAGE_GRID = (5, 5)  # image cells (columns, rows) in which the board's corners are looked for
MIN_COVERAGE = 0.8
MIN_TILT_DEG = 20.0
_IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm", ".ppm")


@dataclass(frozen=True)
class ViewResult:
    """One image: how many board corners were found, its reprojection RMS, and whether it was used."""

    name: str
    points: int
    rms_px: float  # NaN when the board was not found
    used: bool
    reason: str = ""  # why not used
    tilt_deg: float = float("nan")  # angle between the board's normal and the optical axis


@dataclass(frozen=True)
class IntrinsicsResult:
    camera: CameraModel
    model: DistortionModel
    rms_px: float  # over every corner of the used images
    sigma: dict[str, float]  # 1-σ of fx, fy, cx, cy (px), from OpenCV's covariance
    views: list[ViewResult]
    coverage: float  # fraction of COVERAGE_GRID cells with a corner of a used image
    warnings: list[str] = field(default_factory=list)

    @property
    def used(self) -> list[ViewResult]:
        return [v for v in self.views if v.used]

    def summary(self, spec: BoardSpec, out: Path) -> dict[str, object]:
        """What `calibrate camera --format json` prints (`schema_version` 1)."""
        K = self.camera.K
        return {
            "schema_version": 1,
            "output": str(out),
            "board": spec.describe(),
            "image_width": self.camera.width,
            "image_height": self.camera.height,
            "fx_px": float(K[0, 0]),
            "fy_px": float(K[1, 1]),
            "cx_px": float(K[0, 2]),
            "cy_px": float(K[1, 2]),
            "sigma_px": self.sigma,
            "distortion_model": self.model.value,
            "distortion_coefficients": [float(d) for d in self.camera.dist],
            "rms_px": self.rms_px,
            "coverage": self.coverage,
            "images": [
                {
                    "image": v.name,
                    "points": v.points,
                    "rms_px": _finite(v.rms_px),
                    "tilt_deg": _finite(v.tilt_deg),
                    "used": v.used,
                    "reason": v.reason,
                }
                for v in self.views
            ],
            "warnings": self.warnings,
        }


def _finite(x: float) -> float | None:
    return None if math.isnan(x) else round(x, 4)


def image_paths(inputs: Sequence[Path]) -> list[Path]:
    """Image files from the command line: files as given, directories expanded (sorted), at most MAX_IMAGES."""
    out: list[Path] = []
    from armtool.calib.inputs.files import unreadable_reason

    for p in inputs:
        if p.is_dir():
            try:
                found = sorted(q for q in p.iterdir() if q.suffix.lower() in _IMAGE_SUFFIXES)
            except OSError as exc:
                raise ArmtoolError(
                    f"cannot list the image directory: {exc.strerror or exc}", str(p), "check its permissions"
                ) from None
            out.extend(q for q in found if unreadable_reason(q) is None)  # skip sub-directories, FIFOs named *.png
        elif (why := unreadable_reason(p)) is None:
            out.append(p)
        else:
            raise ArmtoolError(f"image {why}", str(p), "pass image files or a directory of images")
    if not out and any(p.is_dir() for p in inputs):
        raise ArmtoolError(
            "no readable image files in the director" + ("ies" if len(inputs) > 1 else "y"),
            ", ".join(str(p) for p in inputs),
            f"images end in {', '.join(_IMAGE_SUFFIXES)}",
        )
    if not out:
        raise ArmtoolError(
            "no images given", ", ".join(str(p) for p in inputs), f"images end in {', '.join(_IMAGE_SUFFIXES)}"
        )
    if len(out) > MAX_IMAGES:
        raise ArmtoolError(
            f"{len(out)} images given, at most {MAX_IMAGES} are read",
            hint="pass a subset: 15-40 well-spread views are enough",
        )
    return out


def find_boards(
    paths: Sequence[Path], spec: BoardSpec, progress: Callable[[int, int], None] | None = None
) -> tuple[list[tuple[str, BoardView]], tuple[int, int]]:
    """The board's corners in every image, and the common image size (width, height)."""

    from armtool.calib.inputs.files import read_gray

    views: list[tuple[str, BoardView]] = []
    size: tuple[int, int] | None = None
    for k, path in enumerate(paths):
        gray = read_gray(path)
        if gray is None:
            raise ArmtoolError("cannot read image", str(path), "is it a PNG/JPEG image?")
        here = (int(gray.shape[1]), int(gray.shape[0]))
        if size is None:
            size = here
        elif here != size:
            raise ArmtoolError(
                f"image is {here[0]}x{here[1]} but {paths[0].name} is {size[0]}x{size[1]}",
                str(path),
                "intrinsics hold for one image size: calibrate each resolution separately",
            )
        views.append((str(path), find_board(gray, spec)))
        if progress is not None:
            progress(k + 1, len(paths))
    assert size is not None
    return views, size


def _flags(model: DistortionModel) -> int:
    import cv2

    return {
        DistortionModel.NONE: cv2.CALIB_FIX_K1 | cv2.CALIB_FIX_K2 | cv2.CALIB_FIX_K3 | cv2.CALIB_ZERO_TANGENT_DIST,
        DistortionModel.K1K2: cv2.CALIB_FIX_K3,
        DistortionModel.PLUMB_BOB: 0,
        DistortionModel.RATIONAL: cv2.CALIB_RATIONAL_MODEL,
    }[model]


@dataclass
class _Fit:
    K: Array
    dist: Array
    rms_per_view: Array
    tilts_deg: Array
    sigma: Array


def _fit(obj: list[Array], img: list[Array], size: tuple[int, int], model: DistortionModel) -> _Fit:
    import cv2

    criteria = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 200, 1e-12)
    try:
        _, K, dist, rvecs, tvecs, std_intr, _, _ = cv2.calibrateCameraExtended(  # type: ignore[call-overload]  # None K/dist: OpenCV starts from its own guess
            [o.astype(np.float32) for o in obj],
            [i.astype(np.float32) for i in img],
            size,
            None,
            None,
            flags=_flags(model),
            criteria=criteria,
        )
    except cv2.error as exc:
        raise ArmtoolError(
            f"OpenCV could not calibrate from these images: {str(exc).strip().splitlines()[-1]}",
            hint="use more images with the board tilted in different directions",
        ) from None
    K = np.asarray(K, dtype=np.float64)
    dist = np.asarray(dist, dtype=np.float64).reshape(-1)
    dist = dist[:8] if model is DistortionModel.RATIONAL else dist[:5]
    rms, tilts = [], []
    for o, i, r, t in zip(obj, img, rvecs, tvecs):
        proj, _ = cv2.projectPoints(o, r, t, K, dist)
        rms.append(float(np.sqrt(np.mean(np.sum((proj.reshape(-1, 2) - i) ** 2, axis=1)))))
        R = cv2.Rodrigues(np.asarray(r, dtype=np.float64))[0]
        tilts.append(float(np.degrees(np.arccos(np.clip(abs(R[2, 2]), 0.0, 1.0)))))
    return _Fit(K, dist, np.array(rms), np.array(tilts), np.asarray(std_intr, dtype=np.float64).reshape(-1)[:4])


def calibrate_views(
    views: Sequence[tuple[str, BoardView]],
    spec: BoardSpec,
    image_size: tuple[int, int],
    model: DistortionModel = DistortionModel.PLUMB_BOB,
    min_images: int = MIN_IMAGES,
) -> IntrinsicsResult:
    """Fit intrinsics from board views (name, corners); drop outlying images; judge coverage.

    Raises ArmtoolError when fewer than `min_images` images show the board.
    """
    points = board_points(spec)
    usable = [(name, v) for name, v in views if not v.reason]
    if len(usable) < min_images:
        missing = [f"{Path(name).name}: {v.reason}" for name, v in views if v.reason][:5]
        raise ArmtoolError(
            f"the board was found in {len(usable)} of {len(views)} images; at least {min_images} are needed"
            + "".join(f"\n  {m}" for m in missing),
            hint=f"take {min_images}-30 images of the whole board, tilted 20-45° in different directions and "
            "reaching every part of the image; check --board (type, size, dictionary)",
        )
    obj = {name: points[v.ids] for name, v in usable}
    img = {name: v.pixels for name, v in usable}
    used = [name for name, _ in usable]
    rejected: dict[str, str] = {}
    while True:
        fit = _fit([obj[n] for n in used], [img[n] for n in used], image_size, model)
        median = float(np.median(fit.rms_per_view))
        limit = max(OUTLIER_MIN_PX, OUTLIER_FACTOR * median)
        worst = int(np.argmax(fit.rms_per_view))
        if fit.rms_per_view[worst] <= limit or len(used) <= min_images:
            break
        name = used.pop(worst)
        rejected[name] = (
            f"outlier: reprojection RMS {fit.rms_per_view[worst]:.2f} px, more than max({OUTLIER_MIN_PX} px, {OUTLIER_FACTOR:g} × median {median:.2f} px)"
        )
        log.info("%s rejected: %s", name, rejected[name])

    rms_of = dict(zip(used, fit.rms_per_view))
    tilt_of = dict(zip(used, fit.tilts_deg))
    camera = CameraModel(fit.K, fit.dist, image_size[0], image_size[1])
    results: list[ViewResult] = []
    for name, v in views:
        if v.reason:
            results.append(ViewResult(name, len(v.ids), float("nan"), False, v.reason))
        elif name in rejected:
            results.append(ViewResult(name, len(v.ids), _view_rms(camera, obj[name], img[name]), False, rejected[name]))
        else:
            results.append(ViewResult(name, len(v.ids), float(rms_of[name]), True, tilt_deg=float(tilt_of[name])))
    counts = np.array([len(obj[n]) for n in used])
    rms = float(np.sqrt(np.sum(fit.rms_per_view**2 * counts) / np.sum(counts)))
    coverage, empty_corners = _coverage(np.concatenate([img[n] for n in used]), image_size)
    warnings = []
    if coverage < MIN_COVERAGE or empty_corners:
        where = (
            f"; never near the image's {', '.join(empty_corners)} corner(s), where distortion is largest"
            if empty_corners
            else ""
        )
        warnings.append(
            f"poor coverage: the board's corners reach {coverage:.0%} of a {COVERAGE_GRID[0]}x{COVERAGE_GRID[1]} grid over the image{where}. "
            "Distortion is extrapolated where the board never was: add images with the board there"
        )
    if float(np.max(fit.tilts_deg)) < MIN_TILT_DEG:
        warnings.append(
            f"the board is never tilted more than {float(np.max(fit.tilts_deg)):.0f}° from facing the camera: "
            f"the focal length is poorly constrained; add images tilted {MIN_TILT_DEG:.0f}-45° in different directions"
        )
    if len(used) < len(usable) and len(used) <= min_images:
        log.info("stopped rejecting outliers at the minimum of %d images", min_images)
    sigma = dict(zip(("fx", "fy", "cx", "cy"), (float(s) for s in fit.sigma)))
    return IntrinsicsResult(camera, model, rms, sigma, results, coverage, warnings)


def _residuals(camera: CameraModel, obj: Array, img: Array) -> Array:
    """Reprojection residuals of one view at its own best pose (PnP) with the fitted camera."""
    import cv2

    ok, r, t = cv2.solvePnP(obj, img, camera.K, camera.dist, flags=cv2.SOLVEPNP_ITERATIVE)
    if not ok:
        return np.full_like(img, np.nan)
    proj, _ = cv2.projectPoints(obj, r, t, camera.K, camera.dist)
    return np.asarray(proj, dtype=np.float64).reshape(-1, 2) - img


def _view_rms(camera: CameraModel, obj: Array, img: Array) -> float:
    res = _residuals(camera, obj, img)
    return float(np.sqrt(np.mean(np.sum(res**2, axis=1))))


def _coverage(pixels: Array, size: tuple[int, int]) -> tuple[float, list[str]]:
    """Fraction of grid cells holding a corner, and which of the four image-corner cells are empty."""
    cols, rows = COVERAGE_GRID
    cx = np.clip((pixels[:, 0] / size[0] * cols).astype(int), 0, cols - 1)
    cy = np.clip((pixels[:, 1] / size[1] * rows).astype(int), 0, rows - 1)
    hit = np.zeros((rows, cols), dtype=bool)
    hit[cy, cx] = True
    corners = {
        "top-left": (0, 0),
        "top-right": (0, cols - 1),
        "bottom-left": (rows - 1, 0),
        "bottom-right": (rows - 1, cols - 1),
    }
    return float(hit.mean()), [name for name, rc in corners.items() if not hit[rc]]


def calibrate_images(
    paths: Sequence[Path],
    spec: BoardSpec,
    model: DistortionModel = DistortionModel.PLUMB_BOB,
    min_images: int = MIN_IMAGES,
    progress: Callable[[int, int], None] | None = None,
) -> IntrinsicsResult:
    """`calibrate_views` on images read from files."""
    views, size = find_boards(paths, spec, progress)
    return calibrate_views(views, spec, size, model, min_images)


def intrinsics_yaml(result: IntrinsicsResult, spec: BoardSpec) -> str:
    """OpenCV FileStorage YAML: image_width, image_height, camera_matrix, distortion_coefficients
    (the keys `load_intrinsics` and `cv2.FileStorage` read), plus how it was obtained."""
    import cv2

    cam = result.camera
    fs = cv2.FileStorage("camera.yaml", cv2.FILE_STORAGE_WRITE | cv2.FILE_STORAGE_MEMORY | cv2.FILE_STORAGE_FORMAT_YAML)
    fs.writeComment(f"armtool calibrate camera: {spec.describe()}")
    fs.write("image_width", cam.width)
    fs.write("image_height", cam.height)
    fs.write("camera_matrix", np.array(cam.K))
    fs.write("distortion_model", "rational_polynomial" if result.model is DistortionModel.RATIONAL else "plumb_bob")
    fs.write("distortion_coefficients", np.array(cam.dist).reshape(1, -1))
    fs.write("avg_reprojection_error", result.rms_px)
    fs.write("nr_of_frames", len(result.used))
    return str(fs.releaseAndGetString())


def write_intrinsics(result: IntrinsicsResult, spec: BoardSpec, path: Path) -> None:
    """Write `intrinsics_yaml` atomically, after checking that `load_intrinsics` reads it back."""
    import tempfile

    from armtool.calib.model.camera import load_intrinsics
    from armtool.fileio import write_atomic

    text = intrinsics_yaml(result, spec)
    with tempfile.TemporaryDirectory() as tmp:
        probe = Path(tmp) / "camera.yaml"
        probe.write_text(text, encoding="utf-8")
        back = load_intrinsics(probe)
    if not (
        np.allclose(back.K, result.camera.K, rtol=1e-12, atol=1e-9)
        and np.allclose(back.dist, result.camera.dist, atol=1e-12)
    ):
        raise ArmtoolError("internal error: the intrinsics file does not read back as written", str(path))
    write_atomic(path, text)
