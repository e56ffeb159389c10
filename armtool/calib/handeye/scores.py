"""Every method's frames scored as a user checks them: held-out reprojection, and the board's spread.

* Held-out reprojection: k-fold over images (`folds`, default 5; images dealt to folds by a seeded
  shuffle). Each fold's images are predicted by frames fitted to the other images: by every
  closed form, and by the refinement started from the closed form that explains those images best
  (`refine`); every held-out corner's residual is pooled into one RMS per method. The residual a
  fit leaves on its own images is no measure of it: the refinement always lowers it.
* Spread of the board's pose: G_i · X · C_i, with C_i one image's own IPPE pose, is where that image
  alone puts the board (in the base; eye-to-hand, in the flange). Their RMS and largest distance
  from the mean, in position (mm) and rotation (°), over the images that are not outliers of the
  refinement, show the 1-3 cm disagreement that makes easy_handeye users' runs differ, within one run.

With `Intrinsics.AUTO` both refinements (intrinsics held, and refined with the frames) are
scored, and the intrinsics are refined only when that lowers the held-out RMS of the inlier images
by MIN_GAIN or more: on rendered images refining them gained 0.02 % and moved k2 and k3 far from the
truth (0.13 and −0.19 for 0.08 and 0), which the data could not tell apart. Without folds they are held.

The frames written are the refinement's unless a closed form predicts the held-out inlier images
better: all of them fit the same images, and when the flange poses' error dominates they are within
a percent of each other (benchmarks/handeye_bench.py), so the held-out score decides, as `calibrate
fit`'s k-fold does, and a note says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from armtool.calib.choices import Intrinsics
from armtool.calib.fit.handeye import average_pose
from armtool.calib.handeye.closed_forms import METHODS, Method, closed_form
from armtool.calib.handeye.refine import Refined, image_rms, refine, reprojection_residuals
from armtool.calib.handeye.views import Observations
from armtool.calib.model import se3
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError

REFINED = "refined"
REFINED_INTRINSICS = "refined_intrinsics"
MIN_FOLD_IMAGES = 3  # each fold's training set must determine both frames
MIN_GAIN = 0.02  # AUTO refines the intrinsics only when that predicts the inlier images this much better


@dataclass(frozen=True)
class Spread:
    """Where each image alone puts the board: offsets from the mean pose, per image and summarised."""

    offsets_mm: Array  # (N,)
    offsets_deg: Array
    position_rms_mm: float
    position_max_mm: float
    rotation_rms_deg: float
    rotation_max_deg: float


@dataclass(frozen=True)
class Score:
    """One method: its frames fitted to every image, and how they do on images they never saw."""

    method: str  # a closed form's name, REFINED or REFINED_INTRINSICS
    X: Array | None  # None: the method gave no frames (`failed` says why)
    Z: Array | None
    camera: CameraModel
    fit_rms_px: float  # every corner, frames fitted to every image
    heldout_rms_px: float  # every corner of every image, predicted by frames fitted without it; NaN without folds
    heldout_inlier_rms_px: float  # the same without the refinement's outlier images
    heldout_image_rms_px: Array  # (N,)
    spread: Spread | None
    fit_image_rms_px: Array  # (N,) each image's RMS with the frames fitted to every image
    failed: str = ""

    @property
    def is_refinement(self) -> bool:
        return self.method in (REFINED, REFINED_INTRINSICS)


@dataclass(frozen=True)
class Scores:
    rows: list[Score]
    chosen: Score  # the method whose frames are written: the one that predicts held-out images best
    refined: Refined  # the chosen refinement on every image (its outliers and noise are reported)
    folds: int
    notes: list[str] = field(default_factory=list)


def folds_of(count: int, folds: int, seed: int) -> list[NDArray[np.intp]]:
    """The held-out images of each fold: a seeded shuffle dealt into `folds` parts of near-equal size."""
    order = np.random.default_rng(seed).permutation(count)
    return [np.sort(part) for part in np.array_split(order, folds)]


def start(
    obs: Observations, camera: CameraModel, forms: dict[Method, tuple[Array, Array] | str] | None = None
) -> tuple[Array, Array]:
    """The closed form whose frames explain the images best (median image RMS): the refinement's
    start (`forms`: the closed forms of these images, when already computed)."""
    best: tuple[float, Array, Array] | None = None
    for frames in (forms or closed_forms(obs)).values():
        if isinstance(frames, str):
            continue
        rms = image_rms(reprojection_residuals(obs, *frames, camera), obs.image, obs.count)
        score = float(np.median(np.where(np.isfinite(rms), rms, np.inf)))
        if best is None or score < best[0]:
            best = (score, *frames)
    if best is None:
        raise ArmtoolError(
            "no closed form gives the camera's frame from these images",
            hint="take poses that turn the flange by tens of degrees about different axes",
        )
    return best[1], best[2]


def score_methods(
    obs: Observations, camera: CameraModel, *, folds: int = 5, seed: int = 0, intrinsics: Intrinsics = Intrinsics.AUTO
) -> Scores:
    """Every closed form and the refinement(s), fitted to every image and by k-fold (module docstring)."""
    notes: list[str] = []
    k = min(folds, obs.count) if folds >= 2 else 0
    if k and obs.count - math.ceil(obs.count / k) < MIN_FOLD_IMAGES:
        notes.append(f"{obs.count} images are too few for {k}-fold held-out scores")
        k = 0
    variants = {Intrinsics.FIXED: [False], Intrinsics.REFINE: [True], Intrinsics.AUTO: [False, True]}[intrinsics]
    if intrinsics is Intrinsics.AUTO and not k:
        variants = [False]
        notes.append("without held-out scores the intrinsics are held as the file gives them")
    names = [m.value for m in METHODS] + [REFINED_INTRINSICS if v else REFINED for v in variants]
    heldout = {name: np.full((len(obs.pixels), 2), np.nan) for name in names}
    failed: dict[bool, str] = {}
    for test in folds_of(obs.count, k, seed) if k else []:
        train_rows = np.setdiff1d(np.arange(obs.count), test)
        train, held = obs.subset(train_rows), obs.subset(test)
        where = np.isin(obs.image, test)
        forms = closed_forms(train)
        for method, frames in forms.items():
            if not isinstance(frames, str):
                heldout[method.value][where] = reprojection_residuals(held, *frames, camera)
        X0, Z0 = start(train, camera, forms)
        for v in variants:
            fit = _refined(train, X0, Z0, camera, v, failed)
            if fit is not None:
                name = REFINED_INTRINSICS if v else REFINED
                heldout[name][where] = reprojection_residuals(held, fit.X, fit.Z, fit.camera)
    forms = closed_forms(obs)
    X0, Z0 = start(obs, camera, forms)
    found = {v: _refined(obs, X0, Z0, camera, v, failed) for v in variants}
    refinements = {v: fit for v, fit in found.items() if fit is not None and v not in failed}
    if not refinements:
        why = "; ".join(failed.values())
        raise ArmtoolError(
            f"the refinement failed: {why}",
            hint="try --intrinsics fixed, and check the intrinsics file"
            if True in failed
            else "check that each pose row belongs to its image",
        )
    notes += [
        f"refining {'the intrinsics' if v else 'the frames'} failed ({why}): not scored" for v, why in failed.items()
    ]
    outliers = next(iter(refinements.values())).outliers
    rows: list[Score] = []
    for method, frames in forms.items():
        if isinstance(frames, str):
            rows.append(_failed(method.value, frames, camera, obs.count))
        else:
            rows.append(_score(method.value, *frames, camera, obs, heldout[method.value], outliers, k))
    for v, fit in refinements.items():
        name = REFINED_INTRINSICS if v else REFINED
        rows.append(_score(name, fit.X, fit.Z, fit.camera, obs, heldout[name], fit.outliers, k))
    chosen = next(r for r in rows if r.method == (REFINED if False in refinements else REFINED_INTRINSICS))
    with_intrinsics = next((r for r in rows if r.method == REFINED_INTRINSICS), None)
    if (
        k
        and with_intrinsics is not None
        and with_intrinsics.heldout_inlier_rms_px < (1 - MIN_GAIN) * chosen.heldout_inlier_rms_px
    ):
        chosen = with_intrinsics
    refinement = refinements[chosen.method == REFINED_INTRINSICS]
    forms_scored = [r for r in rows if not r.is_refinement and math.isfinite(r.heldout_inlier_rms_px)]
    best_form = min(forms_scored, key=lambda r: r.heldout_inlier_rms_px, default=None)
    if k and best_form is not None and best_form.heldout_inlier_rms_px < chosen.heldout_inlier_rms_px:
        notes.append(
            f"{best_form.method} predicts the held-out images better than the refinement "
            f"({best_form.heldout_inlier_rms_px:.3f} against {chosen.heldout_inlier_rms_px:.3f} px without outliers): "
            "its frames are written"
        )
        chosen = best_form
    return Scores(rows, chosen, refinement, k, notes)


def _refined(
    obs: Observations, X0: Array, Z0: Array, camera: CameraModel, intrinsics: bool, failed: dict[bool, str]
) -> Refined | None:
    """`refine`, or None with the reason kept in `failed` (intrinsics that wander off into a camera
    that is none: a negative focal length, a distortion that folds)."""
    if intrinsics in failed:
        return None
    try:
        return refine(obs, X0, Z0, camera, intrinsics=intrinsics)
    except (ArmtoolError, np.linalg.LinAlgError, ValueError) as exc:
        failed[intrinsics] = getattr(exc, "what", str(exc))
        return None


def closed_forms(obs: Observations) -> dict[Method, tuple[Array, Array] | str]:
    """Every closed form's frames from the images with an unambiguous pose, or why it gave none."""
    out: dict[Method, tuple[Array, Array] | str] = {}
    for method in METHODS:
        try:
            out[method] = closed_form(method, obs.G[obs.start], obs.C[obs.start])
        except (ArmtoolError, np.linalg.LinAlgError) as exc:
            out[method] = getattr(exc, "what", str(exc))
    return out


