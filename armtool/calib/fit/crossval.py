"""Which parameters to fit, chosen by k-fold cross-validation, and an honest held-out residual.

Why: the fit residual always improves with more parameters; only poses a fit never saw say
whether the corrections are real. On about 20 poses, 30 parameters fitted to 16 of them
predicted the others worse than the camera frame alone. So the candidates of a ladder (hand-eye
only, zero offsets, offsets and origin rotations, all origins and offsets, gains) are each fitted
on k − 1 folds and scored on the k-th; the candidate with the lowest held-out score is chosen.

The held-out residual that is reported must not come from the folds that chose the candidate
(that would be tuned on the test poses). With `nested`, each outer training set chooses its own
candidate by an inner k-fold on itself alone, and the outer test fold scores that choice: the
figure is the whole procedure's held-out residual, selection included.

The score is the held-out samples' mean of a soft-L1 loss of their noise-weighted residual (the
noise of the fold's largest candidate, so every candidate is weighed alike): one wrong sample in a
test fold then counts about as much as a few good ones, not hundreds of times more.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from armtool.calib.choices import Criterion
from armtool.calib.fit.problems import Problem
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.params import Family, Parameter, ParamKind
from armtool.calib.model.se3 import Array
from armtool.errors import ArmtoolError


@dataclass(frozen=True)
class Candidate:
    """A parameter set of the ladder: the measurement frames plus some kinematic parameters."""

    name: str
    kinds: frozenset[str]  # "offset", "origin_rotation", "origin_translation", "gain"

    def includes(self, p: Parameter) -> bool:
        if p.kind is ParamKind.FRAME:
            return True
        if p.kind is ParamKind.ORIGIN:
            return ("origin_rotation" if p.is_rotation else "origin_translation") in self.kinds
        return p.kind.value in self.kinds

    def indices(self, model: CalibModel, frames: Sequence[int]) -> list[int]:
        """Its parameters in `model` (the frame parameters are those the measurement constrains)."""
        return [
            i for i, p in enumerate(model.params) if (i in frames if p.kind is ParamKind.FRAME else self.includes(p))
        ]

    @property
    def is_nominal(self) -> bool:
        return not self.kinds

    def urdf_rung(self, candidates: Sequence[Candidate]) -> Candidate:
        """The candidate of `candidates` that fits what of this one a URDF can hold (itself when
        it all fits in one; hand-eye only when no rung does): what calibrated.urdf is fitted as.
        Gains are not joint terms here: they stay in the fit, reported for the driver as before."""
        kinds = self.kinds - NOT_IN_URDF
        return next((c for c in candidates if c.kinds == kinds), HAND_EYE)


NOT_IN_URDF = frozenset({"compliance", "harmonic"})  # joint terms: applied to the readings, not in a URDF
HAND_EYE = Candidate("hand-eye only", frozenset())


def ladder(families: Sequence[Family]) -> list[Candidate]:
    """The candidates, smallest first, that the requested families allow: hand-eye only; zero
    offsets; offsets and origin rotations (the angular errors); all origins and offsets; gains."""
    steps: list[tuple[str, str, Family]] = [
        ("zero offsets", "offset", Family.OFFSETS),
        ("offsets + origin rotations", "origin_rotation", Family.ORIGINS),
        ("origins + offsets", "origin_translation", Family.ORIGINS),
        ("+ gains", "gain", Family.GAINS),
        ("+ compliance", "compliance", Family.COMPLIANCE),
        ("+ harmonics", "harmonic", Family.HARMONICS),
    ]
    out = [HAND_EYE]
    kinds: set[str] = set()
    for name, kind, family in steps:
        if family not in families:
            continue
        kinds.add(kind)
        label = name
        if kind == "origin_rotation" and Family.OFFSETS not in families:
            label = "origin rotations"
        if kind == "origin_translation" and Family.OFFSETS not in families:
            label = "origins"
        if kind in ("gain", "compliance", "harmonic"):  # added to the set before it
            label = f"{out[-1].name} {name}" if len(out) > 1 else name[2:]
        out.append(Candidate(label, frozenset(kinds)))
    return out


@dataclass(frozen=True)
class CandidateFit:
    """One candidate fitted on some samples: what scoring other samples needs."""

    model: CalibModel  # with the frames this fit started from
    x: Array
    sigma: Array  # the noise it estimated, per block
    limit: Array  # its outlier limit on each block's noise-weighted RMS
    parameters: int  # how many it fitted (after the identifiability analysis)
    failed: str = ""  # why it could not be fitted on these samples


FitLadder = Callable[[list[int]], list[CandidateFit]]  # every candidate fitted on some rows of the problem


@dataclass(frozen=True)
class Score:
    """A candidate's held-out residuals over every fold."""

    candidate: Candidate
    loss: float  # mean soft-L1 loss of the noise-weighted held-out residuals (what chooses)
    rms: dict[str, float]  # per block, over every held-out sample, in the block's unit
    maximum: dict[str, float]
    inlier_rms: dict[str, float]  # without the samples its training fits called outliers
    parameters: float  # mean over the folds
    mean_square: float  # mean squared noise-weighted RMS of its held-out inliers (for `verdict.poses_needed`)
    failed: int = 0  # folds on which it could not be fitted
    losses: Array = field(default_factory=lambda: np.zeros(0))  # per held-out sample, in fold order
    standard_error: float = 0.0  # of its mean loss less the best candidate's (paired over the samples)


