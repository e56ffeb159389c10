"""The calibration itself: start with hand-eye only, choose what to fit, fit it, reject outliers.

`calibrate` runs these steps, one function each, for every kind of measurement (tag or board
corners in pixels, measured poses, measured points; see `problems`):
1. Samples without a usable measurement are rejected, the hold-out set is put aside (`_partition`).
2. A closed form starts the two measurement frames (`Problem.start_frames`).
3. Hand-eye-only fit (frames free, nominal robot), re-weighted until each block's noise settles
   (`_settle`, `noise`): the "before" that hand-eye tools give.
4. Identifiability of the requested parameters on the fit poses (`identify.analyse`); a fit that
   cannot separate the frames, or lacks data, is refused (`_check_identified`, `_check_enough_data`).
5. Which parameter set to fit: the ladder's candidates are scored by k-fold cross-validation and
   the smallest within one standard error of the best held-out score is chosen (`crossval`);
   nested, the figure reported is that of the whole procedure on poses it never saw. The folds
   and the ladder's full fits are fitted on linearised problems (`linearized`, `_full_ladder`),
   the chosen set then on the real model.
6. Robust fit (soft-L1) of the chosen set's identifiable parameters; samples whose residual
   stands out are named and removed (`fit_set`); then plain Levenberg–Marquardt on the inliers,
   the noise re-estimated, and the parameters' σ (`_sigma`).
7. Which zero offsets are physical (`zero_offsets.analyse_offsets`), the held-out samples scored
   by the same outlier rule (`_score_holdout`) and what the numbers cannot say (`_fit_warnings`);
   whether the calibration beats the nominal robot at all is `verdict.judge`'s, from the result.
The Jacobian: the residuals' central differences along the six twists of the measured pose,
times each parameter's twist (`Problem.jacobian`, `CalibModel.twists`).
"""

from __future__ import annotations

import logging
import math
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from armtool.calib.choices import Criterion, SampleRole
from armtool.calib.fit import noise
from armtool.calib.fit.crossval import (
    HAND_EYE,
    Candidate,
    CandidateFit,
    CrossValidation,
    FitLadder,
    _rms,
    cross_validate,
    ladder,
    pose_groups,
    repeats_for,
)
from armtool.calib.fit.determined import DEFAULT_PRECISION, Precision, Subspace, determined
from armtool.calib.fit.flange_gauge import FlangeGauge, nearest_nominal_flange
from armtool.calib.fit.holdout import holdout_ids
from armtool.calib.fit.identify import Identifiability, analyse, restricted
from armtool.calib.fit.linearized import LinearizedProblem
from armtool.calib.fit.measurements import Measurements
from armtool.calib.fit.problems import CORNER, Block, Problem
from armtool.calib.fit.zero_offsets import ZeroOffset, analyse_offsets
from armtool.calib.inputs.dataset import Sample
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.params import Family, ParamKind, parse_families
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError

log = logging.getLogger(__name__)

ROBUST_ROUNDS = 3  # outlier rounds: fit, name the samples that stand out, fit again without them
ROBUST_FTOL = 1e-4  # the robust rounds judge residuals: their cost settles long before a flat valley ends


@dataclass(frozen=True)
class FitOptions:
    families: tuple[Family, ...] = (Family.ORIGINS, Family.OFFSETS)
    families_explicit: bool = False  # the user named them with --params: refuse to silently drop all
    holdout: float = 0.0
    seed: int = 0
    # Pixel measurements keep the thresholds measured for tag corners (0.07 px typical noise):
    f_scale_px: float = 0.5  # soft-L1 knee: residuals beyond it count less than quadratically
    # A sample is an outlier when its residual RMS exceeds max(floor, median + spread × 1.4826·MAD)
    # of the inliers: a robust z-score, so a 5° reading error that the robust fit half absorbed
    # (0.6-2 px against 0.1 px for good samples) still stands out, while noisy images raise the bar.
    outlier_floor_px: float = 0.5
    outlier_spread: float = 8.0
    # Pose and point measurements have no pixel scale: their knee and floor are in estimated σ's.
    knee_sigma: float = 3.0
    outlier_floor_sigma: float = 3.0
    qr_tolerance: float = 1e-6
    min_motion_rad: float = math.radians(20)
    folds: int = 5  # k-fold cross-validation of the parameter sets; below 2: none
    select: bool = True  # fit the set that cross-validation chooses (False: the requested families)
    nested: bool = True  # report the held-out residual of the whole procedure, selection included
    precision: Precision = DEFAULT_PRECISION  # combinations determined worse than this are held at nominal
    criterion: Criterion = Criterion.COMBINED  # what chooses the parameter set on held-out poses
    repeats: int = 0  # k-fold partitions the choice pools (0: `crossval.repeats_for` the pose count)
    # Joint terms the k-fold ladder also tries when --params was not given (`tried_families`):
    tried: tuple[Family, ...] = (Family.COMPLIANCE, Family.HARMONICS)

    @property
    def hand_eye_only(self) -> bool:
        """`--params none`: only the measurement frames, the robot held nominal (asked for, not a verdict)."""
        return not self.families

    def tried_families(self, model: CalibModel, fit_samples: int) -> tuple[Family, ...]:
        """The ladder's families: those requested, then, when the k-fold chooses (the default
        --params, folds, selection on), the joint terms of `tried` that `model` carries. Why: a
        compliance or harmonic term is physical only where the data ask for it, and only poses a fit
        never saw can say so; the same one-standard-error rule as every other rung keeps it or not.
        A plain fit (`--folds 0`, `--no-select`) fits what was requested and nothing more."""
        if self.families_explicit or not self.select or self.folds < 2 or fit_samples < 2 * self.folds:
            return self.families
        carried = {t.family for t in model.terms}
        return self.families + tuple(f for f in self.tried if f in carried and f not in self.families)

    @classmethod
    def requested(
        cls,
        params: str | None,
        *,
        holdout: float,
        seed: int,
        folds: int,
        select: bool,
        nested: bool,
        criterion: Criterion = Criterion.COMBINED,
    ) -> FitOptions:
        """The options `calibrate fit` was given: `--params` text (None: the default families) and the others."""
        return cls(
            families=cls.families if params is None else parse_families(params),
            families_explicit=params is not None,
            holdout=holdout,
            seed=seed,
            folds=folds,
            select=select,
            nested=nested,
            criterion=criterion,
        )


