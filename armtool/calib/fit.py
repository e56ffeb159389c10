"""The calibration itself: start with hand-eye only, find what is identifiable, fit, reject outliers.

`calibrate` runs these steps, one function each:
1. Samples without a usable tag are rejected, the hold-out set is put aside (`_partition`).
2. PnP per image and a closed-form AX = XB give the two measurement frames (`_start_frames`).
3. Hand-eye-only fit (frames free, nominal robot): the "before" that hand-eye tools give.
4. Identifiability of every candidate parameter on the fit poses (`identify.analyse`); a fit
   that cannot separate the frames, or lacks data, is refused (`_check_identified`, `_check_enough_data`).
5. Robust fit (soft-L1 on corner reprojection) of the identifiable set; samples whose residual
   stands out are named and removed (`_robust_fit`); then a plain Levenberg–Marquardt polish on
   the inliers and the parameters' σ (`_sigma`).
6. Which zero offsets are physical (`zero_offsets.analyse_offsets`), the held-out samples scored
   by the same outlier rule (`_score_holdout`), and what the numbers cannot say (`_fit_warnings`).
Residuals are corner reprojection errors in pixels; the Jacobian is by central differences on
the model, which is smooth, and costs a few tens of ms.
"""

from __future__ import annotations

import logging
import math
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from armtool.calib import se3
from armtool.calib.camera import CameraModel
from armtool.calib.choices import SampleRole, Setup
from armtool.calib.dataset import Sample
from armtool.calib.holdout import split_holdout
from armtool.calib.identify import Identifiability, analyse
from armtool.calib.model import CalibModel
from armtool.calib.observations import Observation
from armtool.calib.params import Family, ParamKind
from armtool.calib.se3 import Array
from armtool.calib.zero_offsets import ZeroOffset, analyse_offsets
from armtool.errors import ArmtoolError

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class FitOptions:
    families: tuple[Family, ...] = (Family.ORIGINS, Family.OFFSETS)
    families_explicit: bool = False  # the user named them with --params: refuse to silently drop all
    holdout: float = 0.0
    seed: int = 0
    f_scale_px: float = 0.5  # soft-L1 knee: residuals beyond it count less than quadratically
    # A sample is an outlier when its corner RMS exceeds max(floor, median + spread × 1.4826·MAD)
    # of the inliers: a robust z-score, so a 5° reading error that the robust fit half absorbed
    # (0.6-2 px against 0.1 px for good samples) still stands out, while noisy images raise the bar.
    outlier_floor_px: float = 0.5
    outlier_spread: float = 8.0
    qr_tolerance: float = 1e-6
    min_motion_rad: float = math.radians(20)


@dataclass
class SampleResidual:
    sample_id: str
    role: SampleRole
    before_px: float  # corner RMS with the hand-eye-only model
    after_px: float  # corner RMS with the calibrated model
    note: str = ""


@dataclass
class CalibrationResult:
    model: CalibModel
    x: Array  # full parameter vector (corrections; frames relative to model.L0/R0)
    x_handeye: Array  # hand-eye-only solution
    free: list[int]
    sigma: Array  # σ per free parameter (same order as `free`)
    identifiability: Identifiability
    residuals: list[SampleResidual]
    outliers: dict[str, str]  # sample id -> reason
    rejected: dict[str, str]  # sample id -> detection reason
    warnings: list[str] = field(default_factory=list)
    fit_rms_px: tuple[float, float] = (math.nan, math.nan)  # before, after
    holdout_rms_px: tuple[float, float] = (math.nan, math.nan)  # over every held-out sample
    iterations: int = 0
    holdout_inlier_rms_px: tuple[float, float] = (math.nan, math.nan)  # without the held-out outliers
    zero_offsets: list[ZeroOffset] = field(default_factory=list)  # which offsets are physical encoder corrections

    def fitted_frames(self, handeye: bool = False) -> tuple[Array, Array]:
        return self.model.frames(self.x_handeye if handeye else self.x)


