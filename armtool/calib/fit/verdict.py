"""Whether a calibration beats the nominal robot on poses it never saw, said plainly.

Why: a fit with more parameters always lowers its own residual; held-out poses are the only
judge. When no kinematic parameter set predicts held-out poses better than the nominal robot
(hand-eye only), the corrected URDF would be worse: it is not written, `fit` exits 1 (unless
`--allow-nominal`), and the verdict says how many more poses would be needed, and of what kind.

How many: the best kinematic candidate's held-out error is extrapolated with Akaike's final
prediction error, E[held-out MSE] ≈ σ²·(1 + p/n) for p parameters fitted to n coordinates:
σ² of each candidate is read off its k-fold score at today's training size, and the pose count
at which the candidate's curve drops below the nominal model's is solved for. It is a guide (it
assumes the errors the candidate models stay what they are), and says so.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from armtool.calib.fit.crossval import CrossValidation, Score
from armtool.calib.fit.problems import CORNER, Block

WIDE_RANGE_DEG = 90.0  # a joint turned less than this over the poses leaves its parameters weakly determined


@dataclass(frozen=True)
class Verdict:
    improves: bool  # the calibrated robot predicts held-out poses better than the nominal one (or nobody checked)
    checked: bool  # cross-validation ran
    summary: str  # one sentence for the report
    advice: str = ""  # what would help, when it does not improve
    poses_needed: int | None = None  # estimated poses in all for a kinematic calibration to beat the nominal robot


def judge(
    crossval: CrossValidation | None,
    chosen_name: str,
    chosen_is_nominal: bool,
    fit_samples: int,
    coordinates_per_sample: float,
    motion_deg: dict[str, float],
    blocks: Sequence[Block] = (CORNER,),
) -> Verdict:
    """The verdict on a fit of `chosen_name` (what `calibrate` fitted) given its cross-validation."""
    if crossval is None:
        if chosen_is_nominal:
            return Verdict(False, False, "only the measurement frames were fitted: the robot's URDF is unchanged")
        return Verdict(
            True,
            False,
            f"{chosen_name} fitted without cross-validation: nothing says the corrections hold on other poses",
        )
    nominal = crossval.scores[0]
    chosen = crossval.score_of(chosen_name)
    kinematic = [s for s in crossval.scores[1:] if math.isfinite(s.loss)]
    best = min(kinematic, key=lambda s: s.loss) if kinematic else None
    k = crossval.folds
    if not chosen_is_nominal and chosen.loss < nominal.loss:
        return Verdict(
            True,
            True,
            f"{chosen_name} predicts held-out poses better than the nominal robot ({k}-fold): "
            f"{_figures(chosen, blocks)} against {_figures(nominal, blocks)} RMS with hand-eye only",
        )
    if best is None:
        return Verdict(
            False, True, "no kinematic parameter set could be fitted on the training folds", _kind(motion_deg)
        )
    if chosen_is_nominal:
        summary = (
            f"no kinematic calibration beats the nominal robot on held-out poses ({k}-fold): "
            f"the best, {best.candidate.name}, {_figures(best, blocks)} against {_figures(nominal, blocks)} RMS "
            f"with hand-eye only (score {best.loss:.3g} against {nominal.loss:.3g}, standard error {best.standard_error:.2g})"
        )
    else:
        summary = (
            f"{chosen_name} predicts held-out poses worse than the nominal robot ({k}-fold): "
            f"{_figures(chosen, blocks)} against {_figures(nominal, blocks)} RMS with hand-eye only "
            f"(score {chosen.loss:.3g} against {nominal.loss:.3g})"
        )
    needed = poses_needed(nominal, best, fit_samples, k, coordinates_per_sample)
    if needed is None:
        advice = (
            "more poses of the same kind will not help: the kinematic parameters explain nothing the nominal robot "
            "does not (its URDF may be right within the measurement noise); if the residual is well above your "
            "sensor's noise, check the joint readings and the measurements"
        )
    else:
        advice = (
            f"about {needed} poses in all ({max(needed - fit_samples, 1)} more than the {fit_samples} fitted here) "
            f"would let {best.candidate.name} beat it, by Akaike's final prediction error from these folds (a rough guide); "
            + _kind(motion_deg)
        )
    return Verdict(False, True, summary, advice, needed)


def hand_eye_verdict() -> Verdict:
    """`--params none`: hand-eye only was asked for, so the nominal robot is the answer, not a failure."""
    return Verdict(
        False,
        False,
        "hand-eye only (--params none): the measurement frames fitted with the robot held nominal; "
        "its URDF is unchanged, calibrated.urdf is not written",
    )


def poses_needed(nominal: Score, best: Score, samples: int, folds: int, per_sample: float) -> int | None:
    """Poses in all at which `best` would beat `nominal` on held-out poses, or None if never."""
    n_train = samples * (folds - 1) / folds * per_sample  # coordinates a training fold fits
    if not (math.isfinite(nominal.mean_square) and math.isfinite(best.mean_square)) or n_train <= 0:
        return None
    p0, p1 = nominal.parameters, best.parameters
    s0 = nominal.mean_square / (1.0 + p0 / n_train)
    s1 = best.mean_square / (1.0 + p1 / n_train)
    if s1 >= s0:
        return None
    coordinates = (p1 * s1 - p0 * s0) / (s0 - s1)  # where s0 (1 + p0/n) = s1 (1 + p1/n)
    fit_poses = coordinates / per_sample
    return max(samples + 1, math.ceil(fit_poses * folds / (folds - 1)))


def _figures(score: Score, blocks: Sequence[Block]) -> str:
    """'1.95 px' or '1.57 mm, 0.22°': a candidate's held-out RMS per block."""
    parts = []
    for b in blocks:
        value = score.rms.get(b.name, math.nan)
        parts.append(f"{value:.2f}°" if b.unit == "deg" else f"{value:.2f} {b.unit}")
    return ", ".join(parts)


def _kind(motion_deg: dict[str, float]) -> str:
    """What kind of poses: the joints that turned least, or the same spread as now."""
    narrow = sorted((deg, name) for name, deg in motion_deg.items() if deg < WIDE_RANGE_DEG)
    if narrow:
        listed = ", ".join(f"'{name}' (turned {deg:.0f}°)" for deg, name in narrow[:3])
        return f"take poses that turn {listed} over a wider range, with the other joints spread as now"
    return "take poses spread as these are, over every joint's range and the target's tilts"