@dataclass(frozen=True)
class Nested:
    """The held-out residual of the whole procedure (choice included), and the hand-eye model's on the same folds."""

    rms: dict[str, float]
    maximum: dict[str, float]
    inlier_rms: dict[str, float]
    inliers: int
    samples: int
    hand_eye_rms: dict[str, float]
    hand_eye_maximum: dict[str, float]
    chosen: list[str]  # per outer fold
    per_sample: dict[str, Array] = field(default_factory=dict)  # per block, in row order of the problem


@dataclass(frozen=True)
class CrossValidation:
    folds: int
    samples: int
    scores: list[Score]
    chosen: Candidate
    nested: Nested | None  # of what calibrated.urdf holds: each outer fold's choice, its URDF rung
    knee: float
    repeats: int = 1  # k-fold partitions pooled in `scores`
    criterion: Criterion = Criterion.COMBINED
    nested_terms: Nested | None = None  # with the joint terms chosen, when a fold chose any

    def score_of(self, name: str) -> Score:
        """The score of the candidate of that name (the ladder's names are distinct)."""
        return next(s for s in self.scores if s.candidate.name == name)


SAME_POSE_RAD = 1e-3  # joint readings that agree this closely are one pose measured again


def pose_groups(Q: Array, tolerance: float = SAME_POSE_RAD) -> list[list[int]]:
    """Rows of Q grouped by pose: samples whose every joint reading agrees within `tolerance` are
    the same pose measured again (a settled arm, several images). Why it matters: a repeat tells
    the fit nothing new about the kinematics, so a held-out sample whose twin was fitted is not
    held out, and two repeats of a bad pose hide each other from the outlier rule."""
    key = (Q.shape, tolerance, Q.tobytes())
    found = _GROUPS.get(key)
    if found is None:
        found = _pose_groups(Q, tolerance)
        if len(_GROUPS) >= _GROUPS_KEPT:
            _GROUPS.pop(next(iter(_GROUPS)))
        _GROUPS[key] = found
    return [list(g) for g in found]


# The groups of the last joint-reading arrays: a fit's outlier rule groups its samples in every
# round, and the cross-validation fits hundreds of times on the same few training sets.
_GROUPS: dict[tuple[tuple[int, ...], float, bytes], list[list[int]]] = {}
_GROUPS_KEPT = 64


def _pose_groups(Q: Array, tolerance: float) -> list[list[int]]:
    # Rows in order: a row that no earlier group's first row claimed starts a group and claims the
    # later rows within `tolerance` of it (each row joins the earliest such group). A k-d tree in
    # the max-norm finds them: 1000 poses took 3.4 s by pairwise comparison in Python.
    from scipy.spatial import cKDTree

    if not _any_repeat(Q, tolerance):
        return [[row] for row in range(len(Q))]
    tree = cKDTree(Q)
    group_of = np.full(len(Q), -1)
    groups: list[list[int]] = []
    near = tree.query_ball_point(Q, r=tolerance, p=np.inf)
    for row in range(len(Q)):
        if group_of[row] >= 0:
            continue
        claimed = [int(k) for k in sorted(near[row]) if k >= row and group_of[k] < 0]
        group_of[claimed] = len(groups)
        groups.append(claimed)
    return groups