@dataclass
class SampleResidual:
    sample_id: str
    role: SampleRole
    before: dict[str, float]  # per block (corner px, position mm, rotation deg) with the hand-eye-only model
    after: dict[str, float]  # … with the calibrated model
    note: str = ""
    cross_validated: dict[str, float] = field(default_factory=dict)  # … when its fold was held out (nested)


@dataclass(frozen=True)
class Comparison:
    """Hand-eye only against calibrated on a set of samples: per block, (before, after)."""

    samples: int
    rms: dict[str, tuple[float, float]]
    maximum: dict[str, tuple[float, float]]


@dataclass(frozen=True)
class TermsFit:
    """The chosen set when it fits what a URDF cannot hold (joint terms), on the same
    inliers: its own geometry and frames, which go with its terms (calibrated_with_terms.urdf and
    calibration.yaml's `joint_terms`). calibrated.urdf is then its URDF rung fitted alone: a URDF
    read without the terms must predict on its own (on the UR5 tracker data the geometry of
    origins + offsets + compliance + harmonics, read alone, missed held-out points by 4.7 mm, and
    by 0.22 mm with the terms' mean moved into its zero offsets; origins + offsets fitted alone,
    by 0.10 mm)."""

    candidate: Candidate
    x: Array
    free: list[int]
    sigma: Array  # σ per free parameter (same order as `free`)
    subspace: Subspace
    identifiability: Identifiability
    fit: Comparison  # hand-eye only against this model, on the inliers
    flange_gauge: FlangeGauge | None = None  # where the data left it free, its flange moved nearest nominal
    # (n,) rad: what gains and terms add to each reading on average over the inliers; in the
    # written URDF's zero offsets, taken off again by `calibrate apply`
    mean_correction: Array | None = None

    def urdf_x(self, model: CalibModel) -> Array:
        """calibrated_with_terms.urdf's parameters: x with the mean correction in the zero offsets."""
        out: Array = self.x.copy()
        if self.mean_correction is not None:
            model.split(out).offset[:] += self.mean_correction
        return out


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
    rejected: dict[str, str]  # sample id -> why it has no usable measurement
    blocks: tuple[Block, ...] = (CORNER,)
    noise: dict[str, float] = field(default_factory=dict)  # estimated σ per block, in the block's unit
    fit: Comparison | None = None
    holdout: Comparison | None = None
    holdout_inliers: Comparison | None = None  # without the held-out outliers
    warnings: list[str] = field(default_factory=list)
    iterations: int = 0
    zero_offsets: list[ZeroOffset] = field(default_factory=list)  # which offsets are physical encoder corrections
    candidate: Candidate = HAND_EYE  # the parameter set fitted
    candidates: list[Candidate] = field(default_factory=list)  # the ladder it was chosen from
    crossval: CrossValidation | None = None
    motion_deg: dict[str, float] = field(default_factory=dict)  # each joint's range over the fit poses
    coordinates_per_sample: float = 8.0  # measured coordinates per fit sample (8 for a tag's corners, 6 for a pose)
    fit_samples: int = 0  # samples the fit (and its cross-validation) used, outliers included
    subspace: Subspace | None = None  # the combinations of `free` the fit moved; the others held at nominal
    joint_terms: TermsFit | None = None  # the chosen set, when `candidate` is only its URDF rung (joint terms)
    flange_gauge: FlangeGauge | None = None  # where the data left the geometry free, the flange moved nearest nominal

    def fitted_frames(self, handeye: bool = False) -> tuple[Array, Array]:
        return self.model.frames(self.x_handeye if handeye else self.x)

    def block(self, name: str) -> Block:
        return next(b for b in self.blocks if b.name == name)


# -- one fit ---------------------------------------------------------------------------------


def _knee(problem: Problem, options: FitOptions) -> float:
    """The soft-L1 knee in noise-weighted units: 0.5 px for pixels (whatever their noise), 3 σ otherwise."""
    if problem.blocks == (CORNER,):
        return options.f_scale_px / float(problem.sigma[0])
    return options.knee_sigma


def _floor(problem: Problem, options: FitOptions) -> float:
    if problem.blocks == (CORNER,):
        return options.outlier_floor_px / float(problem.sigma[0])
    return options.outlier_floor_sigma


def solve(
    problem: Problem,
    x0: Array,
    free: list[int],
    robust: bool,
    knee: float = 1.0,
    max_nfev: int | None = None,
    basis: Array | None = None,
    ftol: float = 1e-8,
) -> tuple[Array, int]:
    """`free` fitted from x0 (the rest held): soft-L1 with the knee (noise-weighted units) when
    robust, else Levenberg–Marquardt; (x, function evaluations). With `basis` (len(free), d),
    `free` moves only in its span: x[free] = x0[free] + basis · z (`determined.Subspace`)."""
    B = np.eye(len(free)) if basis is None else basis

    def at(z: Array) -> Array:
        x: Array = x0.copy()
        x[free] = x0[free] + B @ z
        return x

    def fun(z: Array) -> Array:
        return problem.residuals(at(z))

    def jac(z: Array) -> Array:
        out: Array = problem.jacobian(at(z), free) @ B
        return out

    if problem.linear:
        z, steps = _solve_linear(problem.residuals(x0), jac(np.zeros(B.shape[1])), robust, knee, ftol)
        return at(z), steps
    # Every parameter is a correction of about a millimetre, a milliradian or 0.1 % of gain.
    scale = 1e-3 / np.maximum(np.linalg.norm(B, axis=0), 1e-300)
    z0 = np.zeros(B.shape[1])
    m = problem.coordinates
    if robust or m < B.shape[1]:
        res = least_squares(
            fun,
            z0,
            jac=jac,
            method="trf",
            loss="soft_l1" if robust else "linear",
            f_scale=knee,
            x_scale=scale,
            ftol=ftol,
            max_nfev=max_nfev or 200,
        )
    else:
        res = least_squares(fun, z0, jac=jac, method="lm", x_scale=scale, max_nfev=max_nfev or 400)
    return at(res.x), int(res.nfev)


