"""Solver.judge / judge_batch: armtool's FK check decides, and a closed-form answer is solved when
any of its solutions passes."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from lxml import etree

from armtool.ik.solver import Answer, Solver
from armtool.model.chain import chain_from_xml
from tests.ik.robots import PLANAR_2R


class Given(Solver):
    """Answers with whatever it is handed (a test double): the judge is what is tested."""

    name = "given"
    summary = "test double"

    def call(self, prepared: Any) -> Any:
        raise NotImplementedError


@pytest.fixture
def solver() -> Given:
    return Given(chain_from_xml(etree.fromstring(PLANAR_2R)))


def test_a_closed_form_answer_is_solved_when_any_solution_passes(solver: Given) -> None:
    chain = solver.chain
    right = np.array([0.4, -0.8])
    target = chain.fk(right)
    wrong, outside = np.array([1.0, 1.0]), right + [0.0, 2 * np.pi]  # same pose, beyond the ±3 rad limit
    answer = Answer(wrong, True, 0, "", (wrong, outside, right, right + 1e-12))
    for result in (solver.judge(answer, target), solver.judge_batch([answer], target[None])[0]):
        assert result.success and not result.reason
        np.testing.assert_allclose(result.q, right)  # the first that passes, in the solver's order
        assert len(result.solutions) == 2  # the ones that pass: right and its rounding twin
        assert result.position_error_m < 1e-12


def test_a_closed_form_answer_whose_solutions_all_fail_is_a_failure(solver: Given) -> None:
    chain = solver.chain
    target = chain.fk(np.array([0.4, -0.8]))
    wrong = np.array([1.0, 1.0])
    answer = Answer(wrong, True, 0, "", (wrong, wrong + 0.1))
    for result in (solver.judge(answer, target), solver.judge_batch([answer], target[None])[0]):
        assert not result.success and result.solutions == ()
        assert "FK check rejects" in result.reason
        np.testing.assert_allclose(result.q, wrong)


def test_judge_batch_mixes_closed_form_and_single_answers(solver: Given) -> None:
    chain = solver.chain
    qs = np.array([[0.4, -0.8], [0.1, 0.2], [-1.0, 0.5]])
    targets = chain.fk_batch(qs)
    answers = [
        Answer(qs[0], True),  # one answer, right
        Answer(qs[0], True, 0, "", (qs[0], qs[1])),  # for target 1: its second solution is right
        Answer(qs[0], False, 0, "gave up"),  # one answer, wrong
    ]
    results = solver.judge_batch(answers, targets)
    assert [r.success for r in results] == [True, True, False]
    np.testing.assert_allclose(results[1].q, qs[1])
    assert results[2].reason == "gave up" and results[0].solutions == ()