def _any_repeat(Q: Array, tolerance: float) -> bool:
    """Whether two rows agree within `tolerance` in every joint: rows sorted by the first joint,
    each compared with the next ones until they are more than `tolerance` apart in it (a handful
    for poses spread over a workspace; the cost of a k-d tree is kept for when a pose is repeated)."""
    if len(Q) < 2:
        return False
    S = Q[np.argsort(Q[:, 0], kind="stable")]
    for k in range(1, len(S)):
        near = S[k:, 0] - S[:-k, 0] <= tolerance
        if not near.any():
            return False
        if (np.abs(S[k:][near] - S[:-k][near]).max(axis=1) <= tolerance).any():
            return True
    return False


def fold_rows(groups: list[list[int]], folds: int, seed: int, repeat: int = 0) -> list[list[int]]:
    """A reproducible random partition of the rows into `folds` folds of whole pose groups (the
    same partition as of single rows when no pose is repeated); `repeat` draws another one."""
    order = np.random.default_rng(seed if repeat == 0 else [seed, repeat]).permutation(len(groups))
    return [sorted(row for g in order[k::folds] for row in groups[int(g)]) for k in range(folds)]


def _loss(z2: Array, knee: float) -> Array:
    """soft-L1 of squared noise-weighted RMS values: quadratic below the knee, linear above."""
    out: Array = 2.0 * knee**2 * (np.sqrt(1.0 + z2 / knee**2) - 1.0)
    return out


@dataclass
class _Fold:
    """Held-out residuals of one fold: per candidate, per test sample."""

    test: list[int]
    fits: list[CandidateFit]
    weighted: list[Array]  # per candidate: (T,) noise-weighted RMS with the fold's reference noise
    weighted_blocks: list[Array]  # per candidate: (T, B) the same per block
    figures: list[dict[str, Array]]  # per candidate: per block (T,) figures in the block's unit
    outlier: list[Array]  # per candidate: (T,) bool, beyond its own training outlier limit


def _score_fold(problem: Problem, test: list[int], fits: list[CandidateFit]) -> _Fold:
    usable = [f for f in fits if not f.failed]
    reference = usable[-1].sigma if usable else np.ones(len(problem.blocks))
    held = problem.subset(test)
    weighted, weighted_blocks, figures, outlier = [], [], [], []
    for fit in fits:
        if fit.failed:
            weighted.append(np.full(len(test), np.inf))
            weighted_blocks.append(np.full((len(test), len(problem.blocks)), np.inf))
            figures.append({b.name: np.full(len(test), np.nan) for b in problem.blocks})
            outlier.append(np.zeros(len(test), dtype=bool))
            continue
        on_fit = held.with_model(fit.model)
        r = on_fit.raw(fit.x)
        referenced = on_fit.with_sigma(reference)
        weighted.append(referenced.normalized_rms(r))
        weighted_blocks.append(referenced.per_block(r) / reference)
        figures.append(on_fit.figures(r))
        outlier.append(on_fit.with_sigma(fit.sigma).outliers(r, fit.limit))
    return _Fold(test, fits, weighted, weighted_blocks, figures, outlier)


def _rms(values: Array) -> float:
    values = values[np.isfinite(values)]
    return float(np.sqrt(np.mean(values**2))) if values.size else math.nan


def _max(values: Array) -> float:
    values = values[np.isfinite(values)]
    return float(values.max()) if values.size else math.nan


def _criterion_z(problem: Problem, fold: _Fold, c: int, criterion: Criterion) -> Array:
    """(T,) what the choice weighs of candidate c's held-out samples in this fold: every block's
    noise-weighted RMS together, or the position block's alone."""
    if criterion is Criterion.COMBINED:
        return fold.weighted[c]
    return fold.weighted_blocks[c][:, position_block(problem)]


def position_block(problem: Problem) -> int:
    """The index of the position block (ArmtoolError for pixels, which have none)."""
    names = [b.name for b in problem.blocks]
    if "position" not in names:
        raise ArmtoolError(
            "--criterion position needs measured poses or points: corner reprojections have no position block",
            hint="leave --criterion at combined for images",
        )
    return names.index("position")