def _solve_linear(r0: Array, J: Array, robust: bool, knee: float, ftol: float) -> tuple[Array, int]:
    """min over z of Σ ρ(r0 + J z) for residuals linear in z: least squares, or, robust, the same
    soft-L1 cost as `least_squares(loss="soft_l1", f_scale=knee)` minimised by iteratively
    re-weighted least squares (weights ρ' = (1 + r²/knee²)^(−1/2), which only ever lower the cost)."""
    z = _least_squares(J, -r0)
    if not robust:
        return z, 1
    cost = math.inf
    for step in range(1, 101):
        r = r0 + J @ z
        new_cost = float(np.sum(2.0 * knee**2 * (np.sqrt(1.0 + (r / knee) ** 2) - 1.0)))
        if cost - new_cost <= ftol * new_cost:
            return z, step
        cost = new_cost
        w = np.sqrt(1.0 / np.sqrt(1.0 + (r / knee) ** 2))
        z = _least_squares(J * w[:, None], -r0 * w)
    return z, 100


WELL_CONDITIONED = 1e-6  # smallest ratio of the Cholesky factor's diagonal to its largest taken as solvable so


def _least_squares(J: Array, b: Array) -> Array:
    """min |J z − b|: by the normal equations of the column-scaled J (Cholesky, one step of
    iterative refinement), unless its factor shows it nearly singular, then by an SVD (numpy's
    lstsq). Why: the folds' re-weighted steps solve thousands of rows for tens of unknowns hundreds
    of times; the normal equations take an eighth of the SVD's time there (2400 × 50: 2.6 ms
    against 23 ms, one core)."""
    from scipy.linalg import LinAlgError, cho_factor, cho_solve

    norms = np.linalg.norm(J, axis=0)
    if J.shape[0] >= J.shape[1] and norms.all():
        A = J / norms
        try:
            factor = cho_factor(A.T @ A)
        except LinAlgError:
            factor = None
        diagonal = np.abs(np.diag(factor[0])) if factor is not None else np.zeros(1)
        if factor is not None and diagonal.min() > WELL_CONDITIONED * diagonal.max():
            y = cho_solve(factor, A.T @ b)
            y = y + cho_solve(factor, A.T @ (b - A @ y))
            out: Array = y / norms
            return out
    return np.asarray(np.linalg.lstsq(J, b, rcond=None)[0], dtype=np.float64)


def _settle(
    problem: Problem,
    x: Array,
    free: list[int],
    robust: bool,
    options: FitOptions,
    rows: Sequence[int] | None = None,
    basis: Array | None = None,
) -> tuple[Problem, Array, int]:
    """Fit, re-estimate each block's noise from the residuals of `rows`, fit again, until the
    noise settles (one extra fit for a single block, whose weight does not move the solution).
    `basis`: `free` moves only in its span (see `solve`)."""
    nfev = 0
    parameters = len(free) if basis is None else int(basis.shape[1])
    # One block's weight scales the whole cost: it moves the solution only through a knee in σ's.
    scale_free = len(problem.blocks) == 1 and (not robust or problem.blocks == (CORNER,))
    for _round in range(noise.ROUNDS):
        sub = problem if rows is None else problem.subset(rows)
        x, n = solve(sub, x, free, robust, _knee(sub, options), basis=basis)
        nfev += n
        sigma = noise.estimate(problem, x, parameters, rows)
        done = scale_free or noise.settled(problem.sigma, sigma)
        problem = problem.with_sigma(sigma)
        if done:
            break
    return problem, x, nfev


@dataclass(frozen=True)
class Fitted:
    """A parameter set fitted with outlier rejection: the problem carries the settled noise."""

    problem: Problem
    x: Array
    free: list[int]
    ident: Identifiability
    subspace: Subspace  # what of `free` the data determine: the fit moved only that
    inliers: list[int]
    outliers: list[int]  # rows named as outliers, in the order found
    limit: (
        Array  # per block, the outlier limit of the last round (noise-weighted RMS; also applied to held-out samples)
    )
    nfev: int