class Problem:
    """Residuals and Jacobian for one set of samples.

    `uv` (N, P, 2) holds each sample's pixels of the target's P points (`tag_points`, (P, 3)): a
    tag's 4 corners, or a board's corners, NaN where an image does not show a point (a partial
    ChArUco view); those coordinates have a residual of 0 and do not count."""

    def __init__(self, model: CalibModel, camera: CameraModel, Q: Array, uv: Array, tag_points: Array) -> None:
        self.model, self.camera, self.Q, self.uv, self.tag_points = model, camera, Q, uv, tag_points
        self.seen = np.isfinite(uv)

    @property
    def coordinates(self) -> int:
        """Pixel coordinates measured: what the parameters are fitted to."""
        return int(self.seen.sum())

    def predict(self, x: Array, Q: Array | None = None) -> Array:
        Q = self.Q if Q is None else Q
        pts = self.model.corners_in_camera(x, Q, self.tag_points).reshape(-1, 3)
        return self.camera.project(pts).reshape(len(Q), -1, 2)

    def residuals(self, x: Array) -> Array:
        return np.where(self.seen, self.predict(x) - np.nan_to_num(self.uv), 0.0).ravel()

    def jacobian(self, x: Array, free: Sequence[int], h: float = 1e-6) -> Array:
        J = np.empty((self.uv.size, len(free)))
        for col, i in enumerate(free):
            xp, xm = x.copy(), x.copy()
            xp[i] += h
            xm[i] -= h
            J[:, col] = (self.residuals(xp) - self.residuals(xm)) / (2 * h)
        return J

    def subset(self, rows: Sequence[int]) -> Problem:
        """The same problem on some of its samples (by row)."""
        return Problem(self.model, self.camera, self.Q[list(rows)], self.uv[list(rows)], self.tag_points)

    def per_sample_rms(self, x: Array) -> Array:
        r = self.residuals(x).reshape(len(self.Q), -1)
        counts = self.seen.reshape(len(self.Q), -1).sum(axis=1)
        rms: Array = np.sqrt((r**2).sum(axis=1) / np.maximum(counts, 1))
        return rms


def _solve(problem: Problem, x0: Array, free: list[int], robust: bool, f_scale: float = 0.5) -> tuple[Array, int]:
    def fun(z: Array) -> Array:
        x = x0.copy()
        x[free] = z
        return problem.residuals(x)

    def jac(z: Array) -> Array:
        x = x0.copy()
        x[free] = z
        return problem.jacobian(x, free)

    # Every parameter is a correction of about a millimetre, a milliradian or 0.1 % of gain.
    scale = np.full(len(free), 1e-3)
    m = problem.uv.size
    if robust or m < len(free):
        res = least_squares(
            fun,
            x0[free],
            jac=jac,
            method="trf",
            loss="soft_l1" if robust else "linear",
            f_scale=f_scale,
            x_scale=scale,
            max_nfev=200,
        )
    else:
        res = least_squares(fun, x0[free], jac=jac, method="lm", x_scale=scale, max_nfev=400)
    x = x0.copy()
    x[free] = res.x
    return x, int(res.nfev)


def _start_frames(
    model: CalibModel, camera: CameraModel, Q: Array, uv: Array, points: Array, hints: dict[str, Array]
) -> tuple[Array, Array]:
    from armtool.calib.handeye import initial_frames
    from armtool.calib.targets.pose import planar_pose

    F = model.flange(np.zeros(model.size), Q)
    flanges, tags = [], []
    for i in range(len(Q)):
        cMt, _rms, ambiguous = planar_pose(points, uv[i], camera)
        if not ambiguous:
            flanges.append(F[i])
            tags.append(cMt)
    try:
        if len(tags) < 3:
            raise ArmtoolError("fewer than 3 unambiguous tag poses")
        return initial_frames(model.setup, flanges, tags)
    except ArmtoolError:
        if model.setup is Setup.EYE_TO_HAND and "camera_in_base" in hints and "tag_in_flange" in hints:
            return se3.inv(hints["camera_in_base"]), hints["tag_in_flange"]
        if model.setup is Setup.EYE_IN_HAND and "camera_in_flange" in hints and "tag_in_base" in hints:
            return se3.inv(hints["camera_in_flange"]), hints["tag_in_base"]
        raise


