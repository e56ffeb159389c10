"""`calibrate handeye` end to end: the dataset checked, the board found, the conventions checked,
every method scored, and the result as a document (handeye.yaml, and the JSON summary).

Everything is checked before work: a dataset problem, an unreadable intrinsics file, too few images
with a board, or a poses file that fits far better read another way stop the run with the fix.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from armtool.calib.choices import ChessboardDetector, Intrinsics, Setup
from armtool.calib.handeye.conventions import ConventionCheck
from armtool.calib.handeye.dataset import HandEyeDataset
from armtool.calib.handeye.scores import Score, Scores
from armtool.calib.handeye.views import View
from armtool.calib.model import se3
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError

RESULT_FORMAT = "armtool-handeye-result/1"
MIN_IMAGES = 6


@dataclass(frozen=True)
class HandEyeRequest:
    dataset: Path
    folds: int = 5
    seed: int = 0
    intrinsics: Intrinsics = Intrinsics.AUTO
    detector: ChessboardDetector = ChessboardDetector.CLASSIC
    keep_conventions: bool = False


@dataclass(frozen=True)
class HandEyeResult:
    request: HandEyeRequest
    ds: HandEyeDataset
    camera: CameraModel  # as the intrinsics file gives it
    views: list[View]  # every shot, each look-alike board's corners relabelled to its turn
    turned: dict[int, int]  # view index → turn (of `len(turns)`) applied
    turns: int
    used: list[int]  # the view of each fitted image
    conventions: ConventionCheck | None
    scores: Scores
    notes: list[str] = field(default_factory=list)

    @property
    def frame_names(self) -> tuple[str, str]:
        """What X and Z are called: camera_in_flange and board_in_base, or camera_in_base and board_in_flange."""
        target = "board" if self.ds.target.board is not None else "tag"
        if self.ds.setup is Setup.EYE_IN_HAND:
            return "camera_in_flange", f"{target}_in_base"
        return "camera_in_base", f"{target}_in_flange"


def run_handeye(request: HandEyeRequest, progress: Callable[[str, int, int], None] | None = None) -> HandEyeResult:
    """The whole calibration (module docstring); `progress(stage, done, total)`."""
    import scipy.optimize  # noqa: F401  (SciPy's BLAS must be loaded before it is limited to one thread)

    from armtool.calib.fit.calibration import one_blas_thread
    from armtool.calib.handeye.conventions import check_conventions
    from armtool.calib.handeye.dataset import load_handeye_dataset, require_ok
    from armtool.calib.handeye.scores import score_methods
    from armtool.calib.handeye.turns import board_turns, resolve_turns
    from armtool.calib.handeye.views import find_views, observations
    from armtool.calib.model.camera import load_intrinsics

    ds = load_handeye_dataset(request.dataset)
    require_ok(ds)
    camera = load_intrinsics(ds.intrinsics)
    found = find_views(
        ds, camera, request.detector, progress=lambda d, t: progress("finding the board", d, t) if progress else None
    )
    usable = sum(v.usable for v in found)
    if usable < MIN_IMAGES:
        missing = [f"{v.name}: {v.reason}" for v in found if not v.usable][:5]
        raise ArmtoolError(
            f"the {ds.target.describe()} was found in {usable} of {len(found)} images; at least {MIN_IMAGES} are needed"
            + "".join(f"\n  {m}" for m in missing),
            ds.poses_file.name,
            "check target: in dataset.yaml (type, size, squares not inner corners) and the images",
        )
    notes: list[str] = []
    with one_blas_thread():
        views, turned = resolve_turns(found, ds.flanges(), ds.setup, ds.target, camera)
        if progress:
            progress("checking the pose conventions", 0, 1)
        conventions = check_conventions(ds, views, camera)
        if progress:
            progress("checking the pose conventions", 1, 1)
        if conventions.better is not None:
            if not request.keep_conventions:
                raise ArmtoolError(
                    conventions.message(),
                    "dataset.yaml",
                    conventions.fix() + " (or calibrate as declared with --keep-conventions)",
                )
            notes.append("kept as declared (--keep-conventions): " + conventions.message())
        obs = observations(views, ds.flanges(), ds.setup, ds.target)
        if progress:
            progress("fitting", 0, 1)
        scores = score_methods(obs, camera, folds=request.folds, seed=request.seed, intrinsics=request.intrinsics)
        if progress:
            progress("fitting", 1, 1)
    used = [k for k, v in enumerate(views) if v.usable]
    turns = len(board_turns(ds.target))
    return HandEyeResult(request, ds, camera, views, turned, turns, used, conventions, scores, notes + scores.notes)


def _finite(x: float, digits: int = 4) -> float | None:
    return round(float(x), digits) if math.isfinite(x) else None


def pose_document(T: Array, sigma: tuple[Array, Array] | None = None) -> dict[str, Any]:
    """A pose as handeye.yaml writes it: metres, URDF rpy (R = Rz·Ry·Rx, rad), quaternion xyzw, 1σ."""
    from armtool.calib.fit.handeye import quaternions

    w, x, y, z = quaternions(T[None, :3, :3])[0]
    out: dict[str, Any] = {
        "xyz_m": [round(float(v), 7) for v in T[:3, 3]],
        "rpy_rad": [round(float(v), 7) for v in se3.rpy_of(T[:3, :3])],
        "quaternion_xyzw": [round(float(v), 8) for v in (x, y, z, w)],
    }
    if sigma is not None:
        out["sigma_position_mm"] = [_finite(v * 1e3) for v in sigma[0]]
        out["sigma_rotation_deg"] = [_finite(math.degrees(v), 5) for v in sigma[1]]
    return out


def _method_document(row: Score, names: tuple[str, str]) -> dict[str, Any]:
    out: dict[str, Any] = {
        "method": row.method,
        "heldout_rms_px": _finite(row.heldout_rms_px),
        "heldout_rms_px_without_outliers": _finite(row.heldout_inlier_rms_px),
        "fit_rms_px": _finite(row.fit_rms_px),
    }
    if row.spread is not None:
        out["board_spread"] = {
            "position_rms_mm": _finite(row.spread.position_rms_mm),
            "position_max_mm": _finite(row.spread.position_max_mm),
            "rotation_rms_deg": _finite(row.spread.rotation_rms_deg),
            "rotation_max_deg": _finite(row.spread.rotation_max_deg),
        }
    if row.X is not None and row.Z is not None:
        out[names[0]] = pose_document(row.X)
        out[names[1]] = pose_document(row.Z)
    if row.failed:
        out["failed"] = row.failed
    return out


def document(result: HandEyeResult) -> dict[str, Any]:
    """handeye.yaml, and what `--format json` prints (`schema_version` 1)."""
    scores, chosen, refined = result.scores, result.scores.chosen, result.scores.refined
    names = result.frame_names
    cam = chosen.camera
    sigmas = (refined.sigma_X, refined.sigma_Z) if chosen.is_refinement else (None, None)
    assert chosen.X is not None and chosen.Z is not None  # a chosen method gave frames
    fitted = {view: n for n, view in enumerate(result.used)}
    outliers = {result.used[i] for i in refined.outliers}
    images = []
    for k, view in enumerate(result.views):
        entry: dict[str, Any] = {"image": view.name, "line": view.line, "corners": len(view.ids), "used": view.usable}
        if not view.usable:
            entry["reason"] = view.reason
        else:
            n = fitted[k]
            entry["outlier"] = k in outliers
            entry["fit_rms_px"] = _finite(chosen.fit_image_rms_px[n])
            entry["heldout_rms_px"] = _finite(chosen.heldout_image_rms_px[n])
            if chosen.spread is not None:
                entry["board_offset_mm"] = _finite(chosen.spread.offsets_mm[n], 3)
                entry["board_offset_deg"] = _finite(chosen.spread.offsets_deg[n], 4)
        if k in result.turned:
            entry["turned_deg"] = 360 * result.turned[k] // result.turns
        images.append(entry)
    return {
        "schema_version": 1,
        "format": RESULT_FORMAT,
        "dataset": str(result.request.dataset),
        "setup": result.ds.setup.value,
        "target": result.ds.target.describe(),
        "method": chosen.method,
        names[0]: pose_document(chosen.X, sigmas[0]),
        names[1]: pose_document(chosen.Z, sigmas[1]),
        "intrinsics": {
            "refined": chosen.method.endswith("intrinsics"),
            "camera_matrix": [[round(float(v), 4) for v in row] for row in cam.K],
            "distortion_coefficients": [round(float(v), 8) for v in cam.dist],
            "image_width": cam.width,
            "image_height": cam.height,
        },
        "noise": {
            "pixel_px": _finite(refined.noise.pixel_px),
            "flange_position_mm": _finite(refined.noise.position_m * 1e3),
            "flange_rotation_deg": _finite(math.degrees(refined.noise.rotation_rad), 5),
        },
        "heldout": {
            "folds": scores.folds,
            "seed": result.request.seed,
            "rms_px": _finite(chosen.heldout_rms_px),
            "rms_px_without_outliers": _finite(chosen.heldout_inlier_rms_px),
            "best_closed_form": _best_closed_form(scores),
        },
        "fit_rms_px": _finite(chosen.fit_rms_px),
        "images_used": len(result.used),
        "images": images,
        "outliers": sorted(result.views[k].name for k in outliers),
        "methods": [_method_document(row, names) for row in scores.rows],
        "conventions": result.conventions.message() if result.conventions is not None else None,
        "notes": result.notes,
    }


def _best_closed_form(scores: Scores) -> dict[str, Any] | None:
    rows = [r for r in scores.rows if r.X is not None and not r.method.startswith("refined")]
    if not scores.folds or not rows:
        return None
    best = min(rows, key=lambda r: r.heldout_rms_px if math.isfinite(r.heldout_rms_px) else np.inf)
    return {"method": best.method, "rms_px": _finite(best.heldout_rms_px)}


def write_result(result: HandEyeResult, path: Path) -> None:
    """handeye.yaml, atomically."""
    import yaml

    from armtool.fileio import write_atomic

    header = "# armtool calibrate handeye: the camera's and the board's frames (metres, rad; rpy is R = Rz·Ry·Rx)\n"
    write_atomic(
        path, header + yaml.safe_dump(document(result), sort_keys=False, allow_unicode=True, default_flow_style=None)
    )