def fit_set(
    problem: Problem,
    x0: Array,
    candidates: list[int],
    options: FitOptions,
    identify_at: Array | None = None,
    ident: Identifiability | None = None,
) -> Fitted:
    """Fit the identifiable ones of `candidates` from x0: soft-L1 rounds that name and drop the
    samples whose residual stands out (a wrong joint reading or a mislabeled image must not bend
    the robot), then plain Levenberg–Marquardt on the inliers with the noise re-estimated, moving
    only the combinations the inliers determine to `options.precision` (`determined`); the others
    stay at `identify_at`'s nominal values.

    Identifiability is judged at `identify_at` (default x0), which should be the nominal robot:
    away from it, exact redundancies (parallel axes) become near ones that pass the test and make
    the fit crawl along a flat valley (a start from a fitted smaller set gave a condition number of
    2.6e5 against 192, and 400 Levenberg–Marquardt steps against 3). `ident`: that analysis,
    when the caller has already made it (at the same point, of the same candidates).

    What is determined is judged with the noise the robust rounds measured with every
    identifiable parameter free: measured with a combination held, the error it carries would
    count as noise, make every σ larger and hold more (on a simulated SO-101 the noise came out
    0.74 px against 0.05 px, and the URDF 2 mm off). The robust rounds stop at a loose tolerance:
    along a nearly redundant combination the cost is flat and the steps creep on (200 on the UR5
    tracker data, 8 s) for residuals, all these rounds are for, that had long stopped changing."""
    at = x0 if identify_at is None else identify_at
    if ident is None:
        ident = analyse(problem.model, problem.jacobian(at, candidates), candidates, options.qr_tolerance)
    free = ident.kept
    inliers = list(range(problem.samples))
    outliers: list[int] = []
    x, nfev = x0.copy(), 0
    limit = np.full(len(problem.blocks), math.inf)
    for _round in range(ROBUST_ROUNDS):
        sub = problem.subset(inliers)
        x, n = solve(sub, x, free, robust=True, knee=_knee(sub, options), ftol=ROBUST_FTOL)
        nfev += n
        problem = problem.with_sigma(noise.estimate(problem, x, len(free), inliers))
        z = _studentized_block_rms(problem, x, free, inliers)
        median = np.median(z[inliers], axis=0)
        mad = np.median(np.abs(z[inliers] - median), axis=0)
        limit = np.maximum(_floor(problem, options), median + options.outlier_spread * 1.4826 * mad)
        new = [inliers[i] for i in np.flatnonzero((z[inliers] > limit).any(axis=1))]
        if not new:
            break
        outliers += new
        inliers = [k for k in inliers if k not in new]
        if problem.subset(inliers).coordinates < 2 * len(free):
            raise ArmtoolError(
                f"{len(outliers)} of {problem.samples} samples disagree with the model",
                hint="check the joint readings and the measurements of each sample",
            )
    kept = problem.subset(inliers)
    subspace = determined(
        problem.model, kept.jacobian(x, free), free, options.precision, kept.residuals(x), (x - at)[free]
    )
    x = subspace.project(x, at)
    problem, x, n = _settle(problem, x, free, robust=False, options=options, rows=inliers, basis=subspace.basis)
    return Fitted(problem, x, free, ident, subspace, inliers, outliers, limit, nfev + n)


def _studentized_block_rms(
    problem: Problem, x: Array, free: list[int], inliers: list[int], basis: Array | None = None
) -> Array:
    """(N, B) each sample's noise-weighted RMS per block, studentized: (I − H_gg)^(−1/2) r_g for
    each pose group g of the inliers, H the hat matrix J (JᵀJ)⁻¹ Jᵀ of what was fitted (`free`,
    or its span of `basis`). Why: a pose far from the others (an extreme joint angle, a steep
    tilt, a pose measured twice) pulls a fit of tens of parameters towards itself and hides its
    own error; its residual's spread shrinks by (I − H_gg), and undoing that puts every sample on
    the same scale. Samples left out of the fit are judged by their plain residual, as held-out
    ones are. Per block, so that a bad position is not hidden by a good rotation."""
    k = len(problem.column_blocks)
    r = problem.raw(x) * problem.weights()
    sub = problem.subset(inliers)
    J = sub.jacobian(x, free)
    if basis is not None:
        J = J @ basis
    p = J.shape[1]
    J = J.reshape(len(inliers), k, p)
    seen = sub.seen
    flat = J.reshape(-1, p)[seen.ravel()]
    A = np.linalg.pinv(flat.T @ flat)
    scaled = r.copy()
    # Groups whose rows see the same number of coordinates are done together (every lone pose of
    # a tracker or pose file at once): one batched eigendecomposition instead of one per group.
    groups = pose_groups(problem.Q[inliers])
    positions = np.arange(len(inliers) * k).reshape(len(inliers), k)  # each coordinate in sub's flat order
    buckets: dict[int, list[NDArray[np.intp]]] = {}  # per size, blocks of groups (G, size)
    single = np.array([g[0] for g in groups if len(g) == 1], dtype=np.intp)
    counts = seen[single].sum(axis=1)
    for size in np.unique(counts):
        rows = single[counts == size]
        buckets.setdefault(int(size), []).append(positions[rows][seen[rows]].reshape(len(rows), int(size)))
    for group in (g for g in groups if len(g) > 1):
        mask = seen[group].ravel()
        buckets.setdefault(int(mask.sum()), []).append(positions[group].ravel()[mask][None])
    flat_J = J.reshape(-1, p)
    flat_r = r[inliers].ravel()
    out = np.zeros_like(flat_r)
    for size, members in buckets.items():
        index = np.concatenate(members)  # (G, size)
        Jg = flat_J[index]  # (G, size, p)
        H = Jg @ A @ np.swapaxes(Jg, 1, 2)
        values, vectors = np.linalg.eigh(np.eye(size) - (H + np.swapaxes(H, 1, 2)) / 2)
        # a group that alone determines a parameter (1 − h ≈ 0) says nothing about its own error
        inverse_root = (vectors / np.sqrt(np.maximum(values, 1e-6))[:, None, :]) @ np.swapaxes(vectors, 1, 2)
        out[index] = (inverse_root @ flat_r[index][:, :, None])[:, :, 0]
    scaled[inliers] = out.reshape(len(inliers), k)
    return problem.per_block(scaled)


def _started(problem: Problem, hints: dict[str, Array]) -> Problem:
    return problem.with_model(problem.model.with_frames(*problem.start_frames(hints)))


def _candidate_fit(fitted: Fitted) -> CandidateFit:
    return CandidateFit(fitted.problem.model, fitted.x, fitted.problem.sigma, fitted.limit, fitted.subspace.dimension)


def _failed(problem: Problem, x: Array, why: str) -> CandidateFit:
    return CandidateFit(problem.model, x, problem.sigma, np.full(len(problem.blocks), math.inf), 0, why)


