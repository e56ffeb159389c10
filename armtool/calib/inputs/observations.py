"""Target corners per sample: detected in the images, or (one AprilTag) read from corners.csv.

Detection is the slow part of a calibration (tens of ms per image), so it runs on a thread per
core (OpenCV releases the GIL while it works; a forked process pool can deadlock on OpenCV's
own thread pool inherited from the parent) and reports progress; a sample whose tag is missing, blurred or ambiguous
keeps its reason, which `check` and `fit` show.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from armtool.calib.inputs.dataset import Dataset, Sample
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.calib.targets.spec import Target
from armtool.errors import ArmtoolError


@dataclass(frozen=True)
class Observation:
    sample_id: str
    # (P,2) OpenCV pixel centres, in the order of the target's points (`Target.points_m`: a tag's 4
    # corners, a board's corners); NaN rows for points the image does not show; None when rejected.
    corners_px: Array | None
    reason: str = ""  # why there are no corners


Detect = Callable[
    [Dataset, CameraModel], dict[str, Observation]
]  # `observe` with progress shown: every sample's corners


def _detect_one(args: tuple[str, str, Target, CameraModel]) -> tuple[str, Array | None, str]:
    from armtool.calib.inputs.files import read_gray
    from armtool.calib.targets.detect import detect_corners

    sample_id, image_path, target, camera = args
    try:
        gray = read_gray(Path(image_path))
    except ArmtoolError as exc:
        return sample_id, None, exc.what
    if gray is None:
        return sample_id, None, f"cannot read image {image_path}"
    if (gray.shape[1], gray.shape[0]) != (camera.width, camera.height):
        return (
            sample_id,
            None,
            f"image is {gray.shape[1]}x{gray.shape[0]}, the intrinsics say {camera.width}x{camera.height}",
        )
    corners, reason = detect_corners(gray, target, camera)
    return sample_id, corners, reason


def observe(
    ds: Dataset,
    camera: CameraModel,
    samples: list[Sample] | None = None,
    progress: Callable[[int, int], None] | None = None,
    workers: int | None = None,
) -> dict[str, Observation]:
    """Corners for every sample: corners.csv when the dataset has one, else detection in the images."""
    from armtool.calib.inputs.files import unreadable_reason

    target = Target.of(ds)
    samples = ds.samples if samples is None else samples
    out: dict[str, Observation] = {}
    if not target.usable:
        return {
            s.id: Observation(s.id, None, "the target in dataset.yaml is not usable (see its problem)") for s in samples
        }
    if ds.corners_file is not None:
        for s in samples:
            uv = ds.corners.get(s.id)
            out[s.id] = Observation(s.id, uv, "" if uv is not None else f"no row for tag {ds.tag_id} in corners.csv")
        return out
    jobs = []
    for s in samples:
        if s.image is None:
            out[s.id] = Observation(s.id, None, "no image and no corners.csv row")
        elif (why := unreadable_reason(Path(s.image))) is not None:
            out[s.id] = Observation(s.id, None, f"image {s.image} {why}")
        else:
            jobs.append((s.id, str(s.image), target, camera))
    total = len(jobs)
    workers = workers or min(os.cpu_count() or 1, 8)
    if total == 0:
        return out
    from concurrent.futures import ThreadPoolExecutor

    done = 0
    with ThreadPoolExecutor(max_workers=workers) as pool:
        for sid, uv, reason in pool.map(_detect_one, jobs):
            out[sid] = Observation(sid, uv, reason)
            done += 1
            if progress:
                progress(done, total)
    return out