def calibrate(
    model: CalibModel,
    camera: CameraModel,
    samples: list[Sample],
    observations: dict[str, Observation],
    size_m: float,
    options: FitOptions = FitOptions(),
    hints: dict[str, Array] | None = None,
    holdout_ids: set[str] | None = None,
    progress: Callable[[str], None] | None = None,
    target_points: Array | None = None,
) -> CalibrationResult:
    """Fit the model to the samples' target corners; `holdout_ids` (default: a random `options.holdout`
    share) are kept out of the fit and only scored. The target is a tag of edge `size_m`, or the
    points `target_points` (P, 3) of a board that the observations' corners (P, 2) index. Each step
    is one function below."""
    from armtool.calib.apriltag import tag_object_points

    points = tag_object_points(size_m) if target_points is None else np.asarray(target_points, dtype=np.float64)
    say = progress or (lambda _msg: None)
    groups = _partition(samples, observations, holdout_ids, options)
    Q, uv = _arrays(groups.fit, observations, model.chain.n)
    warnings = _motion_warnings(model, Q, options)

    say("initialising the camera and tag frames (PnP + AX=XB)")
    model = model.with_frames(*_start_frames(model, camera, Q, uv, points, hints or {}))
    problem = Problem(model, camera, Q, uv, points)
    frames = model.layout.frames

    say("hand-eye-only fit (nominal robot)")
    x_he, nfev = _solve(problem, np.zeros(model.size), frames, robust=True, f_scale=options.f_scale_px)

    say("identifiability of the parameters")
    candidates = model.indices(options.families)
    ident = analyse(model, problem.jacobian(x_he, candidates), candidates, options.qr_tolerance)
    _check_identified(model, ident, candidates, options)
    free = ident.kept
    _check_enough_data(problem.coordinates, len(free), len(groups.fit))

    say(f"fitting {len(free)} parameters (robust)")
    robust = _robust_fit(problem, x_he, free, groups.fit, options)
    nfev += robust.nfev

    say("final Levenberg–Marquardt on the inliers")
    final = problem.subset(robust.inliers)
    x, n = _solve(final, robust.x, free, robust=False)
    nfev += n
    x_he, n = _solve(final, x_he, frames, robust=False)
    nfev += n
    sigma = _sigma(final, x, free)

    say("which zero offsets the data determines")
    zero_offsets = analyse_offsets(
        model, final.jacobian(x, candidates), candidates, ident, x, dict(zip(free, (float(v) for v in sigma)))
    )
    before, after = problem.per_sample_rms(x_he), problem.per_sample_rms(x)
    outliers = dict(robust.outliers)
    residuals = [
        SampleResidual(s.id, "outlier" if s.id in outliers else "fit", float(b), float(a), outliers.get(s.id, ""))
        for s, b, a in zip(groups.fit, before, after)
    ]
    held = _score_holdout(problem, groups.hold, observations, x_he, x, robust)
    outliers.update(held.outliers)
    residuals += held.residuals
    warnings += held.warnings
    residuals += [SampleResidual(sid, "rejected", math.nan, math.nan, why) for sid, why in groups.rejected.items()]
    warnings += _fit_warnings(model, ident, free, len(robust.inliers), options)
    inliers = robust.inliers
    return CalibrationResult(
        model=model,
        x=x,
        x_handeye=x_he,
        free=free,
        sigma=sigma,
        identifiability=ident,
        residuals=residuals,
        outliers=outliers,
        rejected=groups.rejected,
        warnings=warnings,
        fit_rms_px=(_rms(before[inliers]), _rms(after[inliers])),
        holdout_rms_px=(_rms(held.before), _rms(held.after)),
        iterations=nfev,
        holdout_inlier_rms_px=(_rms(held.before[held.kept]), _rms(held.after[held.kept])),
        zero_offsets=zero_offsets,
    )


@dataclass(frozen=True)
class _Groups:
    fit: list[Sample]
    hold: list[Sample]
    rejected: dict[str, str]  # sample id -> why its tag detection is unusable