def fold_ladder(
    problem: Problem, full: Sequence[Fitted | ArmtoolError], options: FitOptions, start: LinearizedProblem
) -> FitLadder:
    """What cross-validation fits on each training fold (rows of `problem`): every candidate by
    `fit_set` on the residual problem linearised at its full fit (`linearized`; `start`: at the
    nominal robot), sliced to the fold's rows and started from the full fit's solution, noise and
    identifiability."""
    nominal = start.x_hat
    linear = [
        LinearizedProblem.at(problem.with_sigma(f.problem.sigma), f.x, f.free, start) if isinstance(f, Fitted) else f
        for f in full
    ]

    def fit(rows: list[int]) -> list[CandidateFit]:
        out = []
        for f, lin in zip(full, linear):
            if not isinstance(f, Fitted) or not isinstance(lin, LinearizedProblem):
                out.append(_failed(problem.subset(rows), nominal, str(f)))
                continue
            sub = lin.subset(rows)
            try:
                fitted = fit_set(sub, f.x, f.free, options, identify_at=nominal, ident=f.ident)
            except (ArmtoolError, np.linalg.LinAlgError, ValueError) as exc:
                out.append(_failed(sub, f.x, str(getattr(exc, "what", exc))))
                continue
            out.append(_candidate_fit(fitted))
        return out

    return fit


def _full_ladder(
    start: LinearizedProblem,
    candidates: list[Candidate],
    options: FitOptions,
    frames: list[int],
    requested: tuple[Identifiability, Array, list[int]],
    exact: bool = False,
) -> list[Fitted | ArmtoolError]:
    """Every candidate fitted on all the fit samples linearised at the hand-eye-only fit (`start`,
    from the Jacobian the identifiability analysis took there), each from the previous one's
    solution (each rung's identifiability read off the analysis of the largest, `requested`: its
    result, Jacobian and parameters): where the folds' problems are linearised and their fits
    start, and the start of the final fit of whichever is chosen.

    Why linearised: these fits only place the folds' linearisations (a fold's problem is the real
    one's value and Jacobian at this point, so a small error of the point moves the fold's fit by
    its square), and the chosen set is then fitted on the real model. Fitted on the real model,
    the six rungs of the default ladder took a third of the default fit's time (UR5 tracker,
    1000 poses); on the linearisation the choice, the scores and the chosen fit are the same
    (`benchmarks/calib_speed.py` compares them with `exact` fits, on the real model)."""
    out: list[Fitted | ArmtoolError] = []
    x = x_start = start.x_hat
    ident, J, columns = requested
    problem = start.base.with_sigma(start.sigma) if exact else start
    for candidate in candidates:
        indices = candidate.indices(start.model, frames)
        try:
            fitted = fit_set(
                problem, x, indices, options, identify_at=x_start, ident=restricted(ident, J, columns, indices)
            )
        except ArmtoolError as exc:
            out.append(exc)
            continue
        x = fitted.x
        out.append(fitted)
    return out


# -- the calibration ---------------------------------------------------------------------------


def calibrate(
    model: CalibModel,
    measurements: Measurements,
    samples: list[Sample],
    options: FitOptions = FitOptions(),
    hints: dict[str, Array] | None = None,
    validation_ids: set[str] | None = None,
    progress: Callable[[str], None] | None = None,
) -> CalibrationResult:
    """Fit the model to the samples' measurements; `validation_ids` (a validation dataset's
    samples) and a random `options.holdout` share of the others are kept out of the fit and only
    scored. Each step is one function."""
    with one_blas_thread():
        return _calibrate(model, measurements, samples, options, hints, validation_ids, progress)