def _per_sample(values: Array, rows: NDArray[np.intp], samples: int) -> Array:
    """The mean of each sample's values over the repeats that held it out (NaN if none did)."""
    counts = np.bincount(rows, minlength=samples).astype(np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):
        out: Array = np.bincount(rows, weights=values, minlength=samples) / counts
    return out


def _scores(
    problem: Problem,
    candidates: list[Candidate],
    folds: list[_Fold],
    knee: float,
    criterion: Criterion = Criterion.COMBINED,
) -> list[Score]:
    """Each candidate's held-out score over `folds` (several repeats of a k-fold partition may be
    pooled: each sample's loss is then its mean over the repeats, so the paired standard errors
    count samples, not repeats)."""
    rows = np.concatenate([f.test for f in folds]).astype(np.intp)
    out = []
    for c, candidate in enumerate(candidates):
        z = np.concatenate([_criterion_z(problem, f, c, criterion) for f in folds])
        losses = _loss(z**2, knee) if np.isfinite(z).all() else np.full(len(z), np.inf)
        per_sample = _per_sample(losses, rows, problem.samples)
        per_sample = per_sample[~np.isnan(per_sample)]
        loss = float(np.mean(per_sample))
        rms, maximum, inlier = {}, {}, {}
        for block in problem.blocks:
            values = np.concatenate([f.figures[c][block.name] for f in folds])
            keep = ~np.concatenate([f.outlier[c] for f in folds])
            rms[block.name], maximum[block.name] = _rms(values), _max(values)
            inlier[block.name] = _rms(values[keep])
        fitted = [f.fits[c] for f in folds if not f.fits[c].failed]
        parameters = float(np.mean([f.parameters for f in fitted])) if fitted else math.nan
        failed = sum(1 for f in folds if f.fits[c].failed)
        keep = ~np.concatenate([f.outlier[c] for f in folds])
        mean_square = float(np.mean(z[keep] ** 2)) if np.isfinite(z).all() and keep.any() else math.inf
        out.append(Score(candidate, loss, rms, maximum, inlier, parameters, mean_square, failed, per_sample))
    return _with_standard_errors(out)


def _with_standard_errors(scores: list[Score]) -> list[Score]:
    """Each score with the standard error of its difference from the best, paired sample by
    sample (the same held-out samples score every candidate)."""
    from dataclasses import replace

    best = min(scores, key=lambda s: s.loss)
    out = []
    for s in scores:
        with np.errstate(invalid="ignore"):  # a candidate that failed everywhere: inf − inf
            d = s.losses - best.losses
        se = float(np.std(d, ddof=1) / math.sqrt(len(d))) if len(d) > 1 and np.isfinite(d).all() else math.inf
        out.append(replace(s, standard_error=0.0 if s is best else se))
    return out


def _choose(scores: list[Score]) -> Candidate:
    """The smallest candidate whose held-out loss is within one standard error of the lowest (the
    one-standard-error rule; Hastie, Tibshirani & Friedman, The Elements of Statistical Learning,
    §7.10): a set that only ties with a smaller one on held-out poses is not shown to be better,
    and the smaller one moves the URDF less."""
    best = min(s.loss for s in scores)
    for s in scores:  # smallest first
        if s.loss <= best + s.standard_error:
            return s.candidate
    return min(scores, key=lambda s: s.loss).candidate


REPEAT_BUDGET = 200  # held-out samples the choice pools at least: a k-fold is repeated until it has them
MAX_REPEATS = 10


def repeats_for(poses: int) -> int:
    """How often a k-fold partition is drawn to choose the parameter set: ⌈200 / poses⌉, at most
    10 (once from 200 poses on). Why: on 18 poses one split's choice flips with the seed (a
    fold of 3 or 4 poses decides); pooling ten splits scores every pose ten times."""
    return max(1, min(MAX_REPEATS, math.ceil(REPEAT_BUDGET / max(poses, 1))))


