"""The linearised residual problem that the cross-validation's fits run on, and the default fit
that fits its ladder on it: the same choice as exact fits, the chosen set fitted exactly."""

from __future__ import annotations

from functools import partial
from unittest import mock

import numpy as np

import armtool.calib.fit.calibration as calibration
from armtool.calib.choices import Setup
from armtool.calib.fit.calibration import FitOptions, calibrate
from armtool.calib.fit.linearized import LinearizedProblem
from armtool.calib.fit.problems import Problem
from armtool.model.chain import Chain
from tests.calib.synthetic import make_measured


def _problem(chain: Chain, kind: str = "pose") -> tuple[Problem, np.ndarray, list[int]]:
    m = make_measured(chain, kind, n=30, setup=Setup.EYE_IN_HAND)
    problem = m.measurements.problem(m.model.with_frames(m.L, m.R), m.samples)
    problem = problem.with_sigma(np.array([5e-5, 2e-4])[: len(problem.blocks)])
    free = [i for i in range(m.model.size) if i in problem.frame_parameters() or i >= 12]
    return problem, np.zeros(m.model.size), free


def test_linearised_at_nominal_is_the_problem_there_to_first_order(clean_chain: Chain) -> None:
    problem, x0, free = _problem(clean_chain)
    J = problem.jacobian(x0, free)
    lin = LinearizedProblem.at_nominal(problem, x0, free, J)
    assert np.allclose(lin.raw(x0), problem.raw(x0), rtol=0, atol=1e-15)
    assert np.allclose(lin.jacobian(x0, free), J, rtol=1e-12, atol=0)
    step = x0.copy()
    step[free] = np.random.default_rng(3).normal(scale=1e-4, size=len(free))
    moved = problem.raw(step) - problem.raw(x0)
    # the linearisation's error is of second order: far below the step's own effect
    assert np.abs(lin.raw(step) - problem.raw(step)).max() < 1e-2 * np.abs(moved).max()


def test_a_subset_of_a_linearised_problem(clean_chain: Chain) -> None:
    problem, x0, free = _problem(clean_chain, "point")
    x_hat = x0.copy()
    x_hat[free] = np.random.default_rng(4).normal(scale=1e-3, size=len(free))
    start = LinearizedProblem.at_nominal(problem, x0, free, problem.jacobian(x0, free))
    lin = LinearizedProblem.at(problem, x_hat, free[:-3], start)
    assert lin.subset(range(lin.samples)) is lin  # all rows, in order: itself, no copy
    rows, again = [0, 3, 4, 8, 9, 20, 29], [1, 2, 5]
    twice = lin.subset(rows).subset(again)
    picked = [rows[i] for i in again]
    assert np.array_equal(twice.J_nominal, lin.J_nominal[picked])  # sliced when asked, rows composed
    assert np.array_equal(twice.J_hat, lin.J_hat[picked])
    x = x_hat + 1e-4
    assert np.allclose(twice.raw(x), lin.raw(x)[picked], rtol=0, atol=1e-15)
    part = free[2:7]
    assert np.array_equal(lin.jacobian(x, part), lin.jacobian(x, free[:-3])[:, 2:7])
    assert np.array_equal(lin.jacobian(x0, free[:-3]), start.jacobian(x0, free[:-3]))  # at nominal: start's


def test_the_linearised_ladder_chooses_as_exact_fits_and_the_chosen_set_is_fitted_exactly(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "pose", n=40, setup=Setup.EYE_IN_HAND)
    options = FitOptions(folds=4)
    result = calibrate(m.model, m.measurements, m.samples, options)
    with mock.patch.object(calibration, "_full_ladder", partial(calibration._full_ladder, exact=True)):
        exact = calibrate(m.model, m.measurements, m.samples, options)
    assert result.crossval is not None and exact.crossval is not None
    assert result.crossval.nested is not None and exact.crossval.nested is not None
    assert result.candidate == exact.candidate
    assert result.crossval.nested.chosen == exact.crossval.nested.chosen
    for a, b in zip(result.crossval.scores, exact.crossval.scores):
        assert abs(a.loss - b.loss) <= 1e-3 * b.loss, a.candidate.name
    # The chosen set is fitted on the real model: the exact ladder's fit, to rounding (its rung's
    # fit on the linearisation alone is 5e-5 off here: the second-order term of the corrections).
    assert np.abs(result.x - exact.x).max() < 1e-9