@contextmanager
def one_blas_thread() -> Iterator[None]:
    """BLAS on one thread: the fit's matrices are small (hundreds by tens), and OpenBLAS threads
    made it 3 times slower in CPU time on a shared 2-core machine (FR3 data, 48 s against 16 s)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


def _calibrate(
    model: CalibModel,
    measurements: Measurements,
    samples: list[Sample],
    options: FitOptions,
    hints: dict[str, Array] | None,
    validation_ids: set[str] | None,
    progress: Callable[[str], None] | None,
) -> CalibrationResult:
    say = progress or (lambda _msg: None)
    hints = hints or {}
    groups = _partition(samples, measurements, validation_ids, options)
    problem = measurements.problem(model, groups.fit)
    warnings = _motion_warnings(model, problem.Q, options)

    say("initialising the measurement frames (closed form)")
    problem = _started(problem, hints)
    model = problem.model
    frames = problem.frame_parameters()

    say("hand-eye-only fit (nominal robot)")
    problem, x_start, nfev = _settle(problem, np.zeros(model.size), frames, robust=True, options=options)

    say("identifiability of the parameters")
    candidates = ladder(options.tried_families(model, len(groups.fit)))
    requested = candidates[-1].indices(model, frames)
    J_requested = problem.jacobian(x_start, requested)
    ident = analyse(model, J_requested, requested, options.qr_tolerance)
    _check_identified(model, ident, requested, options)
    cross = options.folds >= 2 and len(candidates) > 1
    if cross and len(groups.fit) < 2 * options.folds:
        cross = False
        warnings.append(
            f"{len(groups.fit)} fit samples are too few for {options.folds}-fold cross-validation: "
            "the requested parameters were fitted without checking that they generalise"
        )
    asked = ladder(options.families)
    kept, note = affordable(asked, model, frames, ident, problem.coordinates, len(groups.fit), cross, options)
    if len(kept) == len(asked) < len(candidates):  # the tried joint terms where the poses allow them, unannounced
        kept, _ = affordable(candidates, model, frames, ident, problem.coordinates, len(groups.fit), cross, options)
    candidates = kept
    warnings += note

    chosen, crossval = candidates[-1], None
    if cross and len(candidates) > 1:
        say("fitting every parameter set on all fit samples (linearised)")
        start = LinearizedProblem.at_nominal(problem, x_start, requested, J_requested)
        full = _full_ladder(start, candidates, options, frames, (ident, J_requested, requested))
        crossval = cross_validate(
            problem,
            candidates,
            fold_ladder(problem, full, options, start),
            options.folds,
            options.seed,
            lambda p: _knee(p, options),
            nested=options.nested,
            progress=say,
            repeats=(lambda _poses: options.repeats) if options.repeats else repeats_for,
            criterion=options.criterion,
        )
        if options.select:
            chosen = crossval.chosen
        rung = chosen.urdf_rung(candidates)
        say(f"fitting {chosen.name} (robust)")
        fitted = _exact(problem, full, candidates, chosen, options, x_start)
        with_terms = None if rung == chosen else fitted
        if with_terms is not None:
            say(f"fitting {rung.name} alone for calibrated.urdf")
            fitted = (
                _exact(problem, full, candidates, rung, options, x_start)
                if rung in candidates
                else fit_set(problem, x_start, frames, options)
            )
    else:
        say(f"fitting {chosen.name} (robust)")
        candidate_indices = chosen.indices(model, frames)
        known = ident if candidate_indices == requested else None  # the analysis above, at x_start too
        fitted = fit_set(problem, x_start, candidate_indices, options, ident=known)
        rung = chosen.urdf_rung(candidates)
        with_terms = None if rung == chosen else fitted
        if with_terms is not None:
            say(f"fitting {rung.name} alone for calibrated.urdf")
            fitted = fit_set(problem, x_start, rung.indices(model, frames), options)
    chosen_terms = chosen
    chosen = rung
    candidate_indices = chosen.indices(model, frames)
    say("the flange nearest the nominal arm's, where the data leave the geometry free")
    fitted, gauge = _nearest_nominal_flange(fitted, candidate_indices, options)
    terms_gauge = None
    if with_terms is not None:
        with_terms, terms_gauge = _nearest_nominal_flange(with_terms, chosen_terms.indices(model, frames), options)
    problem, x, free = fitted.problem, fitted.x, fitted.free
    nfev += fitted.nfev

    say("hand-eye-only fit on the inliers")
    final = problem.subset(fitted.inliers)
    x_he, n = solve(final, x_start, frames, robust=False)
    nfev += n
    sigma = _sigma(final, x, free, fitted.subspace.basis)

    say("which zero offsets the data determines")
    zero_offsets = (
        analyse_offsets(
            model,
            final.jacobian(x, candidate_indices),
            candidate_indices,
            fitted.ident,
            x,
            dict(zip(free, (float(v) for v in _sigma(final, x, free)))),  # an encoder zero's own σ, nothing held
        )
        if not chosen.is_nominal
        else []
    )
    before, after = problem.per_sample(x_he), problem.per_sample(x)
    typical = {b.name: float(np.median(after[b.name][fitted.inliers])) for b in problem.blocks}
    outliers = {
        groups.fit[k].id: _outlier_note(problem, _row(after, k), typical, groups.fit[k], "residual")
        for k in fitted.outliers
    }
    cv_figures = crossval.nested.per_sample if crossval and crossval.nested else {}
    residuals = [
        SampleResidual(
            s.id,
            "outlier" if s.id in outliers else "fit",
            _row(before, k),
            _row(after, k),
            outliers.get(s.id, ""),
            _row(cv_figures, k) if cv_figures else {},
        )
        for k, s in enumerate(groups.fit)
    ]
    held = _score_holdout(measurements, model, problem, groups.hold, x_he, x, fitted, typical)
    outliers.update(held.outliers)
    residuals += held.residuals
    warnings += held.warnings
    residuals += [SampleResidual(sid, "rejected", {}, {}, why) for sid, why in groups.rejected.items()]
    terms_fit = None
    if with_terms is not None:
        terms_fit = replace(_terms_fit(chosen_terms, with_terms, x_he), flange_gauge=terms_gauge)
        warnings += _fit_warnings(model, with_terms.ident, with_terms.free, len(with_terms.inliers), options)
        warnings += _unphysical_stiffness(model, terms_fit.x, dict(zip(terms_fit.free, map(float, terms_fit.sigma))))
    else:
        warnings += _fit_warnings(model, fitted.ident, free, len(fitted.inliers), options)
    Q = problem.Q
    return CalibrationResult(
        model=model,
        x=x,
        x_handeye=x_he,
        free=free,
        sigma=sigma,
        identifiability=fitted.ident,
        subspace=fitted.subspace,
        joint_terms=terms_fit,
        flange_gauge=gauge,
        residuals=residuals,
        outliers=outliers,
        rejected=groups.rejected,
        blocks=problem.blocks,
        noise=problem.noise(),
        fit=_comparison(problem.blocks, before, after, fitted.inliers),
        holdout=held.all,
        holdout_inliers=held.inliers,
        warnings=warnings,
        iterations=nfev,
        zero_offsets=zero_offsets,
        candidate=chosen,
        candidates=candidates,
        crossval=crossval,
        motion_deg={name: math.degrees(float(m)) for name, m in zip(model.chain.joint_names, np.ptp(Q, axis=0))},
        coordinates_per_sample=problem.coordinates / max(problem.samples, 1),
        fit_samples=problem.samples,
    )


def _exact(
    problem: Problem,
    full: list[Fitted | ArmtoolError],
    candidates: list[Candidate],
    candidate: Candidate,
    options: FitOptions,
    x_start: Array,
) -> Fitted:
    """A candidate fitted on the real model, from its fit on the linearisation (`_full_ladder`),
    or that fit's error raised."""
    picked = full[candidates.index(candidate)]
    if isinstance(picked, ArmtoolError):
        raise picked
    return fit_set(problem, picked.x, picked.free, options, identify_at=x_start, ident=picked.ident)