def cross_validate(
    problem: Problem,
    candidates: list[Candidate],
    fit_ladder: FitLadder,
    folds: int,
    seed: int,
    knee: Callable[[Problem], float],
    nested: bool = True,
    progress: Callable[[str], None] | None = None,
    repeats: Callable[[int], int] = repeats_for,
    criterion: Criterion = Criterion.COMBINED,
) -> CrossValidation:
    """k-fold scores of every candidate on `problem`'s samples (the k-fold repeated `repeats(poses)`
    times), the chosen candidate, and (nested) the held-out residual of choosing so on each outer
    training set alone.

    The outer folds of the nested figure are the first partition. Each outer training set chooses
    by a (k − 1)-fold cross-validation whose folds are the other outer folds (then, when repeated,
    random (k − 1)-fold partitions of it): the training set that leaves out outer folds i and j is
    then the same whether i or j is the outer one, and is fitted once (10 ladders instead of 25
    at k = 5)."""
    say = progress or (lambda _msg: None)
    if criterion is Criterion.POSITION:
        position_block(problem)  # refused at once for pixels
    groups = pose_groups(problem.Q)
    times = repeats(len(groups))
    partitions = [fold_rows(groups, folds, seed, r) for r in range(times)]
    ladders: dict[tuple[int, ...], list[CandidateFit]] = {}

    def scored(test: list[int], within: Sequence[int]) -> _Fold:
        train = tuple(sorted(set(within) - set(test)))
        if train not in ladders:
            ladders[train] = fit_ladder(list(train))
        return _score_fold(problem, test, ladders[train])

    everything = range(problem.samples)
    say(
        f"cross-validating {len(candidates)} parameter sets on {folds} folds"
        + (f", {times} times" if times > 1 else "")
    )
    outer = [scored(test, everything) for partition in partitions for test in partition]
    k = knee(problem)
    scores = _scores(problem, candidates, outer, k, criterion)
    chosen = _choose(scores)
    result_nested = nested_terms = None
    if nested:
        first = partitions[0]
        picks: list[int] = []
        for number, test in enumerate(first):
            say(f"nested cross-validation: choosing on outer training set {number + 1} of {folds}")
            train = sorted(set(everything) - set(test))
            own = [[train[i] for i in g] for g in pose_groups(problem.Q[train])]
            inner_k = max(folds - 1, 2)
            inner_partitions = [fold_rows(own, inner_k, seed + number + 1, r) for r in range(repeats(len(own)))]
            if folds >= 3:
                inner_partitions[0] = [fold for j, fold in enumerate(first) if j != number]
            inner = [scored(t, train) for partition in inner_partitions for t in partition]
            picks.append(candidates.index(_choose(_scores(problem, candidates, inner, k, criterion))))
        names = [candidates[c].name for c in picks]
        written = [candidates.index(candidates[c].urdf_rung(candidates)) for c in picks]
        result_nested = _nested(problem, outer[:folds], written, candidates, names)
        if written != picks:
            nested_terms = _nested(problem, outer[:folds], picks, candidates, names)
    return CrossValidation(folds, problem.samples, scores, chosen, result_nested, k, times, criterion, nested_terms)


def _nested(
    problem: Problem, folds: list[_Fold], picks: list[int], candidates: list[Candidate], chosen: list[str]
) -> Nested:
    """The held-out residual of each outer fold's `picks` (indices into `candidates`); `chosen`:
    what each fold chose (the same, or a set whose URDF rung `picks` is)."""
    rms, maximum, inlier, he_rms, he_max = {}, {}, {}, {}, {}
    per_sample: dict[str, Array] = {}
    keep = ~np.concatenate([f.outlier[c] for f, c in zip(folds, picks)])
    order = np.concatenate([f.test for f in folds])
    for block in problem.blocks:
        values = np.concatenate([f.figures[c][block.name] for f, c in zip(folds, picks)])
        hand_eye = np.concatenate([f.figures[0][block.name] for f in folds])
        rms[block.name], maximum[block.name], inlier[block.name] = _rms(values), _max(values), _rms(values[keep])
        he_rms[block.name], he_max[block.name] = _rms(hand_eye), _max(hand_eye)
        by_row = np.full(problem.samples, np.nan)
        by_row[order] = values
        per_sample[block.name] = by_row
    return Nested(rms, maximum, inlier, int(keep.sum()), int(keep.size), he_rms, he_max, chosen, per_sample)


def describe_choices(chosen: list[str]) -> str:
    """'origins + offsets on 4 folds, zero offsets on 1'."""
    counts = Counter(chosen)
    return ", ".join(f"{name} on {n} fold{'s' if n > 1 else ''}" for name, n in counts.most_common())
