"""The verdict's arithmetic: when a kinematic set would overtake the nominal robot, and what to measure."""

from __future__ import annotations

import math

import numpy as np

from armtool.calib.choices import Criterion
from armtool.calib.fit.crossval import HAND_EYE, Candidate, CrossValidation, Score
from armtool.calib.fit.problems import POSITION, ROTATION
from armtool.calib.fit.verdict import _kind, judge, poses_needed


def _score(candidate: Candidate, mean_square: float, parameters: float) -> Score:
    return Score(candidate, mean_square, {}, {}, {}, parameters, mean_square, 0, np.zeros(0))


FULL = Candidate("origins + offsets", frozenset({"offset", "origin_rotation", "origin_translation"}))


def test_poses_needed_solves_the_final_prediction_error_for_the_crossing() -> None:
    # 16 training poses of 8 coordinates: the full set's held-out error is inflated by its 30
    # parameters; its noise floor is lower than the nominal model's, so enough poses overtake it.
    n = 20 * 4 / 5 * 8
    s0, s1 = 1.0, 0.95
    nominal = _score(HAND_EYE, s0 * (1 + 12 / n), 12)
    full = _score(FULL, s1 * (1 + 30 / n), 30)
    needed = poses_needed(nominal, full, samples=20, folds=5, per_sample=8.0)
    crossing = (30 * s1 - 12 * s0) / (s0 - s1) / 8  # training poses where s0(1 + 12/n) = s1(1 + 30/n)
    assert nominal.mean_square < full.mean_square  # today the nominal robot is better held out
    assert needed == math.ceil(crossing * 5 / 4) == 52


def test_no_number_of_poses_helps_a_set_that_explains_nothing() -> None:
    n = 16 * 8
    nominal = _score(HAND_EYE, 1.0 * (1 + 12 / n), 12)
    full = _score(FULL, 1.0 * (1 + 30 / n), 30)
    assert poses_needed(nominal, full, samples=20, folds=5, per_sample=8.0) is None


def test_the_joints_that_turned_least_are_named() -> None:
    text = _kind({"j1": 200.0, "j2": 12.0, "j3": 45.0})
    assert "'j2' (turned 12°), 'j3' (turned 45°)" in text and "j1" not in text
    assert "spread as these are" in _kind({"j1": 200.0, "j2": 120.0})


def _scored(candidate: Candidate, loss: float, se: float, position_mm: float, rotation_deg: float) -> Score:
    rms = {"position": position_mm, "rotation": rotation_deg}
    return Score(candidate, loss, rms, rms, rms, 30, loss, 0, np.zeros(0), se)


def _crossval(scores: list[Score], chosen: Candidate, criterion: Criterion = Criterion.COMBINED) -> CrossValidation:
    return CrossValidation(5, 23, scores, chosen, None, 3.0, 3, criterion)


def test_a_refusal_prints_the_standard_error_that_decided_it() -> None:
    # The best set's own standard error is 0 by construction; the nominal robot's (of its
    # difference from the best) is what kept it: 0.31 here, against a difference of 0.12.
    scores = [_scored(HAND_EYE, 1.30, 0.31, 4.08, 0.30), _scored(FULL, 1.18, 0.0, 3.96, 0.29)]
    verdict = judge(_crossval(scores, HAND_EYE), HAND_EYE.name, True, 18, 6.0, {}, (POSITION, ROTATION))
    assert not verdict.improves
    assert "within one standard error of the difference (0.31)" in verdict.summary
    assert "5-fold repeated 3 times, by the combined score (position and rotation, each divided by its noise)" in (
        verdict.summary
    )


def test_better_on_the_combined_score_but_worse_in_position_says_so() -> None:
    scores = [_scored(HAND_EYE, 1.30, 0.4, 4.08, 0.50), _scored(FULL, 1.00, 0.0, 4.20, 0.20)]
    verdict = judge(_crossval(scores, FULL), FULL.name, False, 23, 6.0, {}, (POSITION, ROTATION))
    assert verdict.improves
    assert "worse held out in position 4.20 mm against 4.08 mm" in verdict.summary
    assert "pass --criterion position" in verdict.summary
    by_position = judge(
        _crossval(scores, FULL, Criterion.POSITION), FULL.name, False, 23, 6.0, {}, (POSITION, ROTATION)
    )
    assert "by the position alone (--criterion position)" in by_position.summary