def _nearest_nominal_flange(fitted: Fitted, candidates: list[int], options: FitOptions) -> tuple[Fitted, FlangeGauge]:
    """`fitted` with its flange nearest the nominal arm's where its inliers leave the geometry free (`flange_gauge`)."""
    x, gauge = nearest_nominal_flange(fitted.problem.subset(fitted.inliers), fitted.x, candidates, options.precision)
    return replace(fitted, x=x), gauge


def _terms_fit(candidate: Candidate, fitted: Fitted, x_he: Array) -> TermsFit:
    """The chosen set with its joint terms, as its own fit left it (its inliers, its noise)."""
    final = fitted.problem.subset(fitted.inliers)
    sigma = _sigma(final, fitted.x, fitted.free, fitted.subspace.basis)
    before, after = fitted.problem.per_sample(x_he), fitted.problem.per_sample(fitted.x)
    comparison = _comparison(fitted.problem.blocks, before, after, fitted.inliers)
    mean = fitted.problem.model.mean_correction(fitted.x, final.Q)
    return TermsFit(candidate, fitted.x, fitted.free, sigma, fitted.subspace, fitted.ident, comparison, None, mean)


def _row(figures: dict[str, Array], k: int) -> dict[str, float]:
    return {name: float(values[k]) for name, values in figures.items()}


def _describe(problem: Problem, figures: dict[str, float], digits: int = 1) -> str:
    """'1.2 px RMS' or '7.41 mm, 0.91°'."""
    parts = []
    for block in problem.blocks:
        value = figures[block.name]
        if block.unit == "px":
            parts.append(f"{value:.{digits}f} px RMS")
        else:
            parts.append(f"{value:.2f}°" if block.unit == "deg" else f"{value:.2f} {block.unit}")
    return ", ".join(parts)


def _outlier_note(
    problem: Problem, mine: dict[str, float], typical: dict[str, float], sample: Sample, what: str
) -> str:
    """'residual 1.2 px RMS against a median of 0.08 px (row 7: wrong joint reading or mislabeled image?)'."""
    cause = (
        "wrong joint reading or mislabeled image?"
        if problem.blocks == (CORNER,)
        else "wrong joint reading or a bad measurement?"
    )
    median = _describe(problem, typical, digits=2).replace(" RMS", "")
    return f"{what} {_describe(problem, mine)} against {'the fit' + chr(39) + 's' if what.startswith('held') else 'a'} median of {median} (row {sample.row}: {cause})"


def _comparison(
    blocks: tuple[Block, ...],
    before: dict[str, Array],
    after: dict[str, Array],
    rows: Sequence[int] | NDArray[np.bool_],
) -> Comparison:
    idx = np.asarray(rows)
    rms, maximum = {}, {}
    for b in blocks:
        pb, pa = before[b.name][idx], after[b.name][idx]
        rms[b.name] = (_rms(pb), _rms(pa))
        maximum[b.name] = (float(pb.max()) if pb.size else math.nan, float(pa.max()) if pa.size else math.nan)
    count = int(idx.sum()) if idx.dtype == bool else len(idx)
    return Comparison(count, rms, maximum)


@dataclass(frozen=True)
class _Groups:
    fit: list[Sample]
    hold: list[Sample]
    rejected: dict[str, str]  # sample id -> why it has no usable measurement


def _partition(
    samples: list[Sample], measurements: Measurements, validation_ids: set[str] | None, options: FitOptions
) -> _Groups:
    """Samples without a usable measurement are rejected first, so the hold-out share is of the
    usable ones; fewer than 3 left to fit is refused with the most common reason, which is almost
    always the cause (a wrong tag family, id or size in dataset.yaml; ids that do not match)."""
    rejected = {s.id: why for s in samples if (why := measurements.reason(s.id)) is not None}
    usable = [s for s in samples if s.id not in rejected]
    held = holdout_ids([s.id for s in usable], options.holdout, options.seed, validation_ids)
    fit = [s for s in usable if s.id not in held]
    hold = [s for s in usable if s.id in held]
    if len(fit) < 3:
        common = Counter(rejected.values()).most_common(1)
        why = f"; most samples: {common[0][0]} ({common[0][1]} of {len(rejected)})" if common else ""
        raise ArmtoolError(
            f"only {len(fit)} sample(s) with a usable measurement to fit{why}",
            hint="check the target (family/id/size_m, or board) or the observations in dataset.yaml with `armtool calibrate check`",
        )
    return _Groups(fit, hold, rejected)


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
            hint="take poses at different distances and tilts, turning every joint",
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


MIN_COORDINATES_PER_PARAMETER = 2  # the minimum-pose rule


def affordable(
    candidates: list[Candidate],
    model: CalibModel,
    frames: list[int],
    ident: Identifiability,
    coordinates: int,
    fit_samples: int,
    cross: bool,
    options: FitOptions,
) -> tuple[list[Candidate], list[str]]:
    """The minimum-pose rule: a parameter set is fitted only to at least two measured coordinates
    per parameter it identifies (a pose measures 6, a point 3, a tag's corners 8), counted on the
    smallest training fold when cross-validation chooses (k − 1 of k folds). The ladder's sets that
    break it are left out, with a warning that says how many poses would allow them; when
    `--no-select` asked for one of them, or not even hand-eye only meets it, the fit is refused."""
    kept = set(ident.kept)
    per_sample = coordinates / max(fit_samples, 1)
    share = (options.folds - 1) / options.folds if cross else 1.0
    available = math.floor(coordinates * share)
    counts = [sum(1 for i in c.indices(model, frames) if i in kept) for c in candidates]
    fits = [c for c, n in zip(candidates, counts) if MIN_COORDINATES_PER_PARAMETER * n <= available]
    where = f"{available} in each training fold, " if cross else ""

    def poses_for(n: int) -> int:
        return math.ceil(MIN_COORDINATES_PER_PARAMETER * n / per_sample / share)

    if len(fits) == len(candidates):
        return candidates, []
    largest = counts[-1]
    if not fits or not options.select:
        n = counts[len(fits)] if not fits else largest
        hint = f"collect at least {poses_for(n)} poses (30-60 recommended)"
        if options.holdout > 0:
            hint += ", or lower --holdout"
        raise ArmtoolError(
            f"{fit_samples} fit samples give {coordinates} measured coordinates ({where}two are needed per parameter) "
            f"for {n} identifiable parameters",
            hint=hint,
        )
    left = [c.name for c in candidates[len(fits) :]]
    return fits, [
        f"{fit_samples} fit samples give {coordinates} measured coordinates ({where}two are needed per parameter): "
        f"{', '.join(left)} ({largest} parameters) left out of the choice; about {poses_for(largest)} poses would allow it"
    ]