def _failed(method: str, why: str, camera: CameraModel, count: int) -> Score:
    nan = float("nan")
    return Score(method, None, None, camera, nan, nan, nan, np.full(count, nan), None, np.full(count, nan), why)


def _score(
    method: str,
    X: Array,
    Z: Array,
    camera: CameraModel,
    obs: Observations,
    heldout: Array,
    outliers: NDArray[np.intp],
    folds: int,
) -> Score:
    fit = reprojection_residuals(obs, X, Z, camera)
    inliers = ~np.isin(obs.image, outliers)
    return Score(
        method,
        X,
        Z,
        camera,
        _rms(fit),
        _rms(heldout) if folds else float("nan"),
        _rms(heldout[inliers]) if folds else float("nan"),
        image_rms(heldout, obs.image, obs.count),
        spread(obs, X, camera, np.setdiff1d(np.arange(obs.count), outliers)),
        image_rms(fit, obs.image, obs.count),
    )


def _rms(residuals: Array) -> float:
    """RMS pixel distance over corners (M, 2); infinite when a corner has no prediction (behind the camera)."""
    if len(residuals) == 0:
        return float("nan")
    return float(np.sqrt(np.mean(np.sum(residuals**2, axis=1))))


def spread(obs: Observations, X: Array, camera: CameraModel, inliers: NDArray[np.intp]) -> Spread:
    """The board's pose predicted from each image alone, G_i X C_i, against the mean of the inlier
    images' (every image's offset; the RMS and largest over the inliers: an outlier is named apart)."""
    C = _poses(obs, camera)
    Zs = obs.G @ X @ C
    mean = average_pose(list(Zs[inliers]))
    offsets_mm = np.linalg.norm(Zs[:, :3, 3] - mean[:3, 3], axis=1) * 1e3
    offsets_deg = np.degrees(np.linalg.norm(se3.log3_batch(np.swapaxes(Zs[:, :3, :3], -1, -2) @ mean[:3, :3]), axis=1))
    mm, deg = offsets_mm[inliers], offsets_deg[inliers]
    return Spread(
        offsets_mm,
        offsets_deg,
        float(np.sqrt(np.mean(mm**2))),
        float(mm.max()),
        float(np.sqrt(np.mean(deg**2))),
        float(deg.max()),
    )


def _poses(obs: Observations, camera: CameraModel) -> Array:
    """Each image's IPPE pose with `camera` (the observations' own poses when it is theirs)."""
    from armtool.calib.targets.pose import planar_pose

    out: Array = obs.C.copy()
    for i in range(obs.count):
        mine = obs.image == i
        cMt, rms, _ambiguous = planar_pose(obs.points[mine], obs.pixels[mine], camera)
        if math.isfinite(rms):
            out[i] = cMt
    return out