def _partition(
    samples: list[Sample], observations: dict[str, Observation], holdout_ids: set[str] | None, options: FitOptions
) -> _Groups:
    """Samples without a usable detection are rejected first, so the hold-out share is of the usable
    ones; fewer than 3 left to fit is refused with the most common detection failure, which is
    almost always the reason (a wrong tag family, id or size in dataset.yaml)."""
    rejected = {s.id: observations[s.id].reason for s in samples if observations[s.id].corners_px is None}
    usable = [s for s in samples if s.id not in rejected]
    if holdout_ids is None:
        holdout_ids = split_holdout([s.id for s in usable], options.holdout, options.seed)
    fit = [s for s in usable if s.id not in holdout_ids]
    hold = [s for s in usable if s.id in holdout_ids]
    if len(fit) < 3:
        common = Counter(rejected.values()).most_common(1)
        why = f"; most images: {common[0][0]} ({common[0][1]} of {len(rejected)})" if common else ""
        raise ArmtoolError(
            f"only {len(fit)} sample(s) with a detected tag to fit{why}",
            hint="check target (family/id/size_m, or board) in dataset.yaml and the images with `armtool calibrate check`",
        )
    return _Groups(fit, hold, rejected)


def _arrays(group: list[Sample], observations: dict[str, Observation], joints: int) -> tuple[Array, Array]:
    """Joint readings (N, n) and detected corners (N, P, 2) of samples that all have a detection."""
    if not group:
        return np.zeros((0, joints)), np.zeros((0, 4, 2))
    return np.stack([s.q for s in group]), np.stack([observations[s.id].corners_px for s in group])  # type: ignore[misc]


def _motion_warnings(model: CalibModel, Q: Array, options: FitOptions) -> list[str]:
    """A joint that barely moved leaves its parameters to noise: say so before the numbers mislead."""
    out = []
    for name, m in zip(model.chain.joint_names, Q.max(axis=0) - Q.min(axis=0)):
        if m < options.min_motion_rad:
            out.append(
                f"joint '{name}' moved only {math.degrees(m):.1f}° over the poses: its parameters are poorly determined; "
                "move every joint over a wide range (60° or more)"
            )
    return out


def _check_identified(model: CalibModel, ident: Identifiability, candidates: list[int], options: FitOptions) -> None:
    """Refuse a fit whose measurement frames the poses cannot separate (every other number would
    be meaningless), and a family the user asked for by name of which nothing is identifiable."""
    lost_frames = [i for i in ident.dropped if model.params[i].kind is ParamKind.FRAME]
    if lost_frames:
        names = ", ".join(model.params[i].name for i in lost_frames)
        raise ArmtoolError(
            f"the poses cannot separate the measurement frames ({names})",
            hint="take poses with the tag at different distances and tilts, turning every joint",
        )
    if not options.families_explicit:
        return
    for fam in options.families:
        members = [i for i in candidates if model.params[i].kind is fam.kind]
        if members and all(i in ident.dropped for i in members):
            raise ArmtoolError(
                f"the dataset cannot identify any parameter of --params {fam.value}",
                where=ident.dropped[members[0]],
                hint="move the joints over wider ranges, or leave this family out",
            )


def _check_enough_data(coordinates: int, free: int, fit_samples: int) -> None:
    """At least two corner coordinates per identifiable parameter, or the fit is underdetermined in practice."""
    if coordinates < 2 * free:
        raise ArmtoolError(
            f"{fit_samples} fit samples give {coordinates} corner coordinates for {free} identifiable parameters",
            hint=f"collect at least {math.ceil(2 * free / 8)} poses (30-60 recommended), or lower --holdout",
        )


@dataclass(frozen=True)
class _RobustFit:
    x: Array
    inliers: list[int]  # rows of the fit samples still trusted
    outliers: dict[str, str]  # sample id -> why it was left out
    limit_px: float  # the outlier threshold of the last round (also applied to held-out samples)
    median_px: float  # the inliers' median corner RMS of the last round
    nfev: int


def _robust_fit(problem: Problem, x: Array, free: list[int], samples: list[Sample], options: FitOptions) -> _RobustFit:
    """Soft-L1 fit, then name the samples whose residual stands out and fit again without them
    (up to 3 rounds): a wrong joint reading or a mislabeled image must not bend the robot."""
    outliers: dict[str, str] = {}
    inliers = list(range(len(samples)))
    nfev = 0
    limit = median = math.nan
    for _round in range(3):
        x, n = _solve(problem.subset(inliers), x, free, robust=True, f_scale=options.f_scale_px)
        nfev += n
        rms_all = problem.per_sample_rms(x)
        median = float(np.median(rms_all[inliers]))
        mad = float(np.median(np.abs(rms_all[inliers] - median)))
        limit = max(options.outlier_floor_px, median + options.outlier_spread * 1.4826 * mad)
        new = [k for k in inliers if rms_all[k] > limit]
        if not new:
            break
        for k in new:
            s = samples[k]
            outliers[s.id] = (
                f"residual {rms_all[k]:.1f} px RMS against a median of {median:.2f} px (row {s.row}: wrong joint reading or mislabeled image?)"
            )
        inliers = [k for k in inliers if k not in new]
        if problem.subset(inliers).coordinates < 2 * len(free):
            raise ArmtoolError(
                f"{len(outliers)} of {len(samples)} samples disagree with the model",
                hint="check the joint readings and image names in samples.csv",
            )
    return _RobustFit(x, inliers, outliers, limit, median, nfev)