def _sigma(problem: Problem, x: Array, free: list[int], basis: Array | None = None) -> Array:
    """1-σ of each free parameter from the (noise-weighted) residual variance and the Gauss-Newton
    covariance; with `basis`, of the fit that moved `free` only in its span (the combinations
    held at nominal contribute nothing), else as if every parameter of `free` had been fitted."""
    B = np.eye(len(free)) if basis is None else basis
    J = problem.jacobian(x, free) @ B
    r = problem.residuals(x)
    s2 = float(r @ r) / max(1, problem.coordinates - B.shape[1])
    try:
        covariance = B @ (s2 * np.linalg.inv(J.T @ J)) @ B.T
        sigma: Array = np.sqrt(np.maximum(np.diag(covariance), 0.0))
    except np.linalg.LinAlgError:
        sigma = np.full(len(free), math.nan)
    return sigma


@dataclass(frozen=True)
class _HeldOut:
    residuals: list[SampleResidual]
    outliers: dict[str, str]
    warnings: list[str]
    all: Comparison | None
    inliers: Comparison | None


def _score_holdout(
    measurements: Measurements,
    model: CalibModel,
    fitted_problem: Problem,
    hold: list[Sample],
    x_he: Array,
    x: Array,
    fitted: Fitted,
    typical: dict[str, float],
) -> _HeldOut:
    """Residuals of the held-out samples before and after. A bad held-out sample would make the
    validation look worse than the calibration is: the same rule as for fit samples names it and
    leaves it out of the held-out metrics."""
    if not hold:
        return _HeldOut([], {}, [], None, None)
    hp = measurements.problem(model, hold).with_sigma(fitted_problem.sigma)
    r = hp.raw(x)
    before, after = hp.per_sample(x_he), hp.figures(r)
    keep = ~hp.outliers(r, fitted.limit)  # as for fit samples: only a residual above the limit is an outlier
    outliers: dict[str, str] = {}
    residuals: list[SampleResidual] = []
    for k, s in enumerate(hold):
        if not keep[k]:
            outliers[s.id] = _outlier_note(hp, _row(after, k), typical, s, "held-out residual")
        role: SampleRole = "holdout" if keep[k] else "outlier"
        residuals.append(SampleResidual(s.id, role, _row(before, k), _row(after, k), outliers.get(s.id, "")))
    warnings = []
    if (~keep).sum() * 3 > len(keep):
        warnings.append(
            f"{int((~keep).sum())} of {len(keep)} held-out samples disagree with the calibrated model: "
            "the validation poses may come from another setup, or the fit does not generalise"
        )
    everything = np.ones(len(hold), dtype=bool)
    return _HeldOut(
        residuals,
        outliers,
        warnings,
        _comparison(hp.blocks, before, after, everything),
        _comparison(hp.blocks, before, after, keep) if keep.any() else None,
    )


UNPHYSICAL_SIGMAS = 2.0  # a sag this many σ below zero is not noise


def _unphysical_stiffness(model: CalibModel, x: Array, sigma: dict[int, float]) -> list[str]:
    """A joint that yields against gravity: a fitted sag (τmax / k) below zero by more than 2 σ,
    a negative stiffness. No joint does that, so the term stands in for something else, and the
    report says so rather than write it as a stiffness. Seen on the real UR5 tracker data (1000
    poses, origins + offsets + compliance): the elbow −33 ± 4 kN·m/rad beside a shoulder of
    +37 ± 2. Neither UR's published inertials nor a tool's mass flip it; the grid keeps the tool's
    tilt, so the elbow's sag stands in for an error of wrist 1 periodic in its angle, and with
    harmonics fitted no elbow sag is determined (docs/calibrate.md, "Beyond geometry")."""
    out = []
    for i, p in enumerate(model.params):
        s = sigma.get(i, math.nan)
        if p.kind is ParamKind.COMPLIANCE and math.isfinite(s) and x[i] < -UNPHYSICAL_SIGMAS * s:
            out.append(
                f"{p.name}: the fitted compliance is negative ({x[i] / s:.1f} σ below zero), a joint yielding "
                "against gravity: not a physical stiffness. It stands in for another pose-dependent error, often one "
                "periodic in a joint's angle (fit --params origins,offsets,compliance,harmonics; if the poses tie "
                "joints together, as a grid that keeps the tool's tilt does, vary them apart to measure a stiffness)"
            )
    return out


def _fit_warnings(
    model: CalibModel, ident: Identifiability, free: list[int], fitted: int, options: FitOptions
) -> list[str]:
    """What the numbers cannot say by themselves: a weak pose set, too few samples, gains outside the URDF."""
    out = []
    if ident.condition_number > 1e3:
        out.append(
            f"the identification Jacobian is poorly conditioned ({ident.condition_number:.0f}): "
            "add poses with larger wrist rotations and target tilts"
        )
    if fitted < 20:
        out.append(f"only {fitted} samples were fitted: 30-60 poses give a reliable calibration")
    if Family.GAINS in options.families and any(model.params[i].kind is ParamKind.GAIN for i in free):
        out.append(
            "joint gains were fitted: a URDF cannot hold them, so apply `gain` from calibration.yaml in the driver"
        )
    return out
