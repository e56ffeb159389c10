"""The calibration itself: start with hand-eye only, find what is identifiable, fit, reject outliers.

1. PnP per image and a closed-form AX = XB give the two measurement frames.
2. Hand-eye-only fit (frames free, nominal robot): the "before" that hand-eye tools give.
3. Identifiability of every candidate parameter on the fit poses (`identify.analyse`).
4. Robust fit (soft-L1 on corner reprojection) of the identifiable set; samples whose residual
   stands out are named and removed; then a plain Levenberg–Marquardt polish on the inliers.
Residuals are corner reprojection errors in pixels; the Jacobian is by central differences on
the model, which is smooth, and costs a few tens of ms.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from armtool.calib import se3
from armtool.calib.camera import CameraModel
from armtool.calib.dataset import Sample
from armtool.calib.identify import Identifiability, analyse
from armtool.calib.model import CalibModel, Family, Setup
from armtool.calib.observations import Observation
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
    role: str  # "fit", "holdout", "outlier", "rejected"
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
    """Residuals and Jacobian for one set of samples."""

    def __init__(self, model: CalibModel, camera: CameraModel, Q: Array, uv: Array, tag_points: Array) -> None:
        self.model, self.camera, self.Q, self.uv, self.tag_points = model, camera, Q, uv, tag_points

    def predict(self, x: Array, Q: Array | None = None) -> Array:
        Q = self.Q if Q is None else Q
        pts = self.model.corners_in_camera(x, Q, self.tag_points).reshape(-1, 3)
        return self.camera.project(pts).reshape(len(Q), 4, 2)

    def residuals(self, x: Array) -> Array:
        return (self.predict(x) - self.uv).ravel()

    def jacobian(self, x: Array, free: Sequence[int], h: float = 1e-6) -> Array:
        J = np.empty((self.uv.size, len(free)))
        for col, i in enumerate(free):
            xp, xm = x.copy(), x.copy()
            xp[i] += h
            xm[i] -= h
            J[:, col] = (self.residuals(xp) - self.residuals(xm)) / (2 * h)
        return J

    def per_sample_rms(self, x: Array) -> Array:
        r = (self.predict(x) - self.uv).reshape(len(self.Q), 8)
        rms: Array = np.sqrt((r**2).mean(axis=1))
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
    model: CalibModel, camera: CameraModel, Q: Array, uv: Array, size_m: float, hints: dict[str, Array]
) -> tuple[Array, Array]:
    from armtool.calib.apriltag import pnp_pose
    from armtool.calib.handeye import initial_frames

    F = model.flange(np.zeros(model.size), Q)
    flanges, tags = [], []
    for i in range(len(Q)):
        cMt, _rms, ambiguous = pnp_pose(uv[i], size_m, camera)
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


def split_holdout(ids: list[str], fraction: float, seed: int) -> set[str]:
    if fraction <= 0:
        return set()
    if not fraction < 1:
        raise ArmtoolError(f"--holdout {fraction} leaves nothing to fit", hint="use a fraction such as 0.3")
    rng = np.random.default_rng(seed)
    count = int(round(fraction * len(ids)))
    return set(rng.choice(ids, size=count, replace=False).tolist()) if count else set()


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
) -> CalibrationResult:
    from armtool.calib.apriltag import tag_object_points

    say = progress or (lambda _msg: None)
    tag_points = tag_object_points(size_m)
    rejected = {s.id: observations[s.id].reason for s in samples if observations[s.id].corners_px is None}
    usable = [s for s in samples if s.id not in rejected]
    if holdout_ids is None:
        holdout_ids = split_holdout([s.id for s in usable], options.holdout, options.seed)
    fit_samples = [s for s in usable if s.id not in holdout_ids]
    hold_samples = [s for s in usable if s.id in holdout_ids]
    if len(fit_samples) < 3:
        from collections import Counter

        common = Counter(rejected.values()).most_common(1)
        why = f"; most images: {common[0][0]} ({common[0][1]} of {len(rejected)})" if common else ""
        raise ArmtoolError(
            f"only {len(fit_samples)} sample(s) with a detected tag to fit{why}",
            hint="check target.family/id/size_m in dataset.yaml and the images with `armtool calibrate check`",
        )

    def arrays(group: list[Sample]) -> tuple[Array, Array]:
        if not group:
            return np.zeros((0, model.chain.n)), np.zeros((0, 4, 2))
        return np.stack([s.q for s in group]), np.stack([observations[s.id].corners_px for s in group])  # type: ignore[misc]

    Q, uv = arrays(fit_samples)
    warnings: list[str] = []
    motion = Q.max(axis=0) - Q.min(axis=0)
    for name, m in zip(model.chain.joint_names, motion):
        if m < options.min_motion_rad:
            warnings.append(
                f"joint '{name}' moved only {math.degrees(m):.1f}° over the poses: its parameters are poorly determined; "
                "move every joint over a wide range (60° or more)"
            )

    say("initialising the camera and tag frames (PnP + AX=XB)")
    L0, R0 = _start_frames(model, camera, Q, uv, size_m, hints or {})
    model = model.with_frames(L0, R0)
    x0 = np.zeros(model.size)
    problem = Problem(model, camera, Q, uv, tag_points)
    frames = list(range(12))

    say("hand-eye-only fit (nominal robot)")
    x_he, nfev = _solve(problem, x0, frames, robust=True, f_scale=options.f_scale_px)

    say("identifiability of the parameters")
    candidates = model.indices(options.families)
    ident = analyse(model, problem.jacobian(x_he, candidates), candidates, options.qr_tolerance)
    lost_frames = [i for i in ident.dropped if model.params[i].kind == "frame"]
    if lost_frames:
        names = ", ".join(model.params[i].name for i in lost_frames)
        raise ArmtoolError(
            f"the poses cannot separate the measurement frames ({names})",
            hint="take poses with the tag at different distances and tilts, turning every joint",
        )
    if options.families_explicit:
        for fam in options.families:
            kind = {Family.ORIGINS: "origin", Family.OFFSETS: "offset", Family.GAINS: "gain"}[fam]
            members = [i for i in candidates if model.params[i].kind == kind]
            if members and all(i in ident.dropped for i in members):
                raise ArmtoolError(
                    f"the dataset cannot identify any parameter of --params {fam.value}",
                    where=ident.dropped[members[0]],
                    hint="move the joints over wider ranges, or leave this family out",
                )
    free = ident.kept
    if uv.size < 2 * len(free):
        raise ArmtoolError(
            f"{len(fit_samples)} fit samples give {uv.size} corner coordinates for {len(free)} identifiable parameters",
            hint=f"collect at least {math.ceil(2 * len(free) / 8)} poses (30-60 recommended), or lower --holdout",
        )

    say(f"fitting {len(free)} parameters (robust)")
    x = x_he.copy()
    outliers: dict[str, str] = {}
    inliers = list(range(len(fit_samples)))
    for _round in range(3):
        sub = Problem(model, camera, Q[inliers], uv[inliers], tag_points)
        x, n = _solve(sub, x, free, robust=True, f_scale=options.f_scale_px)
        nfev += n
        rms_all = problem.per_sample_rms(x)
        median = float(np.median(rms_all[inliers]))
        mad = float(np.median(np.abs(rms_all[inliers] - median)))
        limit = max(options.outlier_floor_px, median + options.outlier_spread * 1.4826 * mad)
        new = [k for k in inliers if rms_all[k] > limit]
        if not new:
            break
        for k in new:
            s = fit_samples[k]
            outliers[s.id] = (
                f"residual {rms_all[k]:.1f} px RMS against a median of {median:.2f} px (row {s.row}: wrong joint reading or mislabeled image?)"
            )
        inliers = [k for k in inliers if k not in new]
        if len(inliers) * 8 < 2 * len(free):
            raise ArmtoolError(
                f"{len(outliers)} of {len(fit_samples)} samples disagree with the model",
                hint="check the joint readings and image names in samples.csv",
            )

    say("final Levenberg–Marquardt on the inliers")
    final = Problem(model, camera, Q[inliers], uv[inliers], tag_points)
    x, n = _solve(final, x, free, robust=False)
    nfev += n
    x_he, n = _solve(final, x_he, frames, robust=False)
    nfev += n

    J = final.jacobian(x, free)
    r = final.residuals(x)
    dof = max(1, r.size - len(free))
    s2 = float(r @ r) / dof
    try:
        cov = s2 * np.linalg.inv(J.T @ J)
        sigma = np.sqrt(np.maximum(np.diag(cov), 0.0))
    except np.linalg.LinAlgError:
        sigma = np.full(len(free), math.nan)

    say("which zero offsets the data determines")
    zero_offsets = analyse_offsets(
        model, final.jacobian(x, candidates), candidates, ident, x, dict(zip(free, (float(v) for v in sigma)))
    )
    residuals: list[SampleResidual] = []
    before = problem.per_sample_rms(x_he)
    after = problem.per_sample_rms(x)
    for k, s in enumerate(fit_samples):
        role = "outlier" if s.id in outliers else "fit"
        residuals.append(SampleResidual(s.id, role, float(before[k]), float(after[k]), outliers.get(s.id, "")))
    hold_before = hold_after = np.zeros(0)
    keep = np.zeros(0, dtype=bool)
    if hold_samples:
        Qh, uvh = arrays(hold_samples)
        hp = Problem(model, camera, Qh, uvh, tag_points)
        hold_before, hold_after = hp.per_sample_rms(x_he), hp.per_sample_rms(x)
        # A bad held-out sample would make the validation look worse than the calibration is:
        # the same rule as for fit samples names it and leaves it out of the held-out metrics.
        keep = np.ones(len(hold_samples), dtype=bool)
        for k, s in enumerate(hold_samples):
            if hold_after[k] > limit:
                keep[k] = False
                outliers[s.id] = (
                    f"held-out residual {hold_after[k]:.1f} px RMS against a median of {median:.2f} px (row {s.row}: wrong joint reading or mislabeled image?)"
                )
            role = "holdout" if keep[k] else "outlier"
            residuals.append(
                SampleResidual(s.id, role, float(hold_before[k]), float(hold_after[k]), outliers.get(s.id, ""))
            )
        if (~keep).sum() * 3 > len(keep):
            warnings.append(
                f"{int((~keep).sum())} of {len(keep)} held-out samples disagree with the calibrated model: "
                "the validation poses may come from another setup, or the fit does not generalise"
            )
    for sid, reason in rejected.items():
        residuals.append(SampleResidual(sid, "rejected", math.nan, math.nan, reason))

    def rms(values: Array) -> float:
        return float(np.sqrt(np.mean(values**2))) if values.size else math.nan

    if ident.condition_number > 1e3:
        warnings.append(
            f"the identification Jacobian is poorly conditioned ({ident.condition_number:.0f}): "
            "add poses with larger wrist rotations and tag tilts"
        )
    if len(inliers) < 20:
        warnings.append(f"only {len(inliers)} samples were fitted: 30-60 poses give a reliable calibration")
    if options.families and Family.GAINS in options.families and any(model.params[i].kind == "gain" for i in free):
        warnings.append(
            "joint gains were fitted: a URDF cannot hold them, so apply `gain` from calibration.yaml in the driver"
        )
    kept = keep if hold_samples else np.zeros(0, dtype=bool)
    return CalibrationResult(
        model,
        x,
        x_he,
        free,
        sigma,
        ident,
        residuals,
        outliers,
        rejected,
        warnings,
        (rms(before[inliers]), rms(after[inliers])),
        (rms(hold_before), rms(hold_after)),
        nfev,
        (rms(hold_before[kept]), rms(hold_after[kept])),
        zero_offsets,
    )
