"""The verdict's arithmetic: when a kinematic set would overtake the nominal robot, and what to measure."""

from __future__ import annotations

import math

import numpy as np

from armtool.calib.fit.crossval import HAND_EYE, Candidate, Score
from armtool.calib.fit.verdict import _kind, poses_needed


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
