"""The pinhole camera with OpenCV lens distortion, and its intrinsics files.

Two file formats are read, because those are what users have: OpenCV FileStorage (yaml/xml from
`cv2.FileStorage`, the output of `cv2.calibrateCamera` samples: `camera_matrix`,
`distortion_coefficients`, `image_width`, `image_height`) and ROS `camera_calibration`'s
camera_info yaml (`camera_matrix.data`, `distortion_coefficients.data`, `distortion_model`).
Common spellings (`K`/`D`, `cameraMatrix`/`distCoeffs`, `width`/`height`) are accepted too.

Pixel convention everywhere: OpenCV's, the centre of pixel (0, 0) is at (0.0, 0.0).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armtool.errors import ArmtoolError

Array = NDArray[np.float64]

# Lengths cv2 accepts: (k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4 [τx τy]]]]).
_DIST_LENGTHS = (0, 4, 5, 8, 12, 14)
_K_KEYS = ("camera_matrix", "cameraMatrix", "K", "k", "intrinsic_matrix", "intrinsics")
_DIST_KEYS = (
    "distortion_coefficients",
    "dist_coeffs",
    "distCoeffs",
    "dist_coeff",
    "distortion_coeffs",
    "D",
    "d",
)
_WIDTH_KEYS = ("image_width", "width", "imageWidth")
_HEIGHT_KEYS = ("image_height", "height", "imageHeight")
_SIZE_KEYS = ("image_size", "imageSize", "size")  # [width, height]
# ROS distortion models whose coefficients are in OpenCV's order already.
_ROS_MODELS = {"plumb_bob": (5,), "rational_polynomial": (8,)}
_UNDISTORT_ITERATIONS = 100
_UNDISTORT_EPS_PX = 1e-9


@dataclass(frozen=True, eq=False)
class CameraModel:
    """Pinhole intrinsics K (3×3), OpenCV distortion `dist` (0, 4, 5, 8, 12 or 14 values), image size.

    Arrays are float64 and read-only. `eq=False`: cameras compare by identity (arrays have no
    single truth value); use `np.allclose` on the fields to compare values.
    """

    K: Array
    dist: Array
    width: int
    height: int

    def __post_init__(self) -> None:
        K = np.array(self.K, dtype=np.float64)
        dist = np.array(self.dist, dtype=np.float64).reshape(-1)
        if K.shape != (3, 3) or not np.all(np.isfinite(K)):
            raise ArmtoolError(f"camera matrix must be a finite 3x3 matrix, got shape {K.shape}")
        if K[0, 0] <= 0 or K[1, 1] <= 0 or not np.allclose(K[2], [0.0, 0.0, 1.0]) or K[1, 0] != 0:
            raise ArmtoolError(
                "camera matrix is not [[fx, s, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0",
                hint="the matrix is stored row by row (9 values)",
            )
        if dist.size not in _DIST_LENGTHS or not np.all(np.isfinite(dist)):
            raise ArmtoolError(
                f"distortion coefficients must be 0, 4, 5, 8, 12 or 14 finite values, got {dist.size}",
                hint="OpenCV order: k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4 [tx ty]]]]",
            )
        if int(self.width) <= 0 or int(self.height) <= 0:
            raise ArmtoolError(f"image size must be positive, got {self.width}x{self.height}")
        K.flags.writeable = False
        dist.flags.writeable = False
        object.__setattr__(self, "K", K)
        object.__setattr__(self, "dist", dist)
        object.__setattr__(self, "width", int(self.width))
        object.__setattr__(self, "height", int(self.height))

    @property
    def has_distortion(self) -> bool:
        return bool(np.any(self.dist != 0.0))

    def project(self, points_c: Array) -> Array:
        """Pixels (N,2) of camera-frame points (N,3), with distortion (cv2.projectPoints).

        Points at or behind the camera plane (z <= 0) give NaN.
        """
        import cv2

        pts = np.asarray(points_c, dtype=np.float64).reshape(-1, 3)
        out = np.full((len(pts), 2), np.nan)
        front = pts[:, 2] > 0
        if np.any(front):
            px, _ = cv2.projectPoints(pts[front], np.zeros(3), np.zeros(3), self.K, self.dist)
            out[front] = px.reshape(-1, 2)
        return out

    def normalized(self, pixels: Array) -> Array:
        """Ideal normalized coordinates (N,2) of pixels (N,2): the inverse of `project` for z = 1.

        Iterates OpenCV's undistortion to 1e-9 px instead of its default five steps, which leave
        up to 0.25 px near the corners of a 1280x720 image at f = 600 px, k = (0.1, −0.25, 0.1).
        """
        import cv2

        px = np.ascontiguousarray(np.asarray(pixels, dtype=np.float64).reshape(-1, 1, 2))
        if len(px) == 0:
            return np.zeros((0, 2))
        if not self.has_distortion:
            K = self.K
            y = (px[:, 0, 1] - K[1, 2]) / K[1, 1]
            x = (px[:, 0, 0] - K[0, 2] - K[0, 1] * y) / K[0, 0]
            return np.stack([x, y], axis=1)
        criteria = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, _UNDISTORT_ITERATIONS, _UNDISTORT_EPS_PX)
        out = cv2.undistortPoints(px, self.K, self.dist, R=np.eye(3), P=np.eye(3), criteria=criteria)
        return np.asarray(out, dtype=np.float64).reshape(-1, 2)

    def without_distortion(self) -> CameraModel:
        return CameraModel(self.K, np.zeros(0), self.width, self.height)


def load_intrinsics(path: Path) -> CameraModel:
    """Read an OpenCV FileStorage (yaml/xml) or a ROS camera_info yaml file.

    Raises ArmtoolError naming the file and the missing or invalid key.
    """
    from armtool.calib.limits import MAX_FILE_BYTES
    from armtool.fileio import read_regular

    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise ArmtoolError(
                f"intrinsics file is {size / 2**20:.0f} MB, more than the {MAX_FILE_BYTES // 2**20} MB armtool reads",
                str(path),
                "is this the right file? intrinsics files are a few hundred bytes",
            )
        raw = read_regular(path)  # a FIFO or device is refused, not waited on
    except OSError as exc:
        raise ArmtoolError(f"cannot read intrinsics file: {exc.strerror}", str(path)) from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise ArmtoolError(
            "intrinsics file is not UTF-8 text",
            f"{path}:{line}",
            "is it the right file? intrinsics are a YAML or XML text file",
        ) from None
    deep = _too_deep_line(text)
    if deep is not None:
        raise ArmtoolError(
            f"intrinsics file is nested more than {MAX_NESTING} levels deep",
            f"{path}:{deep}",
            "camera_matrix and distortion_coefficients are flat lists",
        )
    try:
        data = _read_filestorage(path) if _is_filestorage(path, text) else _read_plain_yaml(path, text)
    except RecursionError:
        raise ArmtoolError(
            "intrinsics file is nested too deeply",
            str(path),
            "camera_matrix and distortion_coefficients are flat lists",
        ) from None
    try:
        return _camera_from_mapping(data, path)
    except ArmtoolError as exc:
        # Name the line of the key at fault, as for syntax errors (a missing key has none).
        key = re.search(r"key '([^']+)'", exc.what)
        key_line = _key_line(text, key.group(1)) if key is not None and exc.where == str(path) else None
        if key_line is None:
            raise
        raise ArmtoolError(exc.what, f"{path}:{key_line}", exc.hint) from None


MAX_NESTING = 32  # an intrinsics file nests 2 or 3 levels; deeper is not one (and YAML recursion is slow)


def _too_deep_line(text: str) -> int | None:
    """The line where brackets ([ {) or XML tags first nest more than MAX_NESTING deep, found
    by a scan before parsing (quoted text is skipped): the parsers recurse once per level."""
    depth, line, quote = 0, 1, ""
    for ch in text:
        if ch == "\n":
            line += 1
        elif quote:
            quote = "" if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
            if depth > MAX_NESTING:
                return line
        elif ch in "]}":
            depth = max(depth - 1, 0)
    return None


def _key_line(text: str, key: str) -> int | None:
    """The line where `key` is defined (`key:` in YAML, `<key` in XML), 1-based."""
    found = re.search(rf"^\s*(?:{re.escape(key)}\s*:|<{re.escape(key)}\b)", text, re.MULTILINE)
    return text.count("\n", 0, found.start()) + 1 + (text[found.start() : found.end()].count("\n")) if found else None


def save_intrinsics(camera: CameraModel, path: Path) -> None:
    """Write OpenCV FileStorage yaml (readable by cv2.FileStorage and `load_intrinsics`), atomically."""
    import cv2

    path = Path(path)
    fs = cv2.FileStorage(path.name, cv2.FILE_STORAGE_WRITE | cv2.FILE_STORAGE_MEMORY | cv2.FILE_STORAGE_FORMAT_YAML)
    fs.write("image_width", camera.width)
    fs.write("image_height", camera.height)
    fs.write("camera_matrix", np.array(camera.K))
    fs.write("distortion_coefficients", np.array(camera.dist).reshape(1, -1))
    text = fs.releaseAndGetString()
    from armtool.fileio import write_atomic

    write_atomic(path, text)


def _is_filestorage(path: Path, text: str) -> bool:
    head = text.lstrip()[:200]
    return (
        path.suffix.lower() == ".xml"
        or head.startswith("<?xml")
        or head.startswith("%YAML:1")
        or head.startswith("%YAML 1")
        or "!!opencv-matrix" in text
    )


def _read_filestorage(path: Path) -> dict[str, Any]:
    """Top-level nodes of a cv2.FileStorage file as plain Python values (matrices as arrays)."""
    import cv2

    try:
        fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ)
    except (cv2.error, SystemError) as exc:
        # OpenCV sometimes surfaces its parse error as a SystemError whose cause is the cv2.error.
        cause = exc.__cause__ or exc.__context__ or exc
        lines = str(cause).strip().splitlines()
        msg = lines[-1].strip() if lines else "parse error"
        located = re.search(r"\((\d+)\): (.*?)'?\s*$", msg)  # "... in function 'file(4): Missing , ...'"
        if located:
            raise ArmtoolError(
                f"not a readable OpenCV FileStorage file: {located.group(2)}", f"{path}:{located.group(1)}"
            ) from None
        raise ArmtoolError(f"not a readable OpenCV FileStorage file: {msg}", str(path)) from None
    if not fs.isOpened():
        raise ArmtoolError("not a readable OpenCV FileStorage file", str(path))
    try:
        try:
            root = fs.root()
            names = list(root.keys())
        except (cv2.error, SystemError, UnicodeDecodeError) as exc:
            raise ArmtoolError(
                f"not a readable OpenCV FileStorage file: {(str(exc).strip().splitlines() or ['parse error'])[-1]}",
                str(path),
            ) from None
        values: dict[str, Any] = {}
        for name in names:
            try:
                values[name] = _node_value(root.getNode(name))
            except (cv2.error, SystemError, UnicodeDecodeError) as exc:  # e.g. a matrix whose data is not all numbers
                lines = str(exc.__cause__ or exc).strip().splitlines()
                raise ArmtoolError(
                    f"key '{name}' cannot be read: {lines[-1].strip() if lines else 'bad value'}",
                    str(path),
                    "a matrix is {rows, cols, dt, data: [numbers]}",
                ) from None
        return values
    finally:
        fs.release()


def _node_value(node: Any) -> Any:
    if node.isMap():
        keys = node.keys()
        if "data" in keys and ("rows" in keys or "dt" in keys):
            mat = node.mat()
            if mat is not None:
                return np.asarray(mat, dtype=np.float64)
        return {k: _node_value(node.getNode(k)) for k in keys}
    if node.isSeq():
        return [_node_value(node.at(i)) for i in range(node.size())]
    if node.isInt():
        return int(node.real())
    if node.isReal():
        return float(node.real())
    if node.isString():
        return node.string()
    return None


def _read_plain_yaml(path: Path, text: str) -> dict[str, Any]:
    import yaml

    from armtool.yamlload import safe_load

    try:
        data = safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"{path}:{mark.line + 1}" if mark is not None else str(path)
        problem = getattr(exc, "problem", None) or "invalid YAML"
        raise ArmtoolError(f"cannot parse intrinsics file: {problem}", where) from None
    if not isinstance(data, dict):
        raise ArmtoolError(
            "intrinsics file is not a mapping of keys",
            str(path),
            hint="expected OpenCV FileStorage (camera_matrix, distortion_coefficients, image_width, "
            "image_height) or a ROS camera_info yaml",
        )
    return data


def _find(data: Mapping[str, Any], keys: tuple[str, ...]) -> tuple[str, Any] | None:
    for key in keys:
        if key in data and data[key] is not None:
            return key, data[key]
    return None


def _numbers(value: Any, key: str, path: Path) -> Array:
    """A matrix value as a flat float array: opencv-matrix, ROS {rows, cols, data}, or a list."""
    if isinstance(value, Mapping):
        if "data" not in value:
            raise ArmtoolError(f"key '{key}' has no 'data' list", str(path))
        value = value["data"]
    try:
        arr = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ArmtoolError(f"key '{key}' is not a list of numbers: {value!r:.80}", str(path)) from None
    if not np.all(np.isfinite(arr)):
        raise ArmtoolError(f"key '{key}' contains non-finite numbers", str(path))
    return arr


def _positive_int(value: Any, key: str, path: Path) -> int:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ArmtoolError(f"key '{key}' is not a number: {value!r:.80}", str(path)) from None
    if number <= 0 or number != int(number):
        raise ArmtoolError(f"key '{key}' must be a positive whole number of pixels, got {value!r}", str(path))
    return int(number)


def _camera_from_mapping(data: Mapping[str, Any], path: Path) -> CameraModel:
    found_k = _find(data, _K_KEYS)
    if found_k is None:
        raise ArmtoolError(
            f"missing key 'camera_matrix' (also accepted: {', '.join(_K_KEYS[1:])})",
            str(path),
            hint="expected OpenCV FileStorage or ROS camera_info intrinsics",
        )
    K = _numbers(found_k[1], found_k[0], path)
    if K.size != 9:
        raise ArmtoolError(f"key '{found_k[0]}' must have 9 values (3x3), got {K.size}", str(path))

    found_d = _find(data, _DIST_KEYS)
    if found_d is None:
        raise ArmtoolError(
            f"missing key 'distortion_coefficients' (also accepted: {', '.join(_DIST_KEYS[1:])})",
            str(path),
            hint="write 'distortion_coefficients: [0, 0, 0, 0, 0]' for an undistorted (rectified) camera",
        )
    dist = _numbers(found_d[1], found_d[0], path)
    model = data.get("distortion_model")
    if model is not None:
        if model not in _ROS_MODELS:
            raise ArmtoolError(
                f"unsupported distortion_model '{model}'",
                str(path),
                hint=f"supported: {', '.join(_ROS_MODELS)} (OpenCV's pinhole model); "
                "fisheye/equidistant cameras are not supported",
            )
        if dist.size not in _ROS_MODELS[model] and dist.size != 0:
            raise ArmtoolError(
                f"distortion_model '{model}' needs {_ROS_MODELS[model][0]} coefficients, "
                f"'{found_d[0]}' has {dist.size}",
                str(path),
            )
    if dist.size not in _DIST_LENGTHS:
        raise ArmtoolError(
            f"key '{found_d[0]}' must have 0, 4, 5, 8, 12 or 14 values, got {dist.size}",
            str(path),
            hint="OpenCV order: k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4 [tx ty]]]]",
        )

    width_found, height_found = _find(data, _WIDTH_KEYS), _find(data, _HEIGHT_KEYS)
    if width_found is None or height_found is None:
        size_found = _find(data, _SIZE_KEYS)
        if size_found is None:
            missing = "image_width" if width_found is None else "image_height"
            raise ArmtoolError(
                f"missing key '{missing}' (also accepted: width/height, or image_size: [w, h])",
                str(path),
                hint="the image size the intrinsics were calibrated at, in pixels",
            )
        size = _numbers(size_found[1], size_found[0], path)
        if size.size != 2:
            raise ArmtoolError(f"key '{size_found[0]}' must be [width, height]", str(path))
        width = _positive_int(size[0], size_found[0], path)
        height = _positive_int(size[1], size_found[0], path)
    else:
        width = _positive_int(width_found[1], width_found[0], path)
        height = _positive_int(height_found[1], height_found[0], path)
    try:
        return CameraModel(K.reshape(3, 3), dist, width, height)
    except ArmtoolError as exc:
        raise ArmtoolError(f"key '{found_k[0]}': {exc.what}", str(path), exc.hint) from None