def _sigma(problem: Problem, x: Array, free: list[int]) -> Array:
    """1-σ of each free parameter from the residual variance and the Gauss-Newton covariance."""
    J = problem.jacobian(x, free)
    r = problem.residuals(x)
    s2 = float(r @ r) / max(1, r.size - len(free))
    try:
        sigma: Array = np.sqrt(np.maximum(np.diag(s2 * np.linalg.inv(J.T @ J)), 0.0))
    except np.linalg.LinAlgError:
        sigma = np.full(len(free), math.nan)
    return sigma


@dataclass(frozen=True)
class _HeldOut:
    residuals: list[SampleResidual]
    outliers: dict[str, str]
    warnings: list[str]
    before: Array  # corner RMS per held-out sample, hand-eye only
    after: Array  # … calibrated
    kept: NDArray[np.bool_]  # mask of the held-out samples that are not outliers


def _score_holdout(
    problem: Problem,
    hold: list[Sample],
    observations: dict[str, Observation],
    x_he: Array,
    x: Array,
    robust: _RobustFit,
) -> _HeldOut:
    """Corner RMS of the held-out samples before and after. A bad held-out sample would make the
    validation look worse than the calibration is: the same rule as for fit samples names it and
    leaves it out of the held-out metrics."""
    if not hold:
        return _HeldOut([], {}, [], np.zeros(0), np.zeros(0), np.zeros(0, dtype=bool))
    Qh, uvh = _arrays(hold, observations, problem.model.chain.n)
    hp = Problem(problem.model, problem.camera, Qh, uvh, problem.tag_points)
    before, after = hp.per_sample_rms(x_he), hp.per_sample_rms(x)
    keep = ~(after > robust.limit_px)  # as for fit samples: only a residual above the limit is an outlier
    outliers: dict[str, str] = {}
    residuals: list[SampleResidual] = []
    for k, s in enumerate(hold):
        if not keep[k]:
            outliers[s.id] = (
                f"held-out residual {after[k]:.1f} px RMS against a median of {robust.median_px:.2f} px (row {s.row}: wrong joint reading or mislabeled image?)"
            )
        role: SampleRole = "holdout" if keep[k] else "outlier"
        residuals.append(SampleResidual(s.id, role, float(before[k]), float(after[k]), outliers.get(s.id, "")))
    warnings = []
    if (~keep).sum() * 3 > len(keep):
        warnings.append(
            f"{int((~keep).sum())} of {len(keep)} held-out samples disagree with the calibrated model: "
            "the validation poses may come from another setup, or the fit does not generalise"
        )
    return _HeldOut(residuals, outliers, warnings, before, after, keep)


def _fit_warnings(
    model: CalibModel, ident: Identifiability, free: list[int], fitted: int, options: FitOptions
) -> list[str]:
    """What the numbers cannot say by themselves: a weak pose set, too few samples, gains outside the URDF."""
    out = []
    if ident.condition_number > 1e3:
        out.append(
            f"the identification Jacobian is poorly conditioned ({ident.condition_number:.0f}): "
            "add poses with larger wrist rotations and tag tilts"
        )
    if fitted < 20:
        out.append(f"only {fitted} samples were fitted: 30-60 poses give a reliable calibration")
    if Family.GAINS in options.families and any(model.params[i].kind is ParamKind.GAIN for i in free):
        out.append(
            "joint gains were fitted: a URDF cannot hold them, so apply `gain` from calibration.yaml in the driver"
        )
    return out


def _rms(values: Array) -> float:
    return float(np.sqrt(np.mean(values**2))) if values.size else math.nan
